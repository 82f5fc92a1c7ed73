"""Resistive hydraulic elements: turbulent orifice and laminar resistance (leakage)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, VariableSpec
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role


@register
class Orifice(Component):
    """q = Kv·dp/(dp² + dp_lam²)^¼ from A to B: the turbulent law q = Kv·sign(dp)·sqrt(|dp|)
    (seed 004 eq. 3 with Kv = q_n/sqrt(ΔP_n); Kv = Cd·A·sqrt(2/ρ)) with a laminar transition
    below dp_lam so the derivative stays finite at dp = 0."""

    type = "orifice"
    roles = (role(RL.RESTRICTION, {"a": "A", "b": "B"}, conductance="Kv"),)
    family = "hydraulic"
    description = "Fixed turbulent orifice with a smooth laminar transition"
    source = "seed 004 eq. 3; seed 000 eq. 6"
    ports = (Port("A", H, "inlet"), Port("B", H, "outlet"))
    parameters = (
        Param("Kv", "m^3/s/Pa^0.5", 1e-7, "flow coefficient q/sqrt(dp)", min=0.0, bounds=(1e-10, 1e-4)),
        Param("dp_lam", "Pa", 5e4, "laminar/turbulent transition pressure drop", positive=True),
    )
    variables = (VariableSpec("q", "m^3/s", "flow from A to B"),)

    def equations(self, c):
        branch(c, "q", c.p.Kv * E.signed_sqrt(across_drop(c, "A", "B"), c.p.dp_lam), "A", "B")


@register
class LaminarResistance(Component):
    """q = (p_A − p_B)/R: laminar leakage or a short laminar line (seed 002 eqs. 8–9)."""

    type = "laminar_resistance"
    roles = (role(RL.LAMINAR_RESTRICTION, {"a": "A", "b": "B"}, resistance="R"),)
    family = "hydraulic"
    description = "Linear (laminar) hydraulic resistance, e.g. a leakage path"
    source = "seed 002 eqs. 8–9 (R_m, R_ex); seed 004 eqs. 4–5 (c = 1/R)"
    ports = (Port("A", H, "inlet"), Port("B", H, "outlet"))
    parameters = (Param("R", "Pa*s/m^3", 1e12, "resistance dp/q", positive=True, bounds=(1e8, 1e15)),)
    variables = (VariableSpec("q", "m^3/s", "flow from A to B"),)

    def equations(self, c):
        branch(c, "q", across_drop(c, "A", "B") / c.p.R, "A", "B")
