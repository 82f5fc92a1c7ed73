"""Second (and new) truth forms of the vocabulary effects, for the family generator.

Each class is an ``experiments.concealed.truth.effects.Effect`` (same hooks), so it runs on
both the seed 004 bench truth (eha.py) and the lift / rotary truth (actuator.py). Forms that
read the valve work-port pressures use ``ports(model, y)`` (behind the counterbalance valve
line when one is fitted). ``FORMS`` maps effect -> form name -> (class, nominal params,
scale exponents): the generator multiplies each listed parameter by s**exponent to set the
effect size.
"""
from __future__ import annotations

import math

from experiments.concealed.truth import effects as C
from experiments.concealed.truth.eha import flow_law

Effect = C.Effect


def ports(model, y):
    return model.ports(y) if hasattr(model, "ports") else (y[3], y[4])


def areas(model):
    p = model.p
    return (p["A_A"], p["A_B"]) if "A_A" in p else (p["A"], p["A"])


class LaminarInternalLeakage(Effect):
    name = "internal_leakage"
    form = "laminar cross-piston leakage q = c (P1 - P2)"

    def leakages(self, model, P1, P2):
        return self.params["c"] * (P1 - P2), 0.0, 0.0


class RodSealLeakage(Effect):
    name = "external_leakage"
    form = "laminar leak of chamber B only (rod seal) to drain: q_eB = c (P2 - Pd)"

    def leakages(self, model, P1, P2):
        return 0.0, 0.0, self.params["c"] * (P2 - model.p["Pd"])


class LinearViscous(Effect):
    name = "viscous_friction"
    form = "truth base has NO viscous term; linear viscous F = b v"
    base_overrides = {"kv_p": 0.0, "kv_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        return self.params["b"] * v


class ThinningViscous(Effect):
    name = "viscous_friction"
    form = ("truth base has NO viscous term; shear-thinning film F = b v / sqrt(1 + |v|/v1) "
            "(not linear)")
    base_overrides = {"kv_p": 0.0, "kv_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        return self.params["b"] * v / math.sqrt(1.0 + abs(v) / self.params["v1"])


class TanhCoulomb(Effect):
    name = "coulomb_friction"
    form = "truth base has NO Coulomb term; symmetric F = Fc tanh(v / v_c) with a wide v_c"
    base_overrides = {"kc_p": 0.0, "kc_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        return self.params["Fc"] * math.tanh(v / self.params["v_c"])


class AtanCoulomb(C.CoulombFriction):
    form = ("truth base has NO Coulomb term; asymmetric ARCTAN law "
            "F = Fc_+/- (2/pi) atan(v / v_c)")


class LuGreStribeck(Effect):
    name = "stribeck_friction"
    form = ("dynamic (LuGre-like) bristle friction with a Gaussian Stribeck curve: "
            "dz/dt = v - |v| z / g(v), g = (Fs exp(-(v/vs)^2) + F0)/s0, F = s0 z + s1 dz/dt")

    def setup(self, model):
        model.layout.add("zb")

    def _zdot(self, model, y):
        p = self.params
        v = y[6]
        z = y[model.n_base]
        g = (p["Fs"] * math.exp(-(v / p["vs"]) ** 2) + p["F0"]) / p["s0"]
        return v - abs(v) * z / g

    def extra_friction(self, model, v, P1, P2):
        return 0.0  # applied in piston_accel (needs the state)

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p = self.params
        zd = self._zdot(model, y)
        dy[model.n_base] = zd
        Fb = p["s0"] * y[model.n_base] + p["s1"] * zd - p["F0"] * math.tanh(y[6] / p["vs"])
        return (Fp + F - Ff - Fb) / model.p["m"]

    def atol(self, name):
        return 1e-10


class DiffPressureFriction(Effect):
    name = "pressure_dependent_friction"
    form = "piston-seal friction F = mu A_A |P1 - P2| tanh(v / eps2) (pressure DIFFERENCE)"

    def extra_friction(self, model, v, P1, P2):
        return (self.params["mu"] * areas(model)[0] * abs(P1 - P2)
                * math.tanh(v / self.params["eps2"]))


class RodSealPressureFriction(Effect):
    name = "pressure_dependent_friction"
    form = ("rod-seal friction loaded by the rod-side pressure only: "
            "F = mu A_B (P2 - Pd) tanh(v / eps2)")

    def extra_friction(self, model, v, P1, P2):
        return (self.params["mu"] * areas(model)[1] * max(P2 - model.p["Pd"], 0.0)
                * math.tanh(v / self.params["eps2"]))


class PolytropicAir(Effect):
    name = "entrained_air"
    form = ("free air, POLYTROPIC (n = 1.4), not dissolving: volume fraction "
            "alpha = a0 (P0/P)^(1/n) / (a0 (P0/P)^(1/n) + 1 - a0), "
            "1/beta_eff = (1 - alpha)/beta + alpha/(n P)")

    def bulk_modulus(self, model, P):
        a0, n = self.params["alpha0"], 1.4
        P = max(P, 1e5)
        g = a0 * (1e5 / P) ** (1.0 / n)
        alpha = g / (g + 1.0 - a0)
        return 1.0 / ((1.0 - alpha) / model.p["beta"] + alpha / (n * P))


class DistributedLines(Effect):
    name = "line_dynamics"
    form = ("hoses A and B as N = 3 distributed lumps each: node volume V_h/N, inertance I/N, "
            "laminar R_l/N (valve side first)")
    N = 3

    def setup(self, model):
        for h in "AB":
            model.layout.add(*[f"P{h}{k}" for k in range(self.N)], *[f"q{h}{k}" for k in range(self.N)])

    def init_state(self, model, y, x0, P0):
        i = model.n_base
        for h in range(2):
            for k in range(self.N):
                y[i + 2 * self.N * h + k] = y[3 + h]

    def port_pressures(self, model, y):
        i = model.n_base
        return y[i], y[i + 2 * self.N]

    def chamber_inflows(self, model, y, qa, qb, dy):
        i, N, p = model.n_base, self.N, self.params
        beta = model.p["beta"]
        out = []
        for h, (qin, Pc) in enumerate(((qa, y[3]), (qb, y[4]))):
            o = i + 2 * N * h
            P = y[o:o + N]
            q = y[o + N:o + 2 * N]
            for k in range(N):
                q_prev = qin if k == 0 else q[k - 1]
                dy[o + k] = beta * (q_prev - q[k]) / (p["V_h"] / N)
                P_next = Pc if k == N - 1 else P[k + 1]
                dy[o + N + k] = (P[k] - P_next - p["R_l"] / N * q[k]) / (p["I"] / N)
            out.append(q[N - 1])
        return out[0], out[1]

    def atol(self, name):
        return 10.0 if name[0] == "P" else 1e-9


class SharpAsymOverlap(Effect):
    name = "valve_overlap"
    form = ("SHARP, unequal overlaps: no opening for -o_m < x_v < o_p, linear beyond "
            "(x_e = x_v - o_p or x_v + o_m), corners smoothed over 0.05 %")

    def spool_opening(self, model, xv):
        op, om, e = self.params["o_p"], self.params["o_m"], 0.05
        up = 0.5 * ((xv - op) + math.sqrt((xv - op) ** 2 + e * e))
        dn = 0.5 * ((-xv - om) + math.sqrt((xv + om) ** 2 + e * e))
        return up - dn


class _StateSpool(Effect):
    """An effect on the metering opening that needs the state: ``spool_opening`` reads the
    state the truth stored for this rhs call (``model._y``)."""

    def spool_opening(self, model, xv):
        return self.spool_opening_y(model, model._y, xv)


class PlayHysteresis(_StateSpool):
    name = "valve_hysteresis"
    form = ("mechanical PLAY (backlash) of half-width h between the spool and the metering "
            "land: x_e follows x_v only when |x_v - x_e| reaches h (smoothed)")

    def setup(self, model):
        model.layout.add("zp")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = 0.0

    def spool_opening_y(self, model, y, xv):
        return y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        h, k = self.params["h"], 400.0
        e = y[1] - y[model.n_base]
        # x_e moves with the spool when the gap is taken up (|e| >= h), else stays
        drive = (max(e - h, 0.0) + min(e + h, 0.0))
        dy[model.n_base] = k * drive

    def atol(self, name):
        return 1e-6


class DahlHysteresis(_StateSpool):
    name = "valve_hysteresis"
    form = C.ValveHysteresis.form

    def setup(self, model):
        model.layout.add("zh")

    def spool_opening_y(self, model, y, xv):
        return xv - y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        p, i, rate = self.params, model.n_base, y[2]
        dy[i] = p["sigma"] * rate * (1.0 - (y[i] / p["h"]) * math.tanh(rate / p["eps"]))

    def atol(self, name):
        return 1e-6


class EdgeAsymmetry(Effect):
    name = "valve_asymmetry"
    form = C.ValveAsymmetry.form
    custom_valve = True

    def valve_flows(self, model, xv, Ps, y):
        p, g = model.p, self.params
        P1, P2 = ports(model, y)
        Kv, Pd, dl = p["Kv"], p["Pd"], p["dp_lam"]
        if xv >= 0.0:
            a = Kv * xv / 100.0
            qa = g["g_PA"] * a * flow_law(Ps - P1, dl)
            return _centre_leak(p, Ps, P1, P2, qa, -g["g_BT"] * a * flow_law(P2 - Pd, dl), qa)
        a = -Kv * xv / 100.0
        qb = g["g_PB"] * a * flow_law(Ps - P2, dl)
        return _centre_leak(p, Ps, P1, P2, -g["g_AT"] * a * flow_law(P1 - Pd, dl), qb, qb)


def _centre_leak(p, Ps, P1, P2, qa, qb, qs):
    """A custom valve keeps the base valve's laminar centre leakage G_leak of each edge
    (eha.EHATruth.valve_flows; the winch's valve has one, the others none: unchanged)."""
    G = p.get("G_leak", 0.0)
    if not G:
        return qa, qb, qs
    Pd = p["Pd"]
    return (qa + G * (Ps - P1) - G * (P1 - Pd), qb + G * (Ps - P2) - G * (P2 - Pd),
            qs + G * (Ps - P1) + G * (Ps - P2))


class SolenoidAsymmetry(Effect):
    name = "valve_asymmetry"
    form = ("unequal solenoid gains: the spool stroke is x_v g_p for x_v > 0 and x_v g_m for "
            "x_v < 0 (the edges match; the drive does not)")

    def spool_opening(self, model, xv):
        return xv * (self.params["g_p"] if xv >= 0.0 else self.params["g_m"])


class LagCascadeDelay(Effect):
    name = "input_delay"
    form = ("distributed delay: the command passes N = 4 first-order lags of T_d/4 each "
            "(fieldbus + amplifier filter; not a pure delay)")
    N = 4

    def setup(self, model):
        model.layout.add(*[f"ud{k}" for k in range(self.N)])

    def init_state(self, model, y, x0, P0):
        pass

    def command(self, model, t, y, u, du):
        i, tau = model.n_base, self.params["T_d"] / self.N
        last = y[i + self.N - 1]
        prev = y[i + self.N - 2]
        self._u = u
        return last, (prev - last) / tau

    def more_derivatives(self, model, t, y, dy, qs):
        i, tau = model.n_base, self.params["T_d"] / self.N
        u = getattr(model.inputs, "raw", model.inputs).u_and_slope(t)[0]
        for k in range(self.N):
            src = u if k == 0 else y[i + k - 1]
            dy[i + k] = (src - y[i + k]) / tau

    def atol(self, name):
        return 1e-5


class FrictionJointCompliance(Effect):
    name = "load_compliance"
    form = ("LINEAR rod-load spring k between piston (mass m_p = frac_p m) and load, damped "
            "by DRY friction in the joint F_d tanh(d'/1 mm/s) plus a little viscous c")

    def setup(self, model):
        model.layout.add("xL", "vL")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = x0

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i, m = self.params, model.n_base, model.p["m"]
        mp = p["frac_p"] * m
        d, dd = y[5] - y[i], y[6] - y[i + 1]
        Fs = p["k"] * d + p["c"] * dd + p["Fd"] * math.tanh(dd / p["vd"])
        dy[i] = y[i + 1]
        dy[i + 1] = (Fs + F) / (m - mp)
        return (Fp - Ff - Fs) / mp

    def sensor_outputs(self, model, Y, out):
        out["x"] = Y[model.n_base].copy()
        out["v"] = Y[model.n_base + 1].copy()

    def atol(self, name):
        return 1e-8 if name == "xL" else 1e-7


class CompliantMount(Effect):
    name = "structural_flexibility"
    form = ("cylinder body (mass m_b) on a compliant mount: F_mount = k_b d + k3 d^3 + c_b d'; "
            "the position sensor measures the stroke (rod relative to body); the load's weight acts "
            "at its absolute position, stroke + body deflection (an arm's gravity moment)")

    def setup(self, model):
        model.layout.add("xb", "vb")

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i, m = self.params, model.n_base, model.p["m"]
        xb, vb = y[i], y[i + 1]
        # the load sits where the stroke AND the body's deflection put it: a vane's arm hangs at
        # θ_stroke + θ_body, its weight moment W·sin of that (a cylinder's weight is constant).
        # Until session 45 the weight was taken at the stroke alone, as if the mount deflected
        # the arm's gravity with the housing
        if hasattr(model, "load_force"):     # the EHA's load is an external force input
            F = F - model.load_force(y[5]) + model.load_force(y[5] + xb)
        Fm = self.mount_force(xb, vb)
        ab = (-Fp + Ff - Fm) / p["m_b"]
        dy[i] = vb
        dy[i + 1] = ab
        return (Fp + F - Ff) / m - ab      # stroke acceleration = load - body

    def mount_force(self, xb, vb):
        p = self.params
        return p["k_b"] * xb + p.get("k3", 0.0) * xb ** 3 + p["c_b"] * vb

    def atol(self, name):
        return 1e-9


class LinearBumper(Effect):
    name = "end_stop"
    form = ("elastomer bumper at x_stop: LINEAR spring-damper F = k d + c d' for d = x - x_stop "
            "> 0 (pulling-free), soft")

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        d = y[5] - self.params["x_stop"]
        Fc = 0.0
        if d > 0.0:
            Fc = max(self.params["k"] * d + self.params["c"] * y[6], 0.0)
        return (Fp + F - Ff - Fc) / model.p["m"]


class LaminarSupplyLine(Effect):
    name = "supply_pressure_drop"
    form = ("long LAMINAR supply line, no accumulator: Q = (Ps - Pv)/R_s into the line "
            "volume V_l/beta (+ hose wall compliance C_w)")

    def setup(self, model):
        model.layout.add("Pv")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = self.params.get("Pv0", 1e7)

    def supply_at_valve(self, model, y, Ps):
        return y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        p, i = self.params, model.n_base
        Ps = model.inputs.at(t)[1]
        C = p["V_l"] / model.p["beta"] + p["C_w"]
        dy[i] = ((Ps - y[i]) / p["R_s"] - qs) / C

    def atol(self, name):
        return 10.0


class PressureSensorLag(Effect):
    name = "sensor_lag"
    form = ("slow pressure transducers: P1, P2 measured through a further first-order lag "
            "tau_p (on top of the 1 ms of every recording)")

    def setup(self, model):
        model.layout.add("P1s", "P2s")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = y[3]
        y[model.n_base + 1] = y[4]

    def more_derivatives(self, model, t, y, dy, qs):
        i, tau = model.n_base, self.params["tau_p"]
        dy[i] = (y[7] - y[i]) / tau
        dy[i + 1] = (y[8] - y[i + 1]) / tau

    def sensor_outputs(self, model, Y, out):
        out["P1"] = Y[model.n_base].copy()
        out["P2"] = Y[model.n_base + 1].copy()

    def atol(self, name):
        return 10.0


class RopePendulum(Effect):
    name = "payload_swing"
    form = ("payload m_p on a rope of length L hanging from the arm tip (radius r): the full "
            "nonlinear two-link Lagrangian (arm angle theta, rope angle phi from vertical), rope "
            "damping c_r; theta and its rate are measured on the arm")

    def setup(self, model):
        model.layout.add("phi", "phid")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = 0.0

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i = self.params, model.n_base
        mp, r, L, g = p["m_p"], p["r"], p["L"], 9.81
        th, thd, ph, phd = y[5], y[6], y[i], y[i + 1]
        c, s = math.cos(th - ph), math.sin(th - ph)
        # [J + mp r^2, mp r L c; mp r L c, mp L^2] [thdd, phdd] = rhs
        a11, a12, a22 = model.p["m"] + mp * r * r, mp * r * L * c, mp * L * L
        b1 = Fp + F - Ff - mp * r * L * s * phd * phd - mp * g * r * math.sin(th)
        b2 = mp * r * L * s * thd * thd - mp * g * L * math.sin(ph) - p["c_r"] * phd
        det = a11 * a22 - a12 * a12
        thdd = (b1 * a22 - a12 * b2) / det
        dy[i] = phd
        dy[i + 1] = (a11 * b2 - a12 * b1) / det
        return thdd

    def atol(self, name):
        return 1e-7


class TangentialSpringPayload(Effect):
    name = "payload_swing"
    form = ("flexible payload: a mass m_p at the arm tip (radius r) on a LINEAR tangential "
            "spring-damper k, c (a boom-tip mass, not a rope); its weight m_p g r sin(theta) on "
            "the arm")

    def setup(self, model):
        model.layout.add("q", "qd")

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i = self.params, model.n_base
        mp, r = p["m_p"], p["r"]
        Fs = p["k"] * y[i] + p["c"] * y[i + 1]          # spring force on the payload (-)
        thdd = (Fp + F - Ff - mp * 9.81 * r * math.sin(y[5]) + r * Fs) / model.p["m"]
        dy[i] = y[i + 1]
        dy[i + 1] = -Fs / mp - r * thdd
        return thdd

    def atol(self, name):
        return 1e-8


class _HangingPayload(Effect):
    """A fraction m_frac of the lifted load hangs on a rope under it (the rest stays rigid
    on the rod; the total weight W is unchanged, so the effect is the bounce alone). State s:
    the rope's stretch beyond its static one; tension T = m_frac W + rope(s, s'), clipped at
    0 (a rope cannot push). Load: (1 − m_frac) m ẍ = Fp − Ff + F + m_frac W − T; payload:
    m_frac m ÿ_p = T − m_frac W; s'' = ẍ − ÿ_p. Position and speed are measured on the rod."""
    name = "payload_swing"

    def setup(self, model):
        model.layout.add("s_rope", "sd_rope")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = y[model.n_base + 1] = 0.0

    def rope(self, model, s, sd, W_p):
        raise NotImplementedError

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i, m = self.params, model.n_base, model.p["m"]
        mp, W_p = p["m_frac"] * m, p["m_frac"] * model.p["W"]
        s, sd = y[i], y[i + 1]
        T = max(W_p + self.rope(model, s, sd, W_p), 0.0)
        a = (Fp - Ff + F + W_p - T) / (m - mp)
        dy[i] = sd
        dy[i + 1] = a - (T - W_p) / mp
        return a

    def _k_c(self, model):
        p = self.params
        mp = p["m_frac"] * model.p["m"]
        w = 2.0 * math.pi * p["f_hz"]
        return mp * w * w * self.stiffening(model), 2.0 * p["zeta"] * mp * w

    def stiffening(self, model) -> float:
        """The rope's stiffness over its nominal one (1: a rope of fixed length)."""
        return 1.0

    def atol(self, name):
        return 1e-8


class RopeBouncePayload(_HangingPayload):
    form = ("hook load (fraction m_frac of the lifted mass) on an elastic rope under the rod: "
            "LINEAR rope spring-damper at f_hz with damping ratio zeta, slack-capable")

    def rope(self, model, s, sd, W_p):
        k, c = self._k_c(model)
        return k * s + c * sd


class SheaveFrictionPayload(_HangingPayload):
    form = ("hook load on a multi-fall rope reeved over sheaves: rope spring at f_hz, damped by "
            "the sheaves' DRY friction, proportional to the tension (mu T tanh(s'/1 mm/s)), "
            "plus a little viscous zeta")

    def rope(self, model, s, sd, W_p):
        k, c = self._k_c(model)
        return k * s + c * sd + self.params["mu"] * (W_p + k * s) * math.tanh(sd / 1e-3)
