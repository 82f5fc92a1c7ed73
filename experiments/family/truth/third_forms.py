"""Third truth forms of the vocabulary effects (session 48): physically different from the two
forms the diagnosis was developed on, to test it on forms nobody tuned it on.

Each class is an ``experiments.concealed.truth.effects.Effect`` (same hooks as forms.py), so it
runs on the EHA truth (FamilyEHATruth) and the lift / rotary truth (ActuatorTruth). Forms whose
hooks carry no state read the state the truth stored for this right-hand-side call
(``model._y``, set by ActuatorTruth.rhs and FamilyEHATruth.rhs). Their nominal parameters
and machines are in catalogue.THIRD, beside the first two forms'.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from scipy.integrate import solve_ivp

from experiments.concealed.truth import effects as C
from experiments.concealed.truth.eha import flow_law

from .forms import CompliantMount, areas, ports

Effect = C.Effect
P_REF = 1e5          # [Pa] pressure at which the trapped air pocket's volume is given


def chamber_volumes(model, x: float) -> tuple[float, float]:
    """V_1, V_2 of the truth the effect runs on (cylinder, vane, motor or the EHA's)."""
    if hasattr(model, "chamber_volumes"):
        return model.chamber_volumes(x)
    p = model.p
    return p["V10"] + p["A"] * x, p["V20"] - p["A"] * x


def chamber_volume_A(model, x: float) -> float:
    """V_A(x) of the truth the effect runs on (a cylinder, a vane or the EHA's chamber 1)."""
    return chamber_volumes(model, x)[0]


def logistic(z: float) -> float:
    if z >= 0.0:
        return 1.0 / (1.0 + math.exp(-z))
    e = math.exp(z)
    return e / (1.0 + e)


# ---- 1. entrained_air: a free-air pocket in chamber A only ----------------------------------
class AirPocketChamberA(Effect):
    name = "entrained_air"
    form = ("a pocket of FREE AIR trapped in chamber A only (poorly bled cylinder), isothermal: "
            "V_g = V_g0 p_ref / P_A (p_ref = 1 bar); chamber A's capacitance "
            "C_A = V_A/beta + V_g0 p_ref / P_A^2, dP_A/dt = (net inflow)/C_A; chamber B unaffected")

    def capacitance_A(self, model, x: float, PA: float) -> float:
        PA = max(PA, 1e4)
        return chamber_volume_A(model, x) / model.p["beta"] + self.params["V_g0"] * P_REF / PA ** 2

    def more_derivatives(self, model, t, y, dy, qs):
        # the truth wrote dP_A/dt = beta (net inflow) / V_A: rescale to the pocket's capacitance
        x = y[5]
        C_oil = chamber_volume_A(model, x) / model.p["beta"]
        dy[3] *= C_oil / self.capacitance_A(model, x, y[3])


# ---- 2. internal_leakage: a scored barrel over a band of the stroke -------------------------
class ScoredBoreLeakage(Effect):
    name = "internal_leakage"
    form = ("SCORED BARREL: laminar cross-piston leak only while the piston seal is over the "
            "score, q = c w(x) (P1 - P2), w(x) = s((x - x1)/d) s((x2 - x)/d), s = logistic "
            "(edges of width d, a few % of the stroke); for the vane the same in angle")
    base_overrides = {"c_il": 0.0}

    def window(self, x: float) -> float:
        p = self.params
        return logistic((x - p["x1"]) / p["d"]) * logistic((p["x2"] - x) / p["d"])

    def leakages(self, model, P1, P2):
        return self.params["c"] * self.window(model._y[5]) * (P1 - P2), 0.0, 0.0


# ---- 3. pressure_dependent_friction: both seals, loaded by gauge pressures ------------------
class BothSealsGaugeFriction(Effect):
    name = "pressure_dependent_friction"
    form = ("piston AND rod seals loaded by their chambers' GAUGE pressures: "
            "F = mu (A_A max(P_A - Pd, 0) + A_B max(P_B - Pd, 0)) tanh(v / eps2) "
            "(not the difference |P_A - P_B|, not the rod side alone)")

    def extra_friction(self, model, v, P1, P2):
        AA, AB = areas(model)
        Pd = model.p["Pd"]
        N = AA * max(P1 - Pd, 0.0) + AB * max(P2 - Pd, 0.0)
        return self.params["mu"] * N * math.tanh(v / self.params["eps2"])


# ---- 4. stribeck_friction: exponential decay ------------------------------------------------
class ExponentialStribeck(Effect):
    name = "stribeck_friction"
    form = ("truth base has NO Stribeck term (ks = 0); symmetric EXPONENTIAL Stribeck hump "
            "F = Fs exp(-|v|/vs) tanh(v / v_eps) (not Gaussian exp(-(v/vs)^2), no bristles)")
    base_overrides = {"ks_p": 0.0, "ks_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        p = self.params
        return p["Fs"] * math.exp(-abs(v) / p["vs"]) * math.tanh(v / p["v_eps"])


# ---- 5. input_delay: a sampled (digital) controller -----------------------------------------
class SampledController(Effect):
    name = "input_delay"
    form = ("the recorded u is a digital controller's output; the valve gets it through a "
            "ZERO-ORDER HOLD at T_s plus one sample of transport delay: "
            "u_valve(t) = u(T_s (floor(t/T_s) - 1)) (a staircase, mean lag 1.5 T_s)")

    def __init__(self, **params):
        super().__init__(**params)
        self._seg = None            # sample index of the segment being integrated (simulate)

    def sample_index(self, t: float) -> int:
        if self._seg is not None:
            return self._seg
        return int(math.floor(t / self.params["T_s"] + 1e-9))

    def command(self, model, t, y, u, du):
        Ts = self.params["T_s"]
        raw = getattr(model.inputs, "raw", model.inputs)
        return raw.u_and_slope(Ts * (self.sample_index(t) - 1))[0], 0.0

    def setup(self, model):
        # the held command jumps at every sample instant: the replay integrates sample interval by
        # sample interval, restarting the solver at each jump (no step straddles a discontinuity);
        # the closed loop (bench.closed_loop, its own solver) reads the same staircase
        eff = self

        def simulate(t_eval, y0, method="LSODA", rtol=1e-7, atol=None, max_step=2e-3):
            return eff.simulate_held(model, t_eval, y0, method, rtol, atol, max_step)

        model.simulate = simulate

    def simulate_held(self, model, t_eval, y0, method="LSODA", rtol=1e-7, atol=None, max_step=2e-3):
        Ts = self.params["T_s"]
        if atol is None:
            atol = model.default_atol()
        t_eval = np.asarray(t_eval, dtype=float)
        t0, t1 = float(t_eval[0]), float(t_eval[-1])
        k = int(math.floor(t0 / Ts + 1e-9))
        y = np.asarray(y0, dtype=float)
        ys, ts = [], []
        ok, msg = True, "ok"
        try:
            a = t0
            while a < t1:
                b = min((k + 1) * Ts, t1)
                last = b >= t1
                sel = t_eval[(t_eval >= a) & ((t_eval < b) | last)]
                te = sel if (len(sel) and sel[-1] == b) else np.append(sel, b)
                self._seg = k
                if b > a:
                    sol = solve_ivp(model.rhs, (a, b), y, method=method, t_eval=te, rtol=rtol,
                                    atol=atol, max_step=max_step)
                    if not sol.success:
                        ok, msg = False, sol.message
                        break
                    if len(sel):
                        ys.append(sol.y[:, :len(sel)])
                        ts.append(sol.t[:len(sel)])
                    y = sol.y[:, -1]
                a, k = b, k + 1
        finally:
            self._seg = None
        Y = np.concatenate(ys, axis=1) if ys else np.zeros((len(y0), 0))
        return SimpleNamespace(t=np.concatenate(ts) if ts else np.zeros(0), y=Y, success=ok,
                               message=msg)


# ---- 6. sensor_lag: the position transducer through a first-order lag -----------------------
class PositionSensorLag(Effect):
    name = "sensor_lag"
    form = ("slow POSITION transducer: x measured through a first-order lag tau_x, "
            "x_m' = (x - x_m)/tau_x; the cylinder's velocity is differentiated from the same "
            "transducer, so v_m = x_m' = (x - x_m)/tau_x (the same lag); pressures unaffected")

    def setup(self, model):
        model.layout.add("xs")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = y[5]

    def more_derivatives(self, model, t, y, dy, qs):
        i = model.n_base
        dy[i] = (y[5] - y[i]) / self.params["tau_x"]

    def sensor_outputs(self, model, Y, out):
        i = model.n_base
        out["x"] = Y[i].copy()
        out["v"] = (Y[5] - Y[i]) / self.params["tau_x"]

    def atol(self, name):
        return 1e-9


# ---- 7. line_dynamics: one flexible hose on line A -------------------------------------------
class HoseALine(Effect):
    name = "line_dynamics"
    form = ("a long FLEXIBLE hose on line A only (valve port A to chamber A), one lumped "
            "pi-section: capacitance C_h = V_h/beta_h (oil + hose wall, beta_h < beta) split "
            "half at the valve port (node P_vA) and half added to chamber A, inertance I and "
            "laminar R_l between: C_h/2 dP_vA/dt = q_valve - q_h, I dq_h/dt = P_vA - P_A - R_l q_h, "
            "(V_A/beta + C_h/2) dP_A/dt = q_h - A_A v - ...; line B rigid")

    def setup(self, model):
        model.layout.add("PvA", "qhA")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = y[3]
        y[model.n_base + 1] = 0.0

    def C_h(self):
        return self.params["V_h"] / self.params["beta_h"]

    def port_pressures(self, model, y):
        return y[model.n_base], ports(model, y)[1]

    def chamber_inflows(self, model, y, qa, qb, dy):
        i, p = model.n_base, self.params
        PvA, qh = y[i], y[i + 1]
        dy[i] = (qa - qh) / (0.5 * self.C_h())
        dy[i + 1] = (PvA - y[3] - p["R_l"] * qh) / p["I"]
        return qh, qb

    def more_derivatives(self, model, t, y, dy, qs):
        # the truth wrote dP_A/dt = beta (net inflow) / V_A: the hose's cylinder-end half
        # capacitance adds to chamber A's
        C_oil = chamber_volume_A(model, y[5]) / model.p["beta"]
        dy[3] *= C_oil / (C_oil + 0.5 * self.C_h())

    def atol(self, name):
        return 10.0 if name == "PvA" else 1e-9


# ---- 8. structural_flexibility: a friction-damped mount -------------------------------------
class DryDampedMount(CompliantMount):
    form = ("cylinder body / vane housing (mass m_b) on a friction-damped bushing: linear "
            "spring, viscous damper AND a dry-friction damper in parallel, "
            "F_mount = k_b d + c_b d' + F_d tanh(d'/v_d); stroke measured rod to body, the "
            "load's weight at its absolute position (as mount_linear)")

    def mount_force(self, xb, vb):
        p = self.params
        return p["k_b"] * xb + p["c_b"] * vb + p["F_d"] * math.tanh(vb / p["v_d"])


# ---- 9. end_stop: a hydraulic end-of-stroke cushion -----------------------------------------
class HydraulicCushion(C.EndStop):
    """The cushion's throttling on the valve's B edge; the metal contact at x_stop is the
    Hunt–Crossley stop's (``piston_accel`` inherited from ``EndStop``)."""
    form = ("HYDRAULIC CUSHION at the end of stroke: over the last L_c before x_stop a cushion "
            "spear throttles chamber B's OUTFLOW in series with the valve edge, orifice "
            "K_c(x) = K_end / sigma(x), sigma = smoothstep((x - x_stop + L_c)/L_c), so the "
            "edge's outflow scales by 1/sqrt(1 + (a sigma / K_end)^2) (a = the edge's opening); "
            "inflow bypasses it (check valve); metal contact at x_stop as hunt_crossley "
            "(k d^1.5 (1 + lam d'))")
    custom_valve = True

    def sigma(self, x: float) -> float:
        p = self.params
        e = min(max((x - p["x_stop"] + p["L_c"]) / p["L_c"], 0.0), 1.0)
        return e * e * (3.0 - 2.0 * e)

    def throttle(self, a: float, x: float) -> float:
        """Factor on the B edge's outflow: two orifices in series, K_eff = a K_c / sqrt(a^2 + K_c^2)."""
        return 1.0 / math.sqrt(1.0 + (a * self.sigma(x) / self.params["K_end"]) ** 2)

    def valve_flows(self, model, xv, Ps, y):
        PA, PB = ports(model, y)
        qa, qb, qs = model.valve_flows(xv, Ps, PA, PB)
        p = model.p
        a = p["Kv"] * abs(xv) / 100.0
        q_edge = -a * flow_law(PB - p["Pd"], p["dp_lam"]) if xv >= 0.0 else a * flow_law(Ps - PB, p["dp_lam"])
        if q_edge < 0.0:                                  # out of chamber B: through the cushion
            f = self.throttle(a, y[5])
            qb += (f - 1.0) * q_edge
            if xv < 0.0:
                qs += (f - 1.0) * q_edge
        return qa, qb, qs
