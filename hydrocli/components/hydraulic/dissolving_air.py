"""Free air that dissolves (and comes out of solution) during the record: its amount a state.

Oil that stood aerated holds free air when the machine starts; under pressure it goes back
into solution over tens of seconds, and comes out fast where the pressure falls below the
saturation pressure (Zhou, Vacca & Manhartsgruber, J. Fluids Eng. 135 (2013): first-order
release and absorption, τ_r ≪ τ_a; Gholizadeh, Burton & Schoenau, Int. J. Fluid Power 12
(2011): Henry's law). The chamber stiffens with time, which no fixed air fraction, hose or
mount can follow.
"""
from __future__ import annotations

from ...model import expr as E
from .. import roles as RL
from ..base import Component, H, Param, Port, StateSpec, VariableSpec
from ..registry import register
from ..roles import role

P_ATM = 1e5      # Pa: free air is counted at 1 bar (absolute)


@register
class DissolvingAir(Component):
    """Free air on a node whose amount G (its volume at 1 bar) relaxes to Henry's equilibrium
    G_eq = B·V·max(p_sat − p, 0)/p_sat at first order, fast when air comes out (τ_r), slowly
    when it dissolves (τ_a); the gas is isothermal, V_g = G·p_atm/p. Continuity of oil and gas
    filling the node (Zhou et al. 2013):

        (ΣC + G·p_atm/p²)·dp/dt = Σq + p_atm·(dG/dt)/p

    so the element adds the capacitance G·p_atm/p² and takes the flow −p_atm·(dG/dt)/p (the
    volume dissolving air leaves). G = G₀·s, s a state starting at 1: every record starts with
    G₀ of free air, the amount the oil held when it began."""

    type = "dissolving_air"
    roles = (role(RL.DISSOLVING_AIR, {"node": "P"}, free_air="G0", absorption="tau_a", release="tau_r",
                  oil_volume="V", solubility="B", saturation="p_sat"),)
    family = "hydraulic"
    description = "Free air dissolving into (and released from) the oil of a node, its amount a state"
    source = "Zhou, Vacca & Manhartsgruber 2013 (first-order release/absorption); Henry's law"
    ports = (Port("P", H, "node"),)
    parameters = (
        Param("G0", "m^3", 1e-6, "free air at the record's start, as its volume at 1 bar", positive=True,
              bounds=(1e-12, 1e-2)),
        Param("tau_a", "s", 30.0, "time constant of absorption (air going back into solution)", positive=True,
              bounds=(0.5, 1000.0)),
        Param("tau_r", "s", 0.2, "time constant of release (air coming out below p_sat)", positive=True,
              bounds=(0.01, 10.0)),
        Param("V", "m^3", 1e-4, "oil volume whose dissolved air can come out (Henry's law)", positive=True),
        Param("B", "1", 0.09, "Bunsen solubility: dissolved air at 1 bar per volume of oil (mineral oil 0.08–0.09)",
              min=0.0),
        Param("p_sat", "Pa", 1e5, "saturation pressure (absolute): below it air comes out of solution",
              positive=True),
    )
    states = (StateSpec("s", "1", "free air as a share of G0", initial=1.0, nominal=1.0),)
    variables = (VariableSpec("G", "m^3", "free air (volume at 1 bar)"),
                 VariableSpec("V_gas", "m^3", "free-air volume at the node's pressure"))

    def equations(self, c):
        p = c.p
        pp = E.fmax(c.across("P"), 1e4)
        s = c.state("s")
        s_eq = p.B * p.V * E.fmax(p.p_sat - pp, 0.0) / (p.p_sat * p.G0)
        ds = E.fmax(s_eq - s, 0.0) / p.tau_r - E.fmax(s - s_eq, 0.0) / p.tau_a
        c.der("s", ds)
        g = c.let("G", p.G0 * s)
        c.let("V_gas", g * P_ATM / pp)
        c.capacitance("P", g * P_ATM / (pp * pp))
        c.through("P", -P_ATM * p.G0 * ds / pp)
