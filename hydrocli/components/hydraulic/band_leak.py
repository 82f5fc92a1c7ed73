"""Leakage over a band of the stroke: a scored cylinder barrel (or a worn arc of a vane
housing) lets oil past the piston (vane) seal only while the seal is over the damaged band."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, R, T, VariableSpec
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role


def band_window(x, x1, x2, d):
    """w(x) = s((x − x1)/d)·s((x2 − x)/d), s(z) = 1/(1 + e^(−z)) = (1 + tanh(z/2))/2: 1 inside
    the band [x1, x2], 0 outside, with edges d wide (the seal's land crossing the score)."""
    return 0.25 * (1.0 + E.tanh(0.5 * (x - x1) / d)) * (1.0 + E.tanh(0.5 * (x2 - x) / d))


def band_params(unit: str, band: str, where: str, end: float, edge: float) -> tuple[Param, ...]:
    """The band leak's parameters in its motion's unit (m or rad)."""
    return (Param("c", "m^3/s/Pa", 1e-12, f"leak conductance inside the {band}", min=0.0, bounds=(1e-16, 1e-8)),
            Param("x1", unit, 0.0, f"where the {band} starts ({where})"),
            Param("x2", unit, end, f"where the {band} ends ({where})"),
            Param("d", unit, edge, f"width of the {band}'s edges", positive=True))


@register
class BandLeak(Component):
    """q = c·w(x)·(p_A − p_B) from A to B: a laminar leak (seed 004 eqs. 4–5, c = 1/R) that
    exists only while the piston at x = x_rod − x_body is inside the band [x1, x2]
    (:func:`band_window`). The rod port only reads the position: no force."""

    type = "band_leak"
    roles = (role(RL.BAND_RESTRICTION, {"a": "A", "b": "B", "motion": "rod", "reference": "body"},
                  conductance="c", band_start="x1", band_end="x2", edge="d"),)
    family = "hydraulic"
    description = "Laminar leakage over a band of the stroke (a scored barrel)"
    source = "seed 004 eqs. 4–5 (laminar leakage c·Δp) with a logistic window in position"
    ports = (Port("A", H, "inlet (e.g. chamber A)"), Port("B", H, "outlet (e.g. chamber B)"),
             Port("rod", T, "piston rod (position read only, no force)"),
             Port("body", T, "cylinder body (position read only, usually ground)"))
    parameters = band_params("m", "band", "piston position", 0.1, 2e-3)
    variables = (VariableSpec("w", "1", "share of the leak open at the piston's position"),
                 VariableSpec("q", "m^3/s", "flow from A to B"))

    def equations(self, c):
        p = c.p
        x = c.position("rod") - c.position("body")
        w = c.let("w", band_window(x, p.x1, p.x2, p.d))
        branch(c, "q", p.c * w * across_drop(c, "A", "B"), "A", "B")


@register
class BandLeakRotary(BandLeak):
    """:class:`BandLeak` over an arc of a vane's (or rotary piston's) travel: angle in rad."""

    type = "band_leak_rotary"
    description = "Laminar leakage over an arc of a rotary actuator's travel (a worn housing)"
    ports = (Port("A", H, "inlet (e.g. chamber A)"), Port("B", H, "outlet (e.g. chamber B)"),
             Port("rod", R, "vane shaft (angle read only, no torque)"),
             Port("body", R, "housing (angle read only, usually ground)"))
    parameters = band_params("rad", "arc", "angle", 0.5, 0.02)
