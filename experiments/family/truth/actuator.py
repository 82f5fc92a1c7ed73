"""Independent truth simulator of a valve-controlled actuator carrying a gravity load.

Extends the seed 004 bench truth (experiments/concealed/truth/eha.py: same state layout,
valve, friction law, sensors and effect hooks, so the concealed effect classes apply
unchanged) to two new machine types, written by hand with numpy/scipy (no hydrocli):

* ``kind = "linear"``: vertical single-rod cylinder lifting a mass (piston area A_A, annulus
  A_B), gravity force -W (W = m g):
      V_A = V10 + A_A x,  V_B = V20 - A_B x
      dP_A/dt = beta (q_A - A_A v - q_il - q_eA) / V_A
      dP_B/dt = beta (q_B + A_B v + q_il - q_eB) / V_B
      m dv/dt = A_A P_A - A_B P_B - W - F_f(v)
  optionally with a counterbalance valve (``cbv = 1``) between the valve port A line
  (volume V_lA, pressure P_VA: extra base state) and chamber A, piloted by P_B: the vented
  black-box law of seed 000 eqs. 15-22 (mu_x = p_x/p_L, cracking when p_L + C1 p_x > p_cr,
  Q = (A0 + A1 mu_x) s^n0, vanishing as p_V -> p_L) plus its check valve V -> L.
* ``kind = "rotary"``: vane actuator (displacement D = A_A = A_B per rad) on a pendulum
  (inertia J = m, weight moment W): torque D (P1 - P2) - W sin(theta + theta0) - T_f(w);
  x, v are theta, omega (seed 001 eqs. 9-15).
* ``kind = "winch"``: fixed-displacement hydraulic motor (D = A_A = A_B per rad) turning a
  hoist drum that holds a hanging load: continuous rotation, so the chamber volumes do NOT
  change with the angle (V_1 = V10, V_2 = V20), and the load torque is the CONSTANT weight
  moment -W (W = m_load g r_drum):
      dP_1/dt = beta (q_A - D w - q_il - q_e1) / V10
      dP_2/dt = beta (q_B + D w + q_il - q_e2) / V20
      J dw/dt = D (P1 - P2) - W - T_f(w)
  (experiments/family/truth/winch.py has the closed forms the tests check).

Pressures absolute [Pa], u and the spool x_v in percent (as eha.py).
"""
from __future__ import annotations

import math

from experiments.concealed.truth.eha import K_RL, P_TAU, EHATruth, flow_law
from experiments.concealed.truth.effects import Effect


def _reg_power(s: float, n: float, eps: float) -> float:
    """s^n for s > 0 with a linear start below eps (seed 000 eq. 20, regularised)."""
    sp = s if s > 0.0 else 0.0
    return sp * (sp + eps) ** (n - 1.0)


def _smooth_pos(x: float, eps: float) -> float:
    return 0.5 * (x + math.sqrt(x * x + eps * eps))


def cbv_flows(p: dict, P_L: float, P_V: float, P_X: float) -> float:
    """Net flow L -> V through a vented counterbalance valve and its check valve [m^3/s]."""
    Pr = p["Pd"]
    pl, px = P_L - Pr, P_X - Pr
    mu_x = px / max(pl, 1e5)
    s = pl / p["p_cr"] - 1.0 / (1.0 + p["C1"] * mu_x)
    q = (p["A0"] + p["A1"] * mu_x) * _reg_power(s, p["n0"], 1e-3)
    drop = _smooth_pos(P_L - P_V, 1e4)
    q *= drop / (drop + 1e4)
    dpc = P_V - P_L                               # check valve V -> L
    xi = min(max((dpc - 1e5) / 1e5, 0.0), 1.0)
    return q - xi * p["Cv_check"] * flow_law(dpc, 1e4)


class ActuatorTruth(EHATruth):
    """Right-hand side for the lift cylinder / rotary drive / hoist winch; effects as in
    concealed."""

    def __init__(self, p: dict, effect=None, inputs=None):
        self.cbv = bool(p.get("cbv", 0))
        if self.cbv:
            self.BASE_STATES = EHATruth.BASE_STATES + ["PVA"]
        super().__init__(p, effect, inputs)

    def load_force(self, x: float) -> float:
        p = self.p
        if p["kind"] == "rotary":
            return -p["W"] * math.sin(x + p["theta0"])
        return -p["W"]

    def chamber_volumes(self, x: float) -> tuple[float, float]:
        """V_1, V_2: a cylinder's and a vane's change with the stroke / angle, a motor's
        (``kind = "winch"``) do not."""
        p = self.p
        if p["kind"] == "winch":
            return p["V10"], p["V20"]
        return p["V10"] + p["A_A"] * x, p["V20"] - p["A_B"] * x

    def initial_state(self, x0: float, P0: float, PB0: float | None = None):
        import numpy as np
        y = np.zeros(len(self.layout.names))
        y[3] = y[7] = P0
        y[4] = y[8] = P0 if PB0 is None else PB0
        y[5] = x0
        if self.cbv:
            y[9] = y[4]
        if self.effect is not None:
            self.effect.init_state(self, y, x0, P0)
        return y

    def ports(self, y):
        """Pressures at the valve work ports A and B (A behind the CBV line when fitted)."""
        return (y[9] if self.cbv else y[3]), y[4]

    def rhs(self, t, y):
        self._y = y                     # for effects whose hooks need the state (forms.py)
        p, eff, inp = self.p, self.effect, self.inputs
        _, Ps, Fx = inp.at(t)
        if eff is not None and eff.delay > 0.0:
            u, du = inp.u_and_slope(t - eff.delay)
        else:
            u, du = inp.u_and_slope(t)
        if eff is not None and hasattr(eff, "command"):
            u, du = eff.command(self, t, y, u, du)
        xrl, xv, xvd, P1, P2, x, v, P1m, P2m = y[:9]
        dy = [0.0] * len(y)
        s = du + K_RL * (u - xrl)
        smax = p["s_max"]
        dy[0] = smax if s > smax else (-smax if s < -smax else s)
        tv = p["tau_v"]
        dy[1] = xvd
        dy[2] = (xrl - 2.0 * tv * xvd - xv) / (tv * tv)
        xv_eff = eff.spool_opening(self, xv) if eff is not None else xv
        Ps_valve = eff.supply_at_valve(self, y, Ps) if eff is not None else Ps
        if eff is not None and eff.custom_valve:
            qa, qb, qs = eff.valve_flows(self, xv_eff, Ps_valve, y)
        else:
            if eff is None or type(eff).port_pressures is Effect.port_pressures:
                PA, PB = self.ports(y)
            else:
                PA, PB = eff.port_pressures(self, y)
            qa, qb, qs = self.valve_flows(xv_eff, Ps_valve, PA, PB)
        if eff is not None:
            q1, q2 = eff.chamber_inflows(self, y, qa, qb, dy)
        else:
            q1, q2 = qa, qb
        if self.cbv:                               # valve A line -> CBV -> chamber A
            q_cbv = cbv_flows(p, P1, y[9], P2)
            dy[9] = p["beta"] * (q1 + q_cbv) / p["V_lA"]
            q1 = -q_cbv
        AA, AB = p["A_A"], p["A_B"]
        qil = p["c_il"] * (P1 - P2)
        qe1 = p["c_el"] * (P1 - p["Pd"])
        qe2 = p["c_el"] * (P2 - p["Pd"])
        if eff is not None:
            ql, qe1x, qe2x = eff.leakages(self, P1, P2)
            qil += ql
            qe1 += qe1x
            qe2 += qe2x
        V1, V2 = self.chamber_volumes(x)
        b1 = eff.bulk_modulus(self, P1) if eff is not None else p["beta"]
        b2 = eff.bulk_modulus(self, P2) if eff is not None else p["beta"]
        dy[3] = b1 * (q1 - AA * v - qil - qe1) / V1
        dy[4] = b2 * (q2 + AB * v + qil - qe2) / V2
        dy[5] = v
        F = self.load_force(x) + Fx
        Fp = AA * P1 - AB * P2
        Ff = self.friction(v, y)
        if eff is not None:
            Ff += eff.extra_friction(self, v, P1, P2)
            dy[6] = eff.piston_accel(self, y, Fp, F, Ff, dy)
        else:
            dy[6] = (Fp + F - Ff) / p["m"]
        dy[7] = (P1 - P1m) / P_TAU
        dy[8] = (P2 - P2m) / P_TAU
        if eff is not None:
            eff.more_derivatives(self, t, y, dy, qs)
        return dy

    def default_atol(self):
        a = super().default_atol()
        if self.p["kind"] in ("rotary", "winch"):
            a[5], a[6] = 1e-7, 1e-6
        if self.cbv:
            a[9] = 10.0
        return a


class _CommandPath:
    """Inputs seen through an effect's command hook (forms.LagCascadeDelay) on the EHA truth,
    whose right-hand side has no such hook; ``raw`` is the undelayed recording."""

    def __init__(self, model, raw):
        self.model, self.raw = model, raw

    def at(self, t):
        return self.raw.at(t)

    def u_and_slope(self, t):
        u, du = self.raw.u_and_slope(t)
        return self.model.effect.command(self.model, t, self.model._y, u, du)


class FamilyEHATruth(EHATruth):
    """The concealed EHA truth, unchanged, plus the two hooks the family's forms use: the
    current state for spool hooks (``_y``) and the command path (``command``)."""

    @property
    def inputs(self):
        return self._inputs

    @inputs.setter
    def inputs(self, value):
        eff = getattr(self, "effect", None)
        self._inputs = (_CommandPath(self, value) if value is not None and eff is not None
                        and hasattr(eff, "command") else value)

    def rhs(self, t, y):
        self._y = y
        return super().rhs(t, y)
