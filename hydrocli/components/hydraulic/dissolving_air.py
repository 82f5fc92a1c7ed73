"""Free air that dissolves (and comes out of solution) during the record: its amount a state.

Oil that stood aerated holds free air when the machine starts; under pressure it goes back
into solution over tens of seconds, and comes out fast where the pressure falls below the
saturation pressure (Zhou, Vacca & Manhartsgruber, J. Fluids Eng. 135 (2013): first-order
release and absorption, τ_r ≪ τ_a; Gholizadeh, Burton & Schoenau, Int. J. Fluid Power 12
(2011): Henry's law). The chamber stiffens with time, which no fixed air fraction, hose or
mount can follow. Entrained bubbles travel with the oil, so in an actuator's chamber the free
air is a share of the oil there: :class:`ChamberDissolvingAir` scales it with the chamber's
volume as the piston (vane) moves.
"""
from __future__ import annotations

from dataclasses import replace

from ...model import expr as E
from .. import roles as RL
from ..base import Component, H, Param, Port, R, StateSpec, T, VariableSpec
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
        _dissolving(c, 1.0)


#: the smallest share of its volume at the reference position a chamber's oil is counted with
#: (a piston past its stroke; the actuator's own guard stops the solver there)
VOLUME_SHARE_FLOOR = 1e-2


def _dissolving(c, share):
    """The element's equations with the oil holding its air ``share`` (V(x)/V) of its volume at
    the reference position: G = G₀·s·share, the equilibrium share s_eq unchanged (Henry's law
    frees air per volume of oil)."""
    p = c.p
    pp = E.fmax(c.across("P"), 1e4)
    s = c.state("s")
    s_eq = p.B * p.V * E.fmax(p.p_sat - pp, 0.0) / (p.p_sat * p.G0)
    ds = E.fmax(s_eq - s, 0.0) / p.tau_r - E.fmax(s - s_eq, 0.0) / p.tau_a
    c.der("s", ds)
    g = c.let("G", p.G0 * s * share)
    c.let("V_gas", g * P_ATM / pp)
    c.capacitance("P", g * P_ATM / (pp * pp))
    c.through("P", -P_ATM * p.G0 * share * ds / pp)


@register
class ChamberDissolvingAir(DissolvingAir):
    """:class:`DissolvingAir` in an actuator chamber whose oil volume follows the piston,
    V(x) = V + A·x (x = rod − body; A = A_A for a cylinder's chamber A, −A_B for chamber B:
    seed 004 eqs. 4–5). Entrained bubbles travel with the oil, so the free air is a share of
    the oil in the chamber (Gholizadeh, Burton & Schoenau 2011, §4: air content by volume):
    G = G₀·s·V(x)/V, with s the share of the record's starting concentration left free. The
    ports on the rod and body only read the position: no force."""

    type = "dissolving_air_chamber"
    roles = (role(RL.DISSOLVING_AIR, {"node": "P", "motion": "rod", "reference": "body"}, free_air="G0",
                  absorption="tau_a", release="tau_r", oil_volume="V", solubility="B", saturation="p_sat",
                  swept="A"),)
    description = "Free air dissolving in an actuator chamber whose volume follows the piston"
    ports = (Port("P", H, "chamber node"), Port("rod", T, "piston rod (position read only, no force)"),
             Port("body", T, "cylinder body (position read only, usually ground)"))
    parameters = (replace(DissolvingAir.parameters[0], description="free air at the record's start, as its volume "
                          "at 1 bar, were the chamber at its x = 0 volume V (the chamber holds G₀·V(x)/V)"),
                  ) + DissolvingAir.parameters[1:3] + (
        Param("V", "m^3", 1e-4, "the chamber's oil volume at x = 0", positive=True),
        Param("A", "m^2", 0.0, "swept area: the chamber grows by A per metre of piston travel (A_A for chamber A, "
              "−A_B for chamber B)"),
    ) + DissolvingAir.parameters[4:]
    variables = DissolvingAir.variables + (VariableSpec("V_oil", "m^3", "the chamber's volume"),)

    def equations(self, c):
        p = c.p
        vol = c.let("V_oil", E.fmax(p.V + p.A * (c.position("rod") - c.position("body")), VOLUME_SHARE_FLOOR * p.V))
        _dissolving(c, vol / p.V)


@register
class ChamberDissolvingAirRotary(ChamberDissolvingAir):
    """:class:`ChamberDissolvingAir` in a vane actuator's chamber, V(θ) = V + D·θ (seed 001
    eqs. 9–10: D = D_v for chamber 1, −D_v for chamber 2)."""

    type = "dissolving_air_chamber_rotary"
    description = "Free air dissolving in a vane chamber whose volume follows the vane"
    ports = (Port("P", H, "chamber node"), Port("rod", R, "vane shaft (angle read only, no torque)"),
             Port("body", R, "housing (angle read only, usually ground)"))
    parameters = tuple(Param("A", "m^3/rad", 0.0, "swept volume per radian: D_v for chamber 1, −D_v for chamber 2")
                       if q.name == "A" else q for q in ChamberDissolvingAir.parameters)
