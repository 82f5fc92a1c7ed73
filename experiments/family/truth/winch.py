"""The hoist winch's own pieces of truth: closed forms of its base model and the hook load
bouncing on the rope the drum pays out.

The base model is ``ActuatorTruth`` with ``kind = "winch"`` (actuator.py): a fixed-displacement
motor (D = A_A = A_B [m^3/rad]) with CONSTANT chamber volumes V10, V20, a constant load torque
-W (W = m_load g r) and the drum-referred inertia J (the truth's ``m``). Closed forms:

* holding:   D (P1 - P2) = W at rest (friction and flow vanish);
* continuity with the valve closed and no leakage:  V_i dP_i/dt = beta (-/+ D w), so
  P1 + P2 stays constant and P1 - P2 = dp0 - 2 beta D (theta - theta0) / V for V10 = V20 = V;
* locked motor: a small disturbance rings at  omega_h = sqrt(k_h / J),
  k_h = beta D^2 (1/V10 + 1/V20)  (hydraulic stiffness; the constant W does not add one,
  unlike the pendulum's W cos(theta)).

Hook load (``payload_swing``): the load hangs on a rope of length L = L0 - r theta below the
drum (hoisting, theta > 0, shortens it). In drum coordinates (the rope's stretch s as an angle,
s r in metres) the load is a share m_frac of the drum-referred inertia, J_p = m_frac J, and of
the weight moment, W_p = m_frac W, on a rope whose stiffness is that of a steel rope,
EA / L, i.e.

    k(theta) = J_p (2 pi f_hz)^2 L0 / L(theta),     c = 2 zeta J_p 2 pi f_hz,

with f_hz the bounce frequency against a held drum at L = L0 and s the stretch beyond the
static one. Tension T = W_p + k s + c s' (a rope cannot push: T >= 0):

    drum:  (J - J_p) theta'' = D (P1 - P2) - T_f - (W - W_p) - T
    load:  J_p (theta'' - s'') = T - W_p

(``forms._HangingPayload``, the lifts' hook load, with the stiffness above). Angle and speed
are measured on the drum.
"""
from __future__ import annotations


from . import forms as F


def holding_dp(p: dict) -> float:
    """P1 - P2 [Pa] that holds the load at rest: W / D."""
    return p["W"] / p["A_A"]


def hydraulic_stiffness(p: dict) -> float:
    """k_h = beta D^2 (1/V10 + 1/V20) [N m/rad] of the locked motor."""
    return p["beta"] * p["A_A"] ** 2 * (1.0 / p["V10"] + 1.0 / p["V20"])


def rope_length_factor(params: dict, theta: float) -> float:
    """L0 / L(theta), L = L0 - r theta, the rope kept at least a quarter of L0 long."""
    L0 = params["L0"]
    return L0 / max(L0 - params["r"] * theta, 0.25 * L0)


class DrumRopeBounce(F.RopeBouncePayload):
    form = ("hook load (share m_frac of the drum-referred inertia and weight) on the rope paid "
            "out by the drum: LINEAR rope spring-damper at f_hz (at the rope length L0) with "
            "damping ratio zeta, stiffness EA/L growing as the winch hoists (L = L0 - r theta), "
            "slack-capable")

    def stiffening(self, model) -> float:
        return rope_length_factor(self.params, model._y[5])


class DrumSheaveFriction(F.SheaveFrictionPayload):
    form = ("hook block reeved over sheaves on the drum's rope: rope spring EA/L at f_hz (at L0; "
            "L = L0 - r theta), damped by the sheaves' DRY friction proportional to the tension "
            "(mu T tanh(s'/1e-3 rad/s)) plus a little viscous zeta")

    def stiffening(self, model) -> float:
        return rope_length_factor(self.params, model._y[5])
