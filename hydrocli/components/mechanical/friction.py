"""Friction between two translational nodes (seed 004 eqs. 9–11, seed 000 eq. 23)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, T, VariableSpec
from ..dynamics import tanh_sign
from ..registry import register
from ..two_port import branch
from .. import roles as RL
from ..roles import role


def friction_force(v, kv, kc, ks, vs, eps):
    """Viscous + Coulomb + Stribeck: kv·v + (kc + ks·e^(−|v|/vs))·tanh(v/ε) (seed 004 eqs. 9–11)."""
    return kv * v + (kc + ks * E.exp(-E.fabs(v) / vs)) * tanh_sign(v, eps)


@register
class Friction(Component):
    """Direction-dependent viscous, Coulomb and Stribeck friction with tanh smoothing
    (seed 004 eqs. 9–11: k_v^±, k_c^±, k_s^±, τ_s^±), plus an optional pressure-dependent
    Coulomb part μ_p·A_p·(p_a + p_b) when the sensing ports pa/pb are connected
    (seed 000 eq. 23: seal friction grows with chamber pressure)."""

    type = "friction"
    roles = (role(RL.FRICTION, {"a": "a", "b": "b", "pressure_a": "pa", "pressure_b": "pb"}, viscous=("kv_p", "kv_m"), coulomb=("kc_p", "kc_m"), stribeck=("ks_p", "ks_m"), stribeck_speed=("vs_p", "vs_m"), pressure="mu_p", pressure_size="A_p", band="eps"),)
    family = "mechanical"
    description = "Asymmetric viscous/Coulomb/Stribeck friction, optional pressure dependence"
    source = "seed 004 eqs. 9–11; seed 000 eq. 23"
    ports = (Port("a", T, "moving side (e.g. the rod)"), Port("b", T, "fixed side (e.g. ground)"),
             Port("pa", H, "chamber A pressure (sensed only)", optional=True),
             Port("pb", H, "chamber B pressure (sensed only)", optional=True))
    parameters = (
        Param("kv_p", "N*s/m", 0.0, "viscous coefficient for v > 0", min=0.0, bounds=(0.0, 1e6)),
        Param("kv_m", "N*s/m", 0.0, "viscous coefficient for v < 0", min=0.0, bounds=(0.0, 1e6)),
        Param("kc_p", "N", 0.0, "Coulomb force for v > 0", min=0.0, bounds=(0.0, 1e5)),
        Param("kc_m", "N", 0.0, "Coulomb force for v < 0", min=0.0, bounds=(0.0, 1e5)),
        Param("ks_p", "N", 0.0, "Stribeck (breakaway excess) force for v > 0", min=0.0, bounds=(0.0, 1e5)),
        Param("ks_m", "N", 0.0, "Stribeck force for v < 0", min=0.0, bounds=(0.0, 1e5)),
        Param("vs_p", "m/s", 3.41e-3, "Stribeck velocity τ_s for v > 0", positive=True, bounds=(1e-5, 0.1)),
        Param("vs_m", "m/s", 1.96e-3, "Stribeck velocity τ_s for v < 0", positive=True, bounds=(1e-5, 0.1)),
        Param("eps", "m/s", 1e-4, "tanh smoothing velocity", positive=True),
        Param("mu_p", "1", 0.0, "pressure-dependent friction: fraction of A_p·(p_a + p_b)", min=0.0,
              bounds=(0.0, 0.2)),
        Param("A_p", "m^2", 0.0, "area the pressure-dependent friction refers to", min=0.0),
    )
    variables = (VariableSpec("F", "N", "friction force opposing a relative to b"),)

    def equations(self, c):
        p = c.p
        v = c.across("a") - c.across("b")
        f_pos = friction_force(v, p.kv_p, p.kc_p, p.ks_p, p.vs_p, p.eps)
        f_neg = friction_force(v, p.kv_m, p.kc_m, p.ks_m, p.vs_m, p.eps)
        f = E.where(v >= 0.0, f_pos, f_neg)
        if c.connected("pa") and c.connected("pb"):
            f = f + p.mu_p * p.A_p * (c.across("pa") + c.across("pb")) * tanh_sign(v, p.eps)
        branch(c, "F", f)


@register
class CylinderFriction(Component):
    """Cylinder friction of seed 000 (eqs. 23, 26): F_fr = F_S + C_p·|F_p| with the pressure
    force F_p = p_A·A_A − p_B·A_B; it opposes motion, saturated linearly below the transition
    velocity v0: F = F_fr·clamp(v/v0, −1, 1). Outer jib (Table 7): F_S = 6.4 kN, C_p = 0.029;
    a first guess is F_S = A_p·1 bar, C_p = 0.02 (§4.3)."""

    type = "cylinder_friction"
    family = "mechanical"
    description = "Static + pressure-dependent cylinder friction with a transition velocity (seed 000)"
    source = "seed 000 eqs. 23, 26, Table 7"
    ports = (Port("a", T, "rod/piston"), Port("b", T, "cylinder body (usually ground)"),
             Port("pa", H, "chamber A pressure (sensed only)"), Port("pb", H, "chamber B pressure (sensed only)"))
    parameters = (
        Param("F_S", "N", 6.4e3, "static friction force", source="seed 000 eq. 26, Table 7", min=0.0,
              bounds=(0.0, 1e6)),
        Param("C_p", "1", 0.029, "pressure-dependent fraction of |F_p|", source="seed 000 eq. 26, Table 7", min=0.0,
              max=1.0, bounds=(0.0, 0.2)),
        Param("v0", "m/s", 1e-3, "transition velocity", source="seed 000 eq. 23", positive=True, bounds=(1e-5, 0.1)),
        Param("A_A", "m^2", 0.04909, "piston area (0.25 m bore, Table 6)", positive=True),
        Param("A_B", "m^2", 0.03682, "annulus area φ·A_p (0.25/0.125 m, Table 6)", positive=True),
    )
    variables = (VariableSpec("F", "N", "friction force opposing a relative to b"),
                 VariableSpec("F_p", "N", "pressure force p_A·A_A − p_B·A_B"))

    def equations(self, c):
        p = c.p
        v = c.across("a") - c.across("b")
        f_p = c.let("F_p", c.across("pa") * p.A_A - c.across("pb") * p.A_B)
        branch(c, "F", (p.F_S + p.C_p * E.fabs(f_p)) * E.clamp(v / p.v0, -1.0, 1.0))
