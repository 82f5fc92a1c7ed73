"""Pressure-dependent seal friction as a separate element: the seals are pressed against the
rod and bore by the chamber pressures, so the friction force grows with them
(seed 000 eq. 23; Ottestad, Nilsen & Hansen 2012, "Reducing the static friction of hydraulic
cylinders by maintaining relative velocity"):
F = A_p·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b| + μ_b·p_b)·tanh(v/ε).
μ_s models seals loaded by both chambers (symmetric), μ_d a piston seal loaded by the pressure
difference across it, μ_b a single-rod cylinder's rod seal, loaded by the rod side alone. A
vane actuator's vane and hub seals are pressed the same way (seed 001 §2):
τ = D_p·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b|)·tanh(ω/ε) on its displacement per radian D_p
(``rotary_seal_friction``)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, R, T, VariableSpec
from ..dynamics import tanh_sign
from ..registry import register


def _ports(domain, moving: str, fixed: str) -> tuple:
    return (Port("a", domain, moving), Port("b", domain, fixed),
            Port("pa", H, "chamber A (sensed)"), Port("pb", H, "chamber B (sensed)"))


def _parameters(size: Param, speed_unit: str, rod: bool = False) -> tuple:
    """The seal laws' coefficients per unit of ``size``·pressure, the size, the smoothing; with
    ``rod`` a rod seal's, loaded by the rod side (port pb) alone."""
    s = size.name
    own = (Param("mu_b", "1", 0.0, f"friction per unit of {s}·p_b (a rod seal: the rod side only)", min=0.0,
                 bounds=(0.0, 1.0)),) if rod else ()
    return (Param("mu_s", "1", 0.0, f"friction per unit of {s}·(p_a + p_b)", min=0.0, bounds=(0.0, 0.2)),
            Param("mu_d", "1", 0.0, f"friction per unit of {s}·|p_a − p_b|", min=0.0, bounds=(0.0, 1.0)),
            *own, size,
            Param("eps", speed_unit, 1e-3, "tanh smoothing speed", positive=True),
            Param("dp_eps", "Pa", 1e4, "smoothing of |p_a − p_b| near zero", positive=True))


@register
class SealFriction(Component):
    type = "seal_friction"
    family = "effects"
    description = "Seal friction proportional to chamber pressures (sum and |difference|)"
    source = "seed 000 eq. 23"
    ports = _ports(T, "moving side (rod)", "fixed side")
    parameters = _parameters(Param("A_p", "m^2", 1e-3, "reference area (the piston area)", positive=True), "m/s",
                             rod=True)
    variables = (VariableSpec("F", "N", "friction force opposing a relative to b"),)

    def equations(self, c):
        _seal(c, c.p.A_p, "F")


@register
class RotarySealFriction(Component):
    type = "rotary_seal_friction"
    family = "effects"
    description = "Vane/hub seal friction proportional to chamber pressures (sum and |difference|)"
    source = "seed 000 eq. 23; seed 001 §2 (vane seals)"
    ports = _ports(R, "moving side (vane shaft)", "fixed side (housing)")
    parameters = _parameters(Param("D_p", "m^3/rad", 1e-5, "reference displacement per radian (the vane's)",
                                   positive=True), "rad/s")
    variables = (VariableSpec("tau", "N*m", "friction torque opposing a relative to b"),)

    def equations(self, c):
        _seal(c, c.p.D_p, "tau")


def _seal(c, size, name: str) -> None:
    """size·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b|)·tanh(Δv/ε) between a and b (seed 000 eq. 23)."""
    p = c.p
    pa, pb = c.across("pa"), c.across("pb")
    load = p.mu_s * (pa + pb) + p.mu_d * E.smooth_abs(pa - pb, p.dp_eps)
    if c.active("mu_b"):
        load = load + p.mu_b * pb
    f = c.let(name, size * load * tanh_sign(c.across("a") - c.across("b"), p.eps))
    c.through("a", f)
    c.through("b", -f)
