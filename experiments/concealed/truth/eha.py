"""Independent "truth" simulator of the seed 004 electro-hydraulic actuator.

Written by hand from Cogni, Mazzoleni, Previdi (seed 004), deliberately without hydrocli's
netlist, builder or components, so that `hydro diagnose` is tested against physics written
separately.

Base model (seed 004 numbering):
  eq. 1   rate limiter on the spool reference, |d xrl/dt| <= s_max (exact for a piecewise
          linear command: d xrl/dt = clip(du/dt + K_rl (u - xrl), -s_max, s_max))
  eq. 2   spool  X_v / X_rl = 1 / (1 + tau_v s)^2
  eq. 3 / Table I  orifice flows  q = Kv (x_v/100) f(dp),  f(dp) = dp (dp^2 + dp_lam^2)^(-1/4)
          (turbulent sqrt law with a smooth laminar transition below dp_lam)
  (optional) laminar clearance leakage G_leak of each metering edge (valve centre leakage,
          base parameter "G_leak", absent = 0; used as a known base property of one case)
  eqs. 6-7 chamber continuity with internal (c_il) and external (c_el) laminar leakage
  eq. 8   force balance  m dv/dt = A (P1 - P2) + Fext - Ffrict(v)
  eqs. 9-11 asymmetric viscous + Coulomb + Stribeck friction with tanh(v/eps) smoothing

Sensors: P1/P2 through a first-order lag P_tau (states of the ODE), x and v ideal (noise is
added by the generator); effects may change this (see effects.py).

All quantities SI, pressures absolute, u and x_v in percent.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

# seed 004, section V (identified values) + bench constants
NOMINAL_BASE = {
    "Kv": 4.68e-07, "tau_v": 0.004, "s_max": 2000.0, "A": 0.0020993692907613796,
    "V10": 0.000211, "V20": 0.000675, "beta": 1.73e9, "c_il": 2.18e-11, "c_el": 0.0,
    "m": 74.11, "kv_p": 12100.0, "kv_m": 13700.0, "kc_p": 1140.0, "kc_m": 1180.0,
    "ks_p": 244.37, "ks_m": 39.36, "taus_p": 0.00341, "taus_m": 0.00196,
    "eps": 1e-4, "Pd": 1e5, "dp_lam": 5e4,
}
PERTURBED = ["Kv", "tau_v", "V10", "V20", "beta", "c_il", "m", "kv_p", "kv_m", "kc_p", "kc_m",
             "ks_p", "ks_m", "taus_p", "taus_m"]
K_RL = 1000.0          # [1/s] tracking gain of the rate-limiter state (exact when not limiting)
P_TAU = 1e-3           # [s] pressure sensor lag of every recording


def flow_law(dp: float, dp_lam: float) -> float:
    """sign(dp) sqrt(|dp|) for |dp| >> dp_lam, linear (laminar) for |dp| << dp_lam."""
    return dp / math.sqrt(math.sqrt(dp * dp + dp_lam * dp_lam))


class Inputs:
    """Sampled inputs with first-order hold (linear interpolation), as the recordings define."""

    def __init__(self, t0: float, dt: float, u, Ps, Fext):
        self.t0, self.dt = float(t0), float(dt)
        self.u = [float(a) for a in u]
        self.Ps = [float(a) for a in Ps]
        self.F = [float(a) for a in Fext]
        self.n = len(self.u)

    def _idx(self, t: float):
        s = (t - self.t0) / self.dt
        k = int(math.floor(s))
        if k < 0:
            return 0, 0.0
        if k >= self.n - 1:
            return self.n - 2, 1.0
        return k, s - k

    def at(self, t: float):
        k, a = self._idx(t)
        u, P, F = self.u, self.Ps, self.F
        return (u[k] + a * (u[k + 1] - u[k]), P[k] + a * (P[k + 1] - P[k]),
                F[k] + a * (F[k + 1] - F[k]))

    def u_and_slope(self, t: float):
        k, a = self._idx(t)
        u = self.u
        du = u[k + 1] - u[k]
        return u[k] + a * du, du / self.dt


@dataclass
class Layout:
    """Names of the state vector entries (base states first, effect states appended)."""
    names: list = field(default_factory=list)

    def add(self, *names):
        for n in names:
            self.names.append(n)

    def index(self, name):
        return self.names.index(name)


class EHATruth:
    """Right-hand side of the truth model; `effect` is an effects.Effect (or None)."""

    BASE_STATES = ["xrl", "xv", "xvd", "P1", "P2", "x", "v", "P1m", "P2m"]

    def __init__(self, p: dict, effect=None, inputs: Inputs | None = None):
        self.p = dict(p)
        self.effect = effect
        self.inputs = inputs
        self.layout = Layout(list(self.BASE_STATES))
        self.n_base = len(self.BASE_STATES)
        if effect is not None:
            effect.setup(self)

    # ---- pieces the effects may override --------------------------------------------------
    def friction(self, v: float, y) -> float:
        p = self.p
        th = math.tanh(v / p["eps"])
        if v >= 0.0:
            f = p["kv_p"] * v + p["kc_p"] * th + p["ks_p"] * th * math.exp(-v / p["taus_p"])
        else:
            f = p["kv_m"] * v + p["kc_m"] * th + p["ks_m"] * th * math.exp(v / p["taus_m"])
        return f

    def valve_flows(self, xv: float, Ps: float, P1: float, P2: float):
        """Flows INTO chamber lines A and B (Table I), and the flow drawn from supply."""
        p = self.p
        Kv, Pd, dl = p["Kv"], p["Pd"], p["dp_lam"]
        if xv >= 0.0:
            a = Kv * xv / 100.0
            qa = a * flow_law(Ps - P1, dl)
            qb = -a * flow_law(P2 - Pd, dl)
            qs = qa
        else:
            a = -Kv * xv / 100.0
            qa = -a * flow_law(P1 - Pd, dl)
            qb = a * flow_law(Ps - P2, dl)
            qs = qb
        G = p.get("G_leak", 0.0)
        if G:
            # laminar clearance leakage of each of the four metering edges (valve centre
            # leakage; hydrocli's valve_4_3 G_leak): P->A, A->T, P->B, B->T
            qa += G * (Ps - P1) - G * (P1 - Pd)
            qb += G * (Ps - P2) - G * (P2 - Pd)
            qs += G * (Ps - P1) + G * (Ps - P2)
        return qa, qb, qs

    # ---- the model ---------------------------------------------------------------------------
    def initial_state(self, x0: float, P0: float) -> np.ndarray:
        y = np.zeros(len(self.layout.names))
        y[3] = y[4] = y[7] = y[8] = P0
        y[5] = x0
        if self.effect is not None:
            self.effect.init_state(self, y, x0, P0)
        return y

    def rhs(self, t: float, y) -> list:
        p = self.p
        eff = self.effect
        inp = self.inputs
        _, Ps, F = inp.at(t)
        if eff is not None and eff.delay > 0.0:
            u, du = inp.u_and_slope(t - eff.delay)
        else:
            u, du = inp.u_and_slope(t)
        xrl, xv, xvd, P1, P2, x, v, P1m, P2m = y[:9]
        dy = [0.0] * len(y)
        # eq. 1 rate limiter, eq. 2 spool
        s = du + K_RL * (u - xrl)
        smax = p["s_max"]
        dy[0] = smax if s > smax else (-smax if s < -smax else s)
        tv = p["tau_v"]
        dy[1] = xvd
        dy[2] = (xrl - 2.0 * tv * xvd - xv) / (tv * tv)
        xv_eff = eff.spool_opening(self, xv) if eff is not None else xv
        Ps_valve = eff.supply_at_valve(self, y, Ps) if eff is not None else Ps
        # valve flows (Table I)
        if eff is not None and eff.custom_valve:
            qa, qb, qs = eff.valve_flows(self, xv_eff, Ps_valve, y)
        else:
            PA, PB = (eff.port_pressures(self, y) if eff is not None else (P1, P2))
            qa, qb, qs = self.valve_flows(xv_eff, Ps_valve, PA, PB)
        # flows reaching the chambers (line dynamics may intervene)
        if eff is not None:
            q1, q2 = eff.chamber_inflows(self, y, qa, qb, dy)
        else:
            q1, q2 = qa, qb
        # eqs. 6-7 (laminar internal + external leakage), effect leakages added
        A = p["A"]
        qil = p["c_il"] * (P1 - P2)
        qe1 = p["c_el"] * (P1 - p["Pd"])
        qe2 = p["c_el"] * (P2 - p["Pd"])
        if eff is not None:
            ql, qe1x, qe2x = eff.leakages(self, P1, P2)
            qil += ql
            qe1 += qe1x
            qe2 += qe2x
        V1 = p["V10"] + A * x
        V2 = p["V20"] - A * x
        b1 = eff.bulk_modulus(self, P1) if eff is not None else p["beta"]
        b2 = eff.bulk_modulus(self, P2) if eff is not None else p["beta"]
        dy[3] = b1 * (q1 - A * v - qil - qe1) / V1
        dy[4] = b2 * (q2 + A * v + qil - qe2) / V2
        # eq. 8 force balance
        dy[5] = v
        Ff = self.friction(v, y)
        if eff is not None:
            Ff += eff.extra_friction(self, v, P1, P2)
            dy[6] = eff.piston_accel(self, y, A * (P1 - P2), F, Ff, dy)
        else:
            dy[6] = (A * (P1 - P2) + F - Ff) / p["m"]
        # pressure sensors (1 ms lag)
        dy[7] = (P1 - P1m) / P_TAU
        dy[8] = (P2 - P2m) / P_TAU
        if eff is not None:
            eff.more_derivatives(self, t, y, dy, qs)
        return dy

    def measured(self, Y: np.ndarray) -> dict:
        """Noise-free sensor signals from the state trajectory Y (n_states x n_t)."""
        out = {"P1": Y[7].copy(), "P2": Y[8].copy(), "x": Y[5].copy(), "v": Y[6].copy()}
        if self.effect is not None:
            self.effect.sensor_outputs(self, Y, out)
        return out

    def simulate(self, t_eval, y0, method="LSODA", rtol=1e-7, atol=None, max_step=2e-3):
        if atol is None:
            atol = self.default_atol()
        sol = solve_ivp(self.rhs, (t_eval[0], t_eval[-1]), y0, method=method, t_eval=t_eval,
                        rtol=rtol, atol=atol, max_step=max_step)
        return sol

    def default_atol(self) -> np.ndarray:
        scale = {"xrl": 1e-4, "xv": 1e-4, "xvd": 1e-2, "P1": 10.0, "P2": 10.0, "x": 1e-8,
                 "v": 1e-7, "P1m": 10.0, "P2m": 10.0}
        a = []
        for n in self.layout.names:
            if n in scale:
                a.append(scale[n])
            elif self.effect is not None:
                a.append(self.effect.atol(n))
            else:
                a.append(1e-8)
        return np.array(a)
