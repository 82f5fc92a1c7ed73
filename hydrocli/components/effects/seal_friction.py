"""Pressure-dependent seal friction as a separate element: the seals are pressed against the
rod and bore by the chamber pressures, so the friction force grows with them
(seed 000 eq. 23; Ottestad, Nilsen & Hansen 2012, "Reducing the static friction of hydraulic
cylinders by maintaining relative velocity"):
F = A_p·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b| + μ_b·p_b)·tanh(v/ε).
μ_s models seals loaded by both chambers (symmetric), μ_d a piston seal loaded by the pressure
difference across it, μ_b a single-rod cylinder's rod seal, loaded by the rod side alone. A
vane actuator's vane and hub seals are pressed the same way (seed 001 §2):
τ = D_p·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b| + μ_a·p_a + μ_b·p_b)·tanh(ω/ε) on its displacement
per radian D_p (``rotary_seal_friction``), where μ_a, μ_b are the hub seals on each chamber's
side, each pressed by its own chamber (unequal when the seals are: equal, they are μ_s)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, R, T, VariableSpec
from ..dynamics import tanh_sign
from ..registry import register


def _ports(domain, moving: str, fixed: str) -> tuple:
    return (Port("a", domain, moving), Port("b", domain, fixed),
            Port("pa", H, "chamber A (sensed)"), Port("pb", H, "chamber B (sensed)"))


def _parameters(size: Param, speed_unit: str, sides: tuple[str, ...]) -> tuple:
    """The seal laws' coefficients per unit of ``size``·pressure, the size, the smoothing; with
    ``sides`` ("a", "b" or both) the seals pressed by one chamber alone (a rod seal: the rod side,
    port pb)."""
    s = size.name
    own = tuple(Param(f"mu_{k}", "1", 0.0, f"friction per unit of {s}·p_{k} (a seal pressed by chamber {k.upper()} alone)",
                      min=0.0, bounds=(0.0, 1.0)) for k in sides)
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
                             ("b",))
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
                                   positive=True), "rad/s", ("a", "b"))
    variables = (VariableSpec("tau", "N*m", "friction torque opposing a relative to b"),)

    def equations(self, c):
        _seal(c, c.p.D_p, "tau")


def _seal(c, size, name: str) -> None:
    """size·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b| [+ μ_a·p_a] [+ μ_b·p_b])·tanh(Δv/ε) between a and b
    (seed 000 eq. 23); a one-sided term only where the element has it and it is in use."""
    p = c.p
    pa, pb = c.across("pa"), c.across("pb")
    load = p.mu_s * (pa + pb) + p.mu_d * E.smooth_abs(pa - pb, p.dp_eps)
    for k, pk in (("mu_a", pa), ("mu_b", pb)):
        if c.active(k):
            load = load + getattr(p, k) * pk
    f = c.let(name, size * load * tanh_sign(c.across("a") - c.across("b"), p.eps))
    c.through("a", f)
    c.through("b", -f)
