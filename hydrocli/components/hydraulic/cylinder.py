"""Hydraulic cylinders (gyrators between chamber pressures and rod force)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, T, VariableSpec
from ..registry import register
from .fluid import AIR_PARAMS, cavitation_floor, oil_bulk_modulus
from .. import roles as RL
from ..roles import role


#: a chamber compressed below this fraction of its x = 0 volume means the piston has left
#: its stroke (the solver would otherwise fail on the stiffness blow-up as V → 0)
VOLUME_FLOOR = 1e-2


def end_stop_force(x, v, x_min, x_max, k, c, eps):
    """Penalty end stops: a stiff spring-damper acting beyond [x_min, x_max] (force on the
    piston, positive in +x). The damper acts only while penetrating and is smoothed."""
    pen_lo = E.smooth_pos(x_min - x, eps)
    pen_hi = E.smooth_pos(x - x_max, eps)
    act_lo = pen_lo / (pen_lo + eps)
    act_hi = pen_hi / (pen_hi + eps)
    return k * (pen_lo - pen_hi) - c * v * (act_lo + act_hi)


def _cylinder_equations(c, area_a, area_b):
    """Chamber continuity (seed 004 eqs. 4–7) and rod force (eq. 8) for piston areas A_A, A_B."""
    p = c.p
    x = c.let("x", c.position("rod") - c.position("body"))
    v = c.let("v", c.across("rod") - c.across("body"))
    pa, pb = c.across("A"), c.across("B")
    va = c.let("V_A", p.V_A0 + area_a * x)
    vb = c.let("V_B", p.V_B0 - area_b * x)
    c.guard(va <= VOLUME_FLOOR * p.V_A0, "chamber A collapsed below 1 % of its volume at x = 0 (stroke overrun): add end stops (k_stop > 0, "
                       "x_min/x_max) or check V_A0, the command and the load")
    c.guard(vb <= VOLUME_FLOOR * p.V_B0, "chamber B collapsed below 1 % of its volume at x = 0 (stroke overrun): add end stops (k_stop > 0, "
                       "x_min/x_max) or check V_B0, the command and the load")
    cap_a, cap_b = va / oil_bulk_modulus(c, pa), vb / oil_bulk_modulus(c, pb)
    c.capacitance("A", cap_a)
    c.capacitance("B", cap_b)
    cavitation_floor(c, "A", cap_a)
    cavitation_floor(c, "B", cap_b)
    q_il = c.let("q_il", (p.c_il if c.active("c_il") else 0.0) * (pa - pb))
    c_el = p.c_el if c.active("c_el") else 0.0
    c.through("A", area_a * v + q_il + c_el * (pa - p.p_drain))
    c.through("B", -area_b * v - q_il + c_el * (pb - p.p_drain))
    f_stop = c.let("F_stop", end_stop_force(x, v, p.x_min, p.x_max, p.k_stop, p.c_stop, p.eps_stop)
                   if c.active("k_stop") else 0.0)
    force = c.let("F", area_a * pa - area_b * pb)
    c.through("rod", -(force + f_stop))
    c.through("body", force + f_stop)


_COMMON = (
    Param("V_A0", "m^3", 2.11e-4, "chamber A volume at x = 0 (includes dead volume and lines)",
          source="seed 004 eq. 4 (V_10)", positive=True, bounds=(1e-6, 1e-2)),
    Param("V_B0", "m^3", 6.75e-4, "chamber B volume at x = 0", source="seed 004 eq. 5 (V_20)", positive=True,
          bounds=(1e-6, 1e-2)),
    Param("beta", "Pa", 1.5e9, "oil bulk modulus", fluid="beta", positive=True, bounds=(1e8, 2.5e9)),
    *AIR_PARAMS,
    Param("c_il", "m^3/s/Pa", 0.0, "internal (cross-piston) leakage coefficient", source="seed 004 eq. 4",
          min=0.0, bounds=(0.0, 1e-10)),
    Param("c_el", "m^3/s/Pa", 0.0, "external leakage coefficient of each chamber", source="seed 004 eq. 4",
          min=0.0, bounds=(0.0, 1e-10)),
    Param("p_drain", "Pa", 0.0, "pressure the external leakage drains to (seed 004 uses 0)", min=0.0),
    Param("x_min", "m", -1e3, "end stop at the retracted end (piston position)"),
    Param("x_max", "m", 1e3, "end stop at the extended end"),
    Param("k_stop", "N/m", 0.0, "end-stop contact stiffness (0 and not free = no end stops)", min=0.0, bounds=(1e6, 1e10)),
    Param("c_stop", "N*s/m", 0.0, "end-stop contact damping", min=0.0, bounds=(0.0, 1e7)),
    Param("eps_stop", "m", 1e-5, "smoothing of the end-stop contact", positive=True),
)
_VARS = (
    VariableSpec("x", "m", "piston position (rod relative to body)"),
    VariableSpec("v", "m/s", "piston velocity"),
    VariableSpec("V_A", "m^3", "chamber A volume"), VariableSpec("V_B", "m^3", "chamber B volume"),
    VariableSpec("F", "N", "hydraulic force A_A p_A − A_B p_B"),
    VariableSpec("F_stop", "N", "end-stop force"), VariableSpec("q_il", "m^3/s", "internal leakage A→B"),
)
_PORTS = (
    Port("A", H, "chamber A (piston side; extends the rod)"), Port("B", H, "chamber B (rod side)"),
    Port("rod", T, "rod/piston"), Port("body", T, "cylinder body (usually ground)"),
)


@register
class Cylinder(Component):
    """Single-rod differential cylinder: V_A = V_A0 + A_A x, V_B = V_B0 − A_B x;
    continuity with leakage (seed 004 eqs. 4–7), force A_A p_A − A_B p_B (eq. 8) plus
    penalty end stops; a chamber volume reaching zero stops the solver with a hint."""

    type = "cylinder"
    roles = (role(RL.ACTUATOR, {"chamber_a": "A", "chamber_b": "B", "motion": "rod", "reference": "body"}, size="A_A", displacements=("A_A", "A_B"), swept=("A_A", "A_B"), dead_volumes=("V_A0", "V_B0"), bulk_modulus="beta", internal_leakage="c_il", external_leakage="c_el", air="air", air_exponent="air_n", air_dissolve="p_dissolve", stop_min="x_min", stop_max="x_max", stop_stiffness="k_stop", stop_damping="c_stop"),)
    family = "hydraulic"
    description = "Single-rod cylinder: chamber compressibility, leakage, end stops"
    source = "seed 004 eqs. 4–8; seed 000 eqs. 23–26 (areas, Table 6)"
    ports = _PORTS
    parameters = (
        Param("A_A", "m^2", 3.117e-3, "piston area (chamber A)", positive=True, bounds=(1e-6, 1.0)),
        Param("A_B", "m^2", 2.099e-3, "annulus area (chamber B)", positive=True, bounds=(1e-6, 1.0)),
    ) + _COMMON
    variables = _VARS

    def equations(self, c):
        _cylinder_equations(c, c.p.A_A, c.p.A_B)

    def check(self, values):
        out = []
        if values["A_B"] > values["A_A"]:
            out.append("annulus area A_B is larger than piston area A_A (swap them?)")
        if values["x_min"] >= values["x_max"]:
            out.append("x_min must be below x_max")
        return out


@register
class DoubleRodCylinder(Component):
    """Double-rod (symmetric) cylinder: one effective area A on both sides (seed 004's
    model uses this form, A_r in eqs. 4–8)."""

    type = "cylinder_double_rod"
    roles = (role(RL.ACTUATOR, {"chamber_a": "A", "chamber_b": "B", "motion": "rod", "reference": "body"}, size="A", displacements=("A",), swept=("A",), dead_volumes=("V_A0", "V_B0"), bulk_modulus="beta", internal_leakage="c_il", external_leakage="c_el", air="air", air_exponent="air_n", air_dissolve="p_dissolve", stop_min="x_min", stop_max="x_max", stop_stiffness="k_stop", stop_damping="c_stop"),)
    family = "hydraulic"
    description = "Double-rod cylinder with one effective area on both sides"
    source = "seed 004 eqs. 4–8 (A_r)"
    ports = _PORTS
    parameters = (Param("A", "m^2", 2.0994e-3, "effective piston area A_r", positive=True, bounds=(1e-6, 1.0)),) + _COMMON
    variables = _VARS

    def equations(self, c):
        _cylinder_equations(c, c.p.A, c.p.A)

    def check(self, values):
        return ["x_min must be below x_max"] if values["x_min"] >= values["x_max"] else []
