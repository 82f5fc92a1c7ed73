"""Leakage through a sliding seal's lubricating film: a rod (or shaft) seal that holds at
standstill and lets oil past while the rod moves, because the film under its lip thickens
with the sliding speed."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, R, T, VariableSpec
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role


def film_factor(v, v_ref, v_eps, n):
    """φ(v) = v²/(v² + v_ε²) · (√(v² + v_ε²)/v_ref)ⁿ: 1 at the reference speed, (|v|/v_ref)ⁿ
    wherever |v| ≫ v_ε, and 0 at standstill, smooth through v = 0 (the lip seals a rod at rest:
    a bare (√(v² + v_ε²)/v_ref)ⁿ would leak (v_ε/v_ref)ⁿ, a tenth of the reference leak at
    n = ½ and v_ε = v_ref/100, in every hold)."""
    s2 = v * v + v_eps * v_eps
    return v * v / s2 * E.power(s2 / (v_ref * v_ref), 0.5 * n)


def film_params(unit: str, speed: str, v_ref: float, v_eps: float) -> tuple[Param, ...]:
    """The film leak's parameters in its motion's speed unit (m/s or rad/s)."""
    return (Param("c", "m^3/s/Pa", 1e-12, f"leak conductance at the reference {speed}", min=0.0,
                  bounds=(1e-17, 1e-8)),
            Param("n", "1", 0.5, "exponent of the speed: 0.5 a leak through a film whose thickness "
                  "grows as √v (inverse hydrodynamic theory), 1.5 a Poiseuille film (∝ h³)", positive=True,
                  bounds=(0.1, 3.0)),
            Param("v_ref", unit, v_ref, f"reference {speed} (where the conductance is c)", positive=True),
            Param("v_eps", unit, v_eps, f"{speed} below which the law is rounded off (≪ the {speed}s of interest)",
                  positive=True))


@register
class FilmLeak(Component):
    """q = c·φ(v)·(p_A − p_B) from A to B, φ(v) ≈ (|v|/v_ref)ⁿ, 0 at rest (:func:`film_factor`),
    v = v_rod − v_body: a reciprocating seal rides on a hydrodynamic film of thickness
    h ∝ √(μ·v/w′_max) (inverse hydrodynamic lubrication; Müller & Nau, *Fluid Sealing
    Technology* (1998) ch. 11; Nikas, J. Tribology 125 (2003)), so it seals at standstill and
    leaks in motion, the more the faster. n = 1/2: a leak proportional to the film's thickness;
    n = 3/2: a Poiseuille flow through it (∝ h³). The laminar drop (seed 004 eqs. 4–5) at
    c = 1/R. The rod port only reads the speed: no force."""

    type = "film_leak"
    roles = (role(RL.FILM_RESTRICTION, {"a": "A", "b": "B", "motion": "rod", "reference": "body"},
                  conductance="c", exponent="n", speed="v_ref"),)
    family = "hydraulic"
    description = "Laminar leakage of a sliding seal through its film, growing with the rod's speed"
    source = "seed 004 eqs. 4–5 (laminar leakage c·Δp); Müller & Nau (1998) film thickness ∝ √v"
    ports = (Port("A", H, "inlet (e.g. the rod-side chamber)"), Port("B", H, "outlet (e.g. the drain)"),
             Port("rod", T, "piston rod (speed read only, no force)"),
             Port("body", T, "cylinder body (speed read only, usually ground)"))
    parameters = film_params("m/s", "speed", 0.1, 1e-3)
    variables = (VariableSpec("phi", "1", "the film's share of the leak at the rod's speed"),
                 VariableSpec("q", "m^3/s", "flow from A to B"))

    def equations(self, c):
        p = c.p
        v = c.across("rod") - c.across("body")
        phi = c.let("phi", film_factor(v, p.v_ref, p.v_eps, p.n))
        branch(c, "q", p.c * phi * across_drop(c, "A", "B"), "A", "B")


@register
class FilmLeakRotary(FilmLeak):
    """:class:`FilmLeak` on a shaft seal (a vane actuator's or a motor's): speed in rad/s."""

    type = "film_leak_rotary"
    description = "Laminar leakage of a shaft seal through its film, growing with the shaft's speed"
    ports = (Port("A", H, "inlet (e.g. a chamber)"), Port("B", H, "outlet (e.g. the drain)"),
             Port("rod", R, "shaft (speed read only, no torque)"),
             Port("body", R, "housing (speed read only, usually ground)"))
    parameters = film_params("rad/s", "angular speed", 1.0, 0.01)
