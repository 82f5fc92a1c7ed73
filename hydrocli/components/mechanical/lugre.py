"""Dynamic friction with bristles (LuGre: Canudas de Wit, Olsson, Åström & Lischinsky 1995,
IEEE TAC 40(3), eqs. 1–3) on the static curve of ``friction`` (seed 004 eqs. 9–11).

    dz/dt = v − σ0·|v|·z / g(v),   g(v) = k_c + k_s·e^(−|v|/v_s)   (each direction's k_c, k_s, v_s)
    F     = σ0·z + σ1·dz/dt + k_v·v   (+ the pressure term of ``friction``)

In steady sliding z = g(v)·sign(v)/σ0 and F is the static law k_v·v + g(v)·sign(v); below the
breakaway the contact is a spring σ0 with damping σ1 (pre-sliding: a seal deflects by g/σ0,
micrometres, before it slides), so a reversal is a hysteresis in position, not a jump of the
force at v = 0. The static element's tanh band stands in for that deflection; here it is not
used."""
from __future__ import annotations

from ...model import expr as E
from ..base import Param, StateSpec
from ..dynamics import tanh_sign
from ..registry import register
from ..two_port import branch
from .. import roles as RL
from ..roles import role
from ..rotational.elements import RotaryFriction
from .friction import Friction

#: N: floor of g(v), so a contact with no Coulomb or Stribeck force left is a pure spring–damper
#: path that relaxes instead of dividing by zero
G_MIN = 1e-3


def bristle_force(c, v, g, viscous, sigma0, sigma1):
    """F = σ0·z + σ1·dz/dt + viscous, with dz/dt = v − σ0·|v|·z/(g + G_MIN) stamped on the
    element's state ``z`` (Canudas de Wit et al. 1995 eqs. 1–3)."""
    z = c.state("z")
    zdot = v - sigma0 * E.fabs(v) * z / (g + G_MIN)
    c.der("z", zdot)
    return sigma0 * z + sigma1 * zdot + viscous


def bristle_spec(base, force: str, travel: str, sigma0: float, sigma1: float, top: float) -> tuple:
    """(roles, parameters, states) of ``base`` with bristles: its FRICTION role offering
    ``bristle_stiffness``/``bristle_damping``, the parameters σ0 [force/travel] and
    σ1 [force·s/travel] (defaults ``sigma0``, ``sigma1``; σ0 within ``top``·10⁻⁸ … ``top``), and
    the bristle state z [travel]."""
    rl = base.roles[0]
    roles = (role(RL.FRICTION, dict(rl.ports), **dict(rl.params), bristle_stiffness="sigma0", bristle_damping="sigma1"),)
    parameters = base.parameters + (
        Param("sigma0", f"{force}/{travel}", sigma0, f"bristle stiffness σ0 (pre-sliding {travel} g/σ0)", positive=True,
              bounds=(1e-8 * top, top)),
        Param("sigma1", f"{force}*s/{travel}", sigma1, "bristle damping σ1", min=0.0, bounds=(0.0, 1e-3 * top)),
    )
    return roles, parameters, (StateSpec("z", travel, "mean bristle deflection", nominal=1e-6),)


@register
class LuGreFriction(Friction):
    """Asymmetric viscous/Coulomb/Stribeck friction with bristle dynamics (LuGre)."""

    type = "friction_lugre"
    roles, parameters, states = bristle_spec(Friction, "N", "m", 1e8, 1e3, 1e11)
    description = "Asymmetric viscous/Coulomb/Stribeck friction with bristle (pre-sliding) dynamics, LuGre"
    source = "Canudas de Wit et al. 1995 eqs. 1–3; seed 004 eqs. 9–11"

    def equations(self, c):
        p = c.p
        v = c.across("a") - c.across("b")
        speed = E.fabs(v)
        g = E.where(v >= 0.0, p.kc_p + p.ks_p * E.exp(-speed / p.vs_p), p.kc_m + p.ks_m * E.exp(-speed / p.vs_m))
        f = bristle_force(c, v, g, E.where(v >= 0.0, p.kv_p, p.kv_m) * v, p.sigma0, p.sigma1)
        if c.connected("pa") and c.connected("pb"):
            f = f + p.mu_p * p.A_p * (c.across("pa") + c.across("pb")) * tanh_sign(v, p.eps)
        branch(c, "F", f)


@register
class RotaryLuGreFriction(RotaryFriction):
    """Coulomb/viscous/Stribeck friction on a rotational node with bristle dynamics (LuGre):
    the same law as ``friction_lugre`` in torque and angle (a vane's seals deflect before they
    slide)."""

    type = "rotary_friction_lugre"
    roles, parameters, states = bristle_spec(RotaryFriction, "N*m", "rad", 1e5, 10.0, 1e9)
    description = "Coulomb/viscous/Stribeck rotary friction with bristle (pre-sliding) dynamics, LuGre"
    source = "Canudas de Wit et al. 1995 eqs. 1–3; seed 001 eqs. 14–15"

    def equations(self, c):
        p = c.p
        w = c.across("a") - c.across("b")
        g = p.tau_c + p.tau_s * E.exp(-E.fabs(w) / p.w_s)
        tau = c.let("tau", bristle_force(c, w, g, p.b * w, p.sigma0, p.sigma1))
        c.through("a", tau)
        c.through("b", -tau)
