"""A pressure-compensated pump's lagging displacement control, as the pressure drop between
the compensator's set pressure and the pump's outlet: a dip while the swash plate catches up
with a rising flow demand, no steady droop."""
from __future__ import annotations

from ..base import Component, H, Param, Port, StateSpec, VariableSpec
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role


@register
class PumpCompensator(Component):
    """p_A − p_B = k·(q − z), τ·z′ = q − z, q the flow from A (the set pressure) to B (the
    outlet): z is the flow the displacement has followed to, so a step of demand q₀ dips the
    outlet by k·q₀·e^(−t/τ) and the steady outlet pressure is the set pressure. Written for the
    nodes as q = Δp/k + z, z′ = Δp/(k·τ): a resistance k in parallel with an inertance k·τ.
    Source: Manring, *Hydraulic Control Systems* (2005) ch. on pump control, the linearised
    pressure-compensated axial-piston pump (a transient undershoot after a flow demand, no
    steady error); Ivantysyn & Ivantysynova, *Hydrostatic Pumps and Motors* (2001), the
    pressure compensator."""

    type = "pump_compensator"
    roles = (role(RL.PUMP_COMPENSATOR, {"a": "A", "b": "B"}, dip="k", lag="tau"),)
    family = "hydraulic"
    description = "Pressure-compensated pump whose displacement control lags: a dip after a flow demand"
    source = "Manring (2005), the linearised pressure-compensated pump; seed 004 §III.A (P_s)"
    ports = (Port("A", H, "set pressure (the compensator's reference: a pressure source)"),
             Port("B", H, "pump outlet (e.g. the valve's supply port)"))
    parameters = (Param("k", "Pa*s/m^3", 1e10, "pressure dip per unit of sudden flow demand", positive=True,
                        bounds=(1e7, 1e14)),
                  Param("tau", "s", 0.05, "time constant of the displacement control", positive=True,
                        bounds=(1e-3, 2.0)))
    states = (StateSpec("z", "m^3/s", "flow the displacement has followed to", nominal=1e-4),)
    variables = (VariableSpec("q", "m^3/s", "flow from A to B"),)

    def equations(self, c):
        p = c.p
        dp = across_drop(c, "A", "B")
        c.der("z", dp / (p.k * p.tau))
        branch(c, "q", dp / p.k + c.state("z"), "A", "B")
