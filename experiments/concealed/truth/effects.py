"""Switchable concealed effects for the truth simulator (truth/eha.py).

Each effect is written in a form that deliberately DIFFERS from the obvious candidate model
a diagnosis would try (see FORM strings).  "Effect off" is the same model with effect=None
and the same base parameters (for internal_leakage / coulomb_friction / stribeck_friction the
truth base has the corresponding term zeroed, and the effect restores it in a different form).
"""
from __future__ import annotations

import math

from .eha import flow_law


class Effect:
    name = "none"
    form = ""
    delay = 0.0
    custom_valve = False
    base_overrides: dict = {}

    def __init__(self, **params):
        self.params = dict(params)

    # hooks (defaults = base behaviour) ------------------------------------------------------
    def setup(self, model):
        pass

    def init_state(self, model, y, x0, P0):
        pass

    def spool_opening(self, model, xv):
        return xv

    def supply_at_valve(self, model, y, Ps):
        return Ps

    def port_pressures(self, model, y):
        return y[3], y[4]

    def chamber_inflows(self, model, y, qa, qb, dy):
        return qa, qb

    def leakages(self, model, P1, P2):
        return 0.0, 0.0, 0.0

    def bulk_modulus(self, model, P):
        return model.p["beta"]

    def extra_friction(self, model, v, P1, P2):
        return 0.0

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        return (Fp + F - Ff) / model.p["m"]

    def more_derivatives(self, model, t, y, dy, qs):
        pass

    def sensor_outputs(self, model, Y, out):
        pass

    def atol(self, name):
        return 1e-8


class InternalLeakage(Effect):
    name = "internal_leakage"
    form = ("truth base has NO laminar leak (c_il = 0); the cross-piston leak is a worn-seal "
            "ORIFICE (turbulent): q = K_t * dp / (dp^2 + dp_t^2)^(1/4), dp = P1 - P2 "
            "(not laminar c_il * dp)")
    base_overrides = {"c_il": 0.0}

    def leakages(self, model, P1, P2):
        return self.params["K_t"] * flow_law(P1 - P2, self.params["dp_t"]), 0.0, 0.0


class ExternalLeakage(Effect):
    name = "external_leakage"
    form = ("rod-seal leaks to drain through ORIFICES with unequal coefficients: "
            "q_ei = K_ei * f(P_i - Pd), f = turbulent law with laminar transition at dp_t "
            "(not laminar c_el * P)")

    def leakages(self, model, P1, P2):
        Pd, d = model.p["Pd"], self.params["dp_t"]
        return (0.0, self.params["K_e1"] * flow_law(P1 - Pd, d),
                self.params["K_e2"] * flow_law(P2 - Pd, d))


class CoulombFriction(Effect):
    name = "coulomb_friction"
    form = ("truth base has NO Coulomb term (kc_p = kc_m = 0); the effect restores one with "
            "ARCTAN smoothing: F = Fc_+/- * (2/pi) * atan(v / v_c)")
    base_overrides = {"kc_p": 0.0, "kc_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        Fc = self.params["Fc_p"] if v >= 0.0 else self.params["Fc_m"]
        return Fc * (2.0 / math.pi) * math.atan(v / self.params["v_c"])


class StribeckFriction(Effect):
    name = "stribeck_friction"
    form = ("truth base has NO Stribeck term (ks_p = ks_m = 0); the effect adds a GAUSSIAN "
            "Stribeck law F = Fs_+/- * tanh(v/eps) * exp(-(v/vs_+/-)^2) (not exp(-|v|/vs))")
    base_overrides = {"ks_p": 0.0, "ks_m": 0.0}

    def extra_friction(self, model, v, P1, P2):
        p = self.params
        Fs, vs = (p["Fs_p"], p["vs_p"]) if v >= 0.0 else (p["Fs_m"], p["vs_m"])
        return Fs * math.tanh(v / model.p["eps"]) * math.exp(-(v / vs) ** 2)


class PressureDependentFriction(Effect):
    name = "pressure_dependent_friction"
    form = ("seal friction proportional to the pressure DIFFERENCE across the piston seal: "
            "F = mu * A * |P1 - P2| * tanh(v / eps2) (not to P1 + P2)")

    def extra_friction(self, model, v, P1, P2):
        return (self.params["mu"] * model.p["A"] * abs(P1 - P2)
                * math.tanh(v / self.params["eps2"]))


class EntrainedAir(Effect):
    name = "entrained_air"
    form = ("free air, ISOTHERMAL (n = 1), partly dissolving by Henry's law up to P_sat: "
            "alpha(P) = alpha0 * (P0/P) * (1 - (P - P0)/(P_sat - P0)), "
            "1/beta_eff = (1 - alpha)/beta + alpha/P (not the isentropic law)")

    def bulk_modulus(self, model, P):
        p = self.params
        P0, Ps = 1e5, p["P_sat"]
        P = max(P, P0)
        alpha = p["alpha0"] * (P0 / P) * max(0.0, 1.0 - (P - P0) / (Ps - P0))
        return 1.0 / ((1.0 - alpha) / model.p["beta"] + alpha / P)


def _rounded_deadband(x, ov, r):
    return (0.5 * ((x - ov) + math.sqrt((x - ov) ** 2 + r * r))
            - 0.5 * ((-x - ov) + math.sqrt((x + ov) ** 2 + r * r)))


class ValveOverlap(Effect):
    name = "valve_overlap"
    form = ("spool overlap with ROUNDED edges: effective opening "
            "x_e = 0.5*((x-o)+sqrt((x-o)^2+r^2)) - 0.5*((-x-o)+sqrt((x+o)^2+r^2)) [%]")

    def spool_opening(self, model, xv):
        return _rounded_deadband(xv, self.params["overlap"], self.params["edge_radius"])


class ValveAsymmetry(Effect):
    name = "valve_asymmetry"
    form = ("four unmatched metering edges: Kv scaled by g_PA, g_BT (x_v > 0) and "
            "g_PB, g_AT (x_v < 0)")
    custom_valve = True

    def valve_flows(self, model, xv, Ps, y):
        p, g = model.p, self.params
        P1, P2 = y[3], y[4]
        Kv, Pd, dl = p["Kv"], p["Pd"], p["dp_lam"]
        if xv >= 0.0:
            a = Kv * xv / 100.0
            qa = g["g_PA"] * a * flow_law(Ps - P1, dl)
            qb = -g["g_BT"] * a * flow_law(P2 - Pd, dl)
            return qa, qb, qa
        a = -Kv * xv / 100.0
        qa = -g["g_AT"] * a * flow_law(P1 - Pd, dl)
        qb = g["g_PB"] * a * flow_law(Ps - P2, dl)
        return qa, qb, qb


class InputDelay(Effect):
    name = "input_delay"
    form = "pure transport delay of the valve command: u_valve(t) = u(t - T_d)"

    def __init__(self, **params):
        super().__init__(**params)
        self.delay = float(params["T_d"])


class SensorLag(Effect):
    name = "sensor_lag"
    form = ("velocity sensor behind a SECOND-ORDER low-pass (f_c, zeta) instead of an ideal "
            "or first-order one: v_m'' = w^2 (v - v_m) - 2 zeta w v_m'")

    def setup(self, model):
        model.layout.add("vm", "vmd")

    def more_derivatives(self, model, t, y, dy, qs):
        i = model.n_base
        w = 2.0 * math.pi * self.params["f_c"]
        dy[i] = y[i + 1]
        dy[i + 1] = w * w * (y[6] - y[i]) - 2.0 * self.params["zeta"] * w * y[i + 1]

    def sensor_outputs(self, model, Y, out):
        out["v"] = Y[model.n_base].copy()

    def atol(self, name):
        return 1e-7 if name == "vm" else 1e-4


class EndStop(Effect):
    name = "end_stop"
    form = ("hard stop at x_stop with a Hunt-Crossley contact: F = k d^1.5 (1 + lam * d'), "
            "d = max(0, x - x_stop) (not a linear spring-damper)")

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        d = y[5] - self.params["x_stop"]
        Fc = 0.0
        if d > 0.0:
            Fc = self.params["k"] * d ** 1.5 * (1.0 + self.params["lam"] * y[6])
            Fc = max(Fc, 0.0)
        return (Fp + F - Ff - Fc) / model.p["m"]


class LoadCompliance(Effect):
    name = "load_compliance"
    form = ("rod-load connection is a spring-damper with CUBIC hardening between piston mass "
            "m_p = frac_p*m and load mass m_L = (1-frac_p)*m; F = k d + k3 d^3 + c d'; Fext acts "
            "on the load, friction on the piston; x and v measured on the LOAD side")

    def setup(self, model):
        model.layout.add("xL", "vL")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = x0

    def _spring(self, model, y):
        i = model.n_base
        d = y[5] - y[i]
        dd = y[6] - y[i + 1]
        p = self.params
        return p["k"] * d + p["k3"] * d ** 3 + p["c"] * dd

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        m = model.p["m"]
        mp = self.params["frac_p"] * m
        mL = m - mp
        Fs = self._spring(model, y)
        i = model.n_base
        dy[i] = y[i + 1]
        dy[i + 1] = (Fs + F) / mL
        return (Fp - Ff - Fs) / mp

    def sensor_outputs(self, model, Y, out):
        out["x"] = Y[model.n_base].copy()
        out["v"] = Y[model.n_base + 1].copy()

    def atol(self, name):
        return 1e-8 if name == "xL" else 1e-7


class SupplyPressureDrop(Effect):
    name = "supply_pressure_drop"
    form = ("recorded Ps is at the pump; the valve P port sits behind a TURBULENT supply-line "
            "restriction Q = K_s f(Ps - Pv) and a gas accumulator (polytropic n, precharge P0, "
            "gas volume Vg0) plus line oil volume V_l: C(Pv) = V_l/beta + Vg0 P0^(1/n)/(n Pv^(1+1/n))")

    def setup(self, model):
        model.layout.add("Pv")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = self.params.get("Pv0", 1e7)

    def supply_at_valve(self, model, y, Ps):
        return y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        p = self.params
        i = model.n_base
        Pv = y[i]
        _, Ps, _ = model.inputs.at(t)
        Ql = p["K_s"] * flow_law(Ps - Pv, 5e4)
        C = p["V_l"] / model.p["beta"]
        if Pv > p["P0"]:
            C += p["Vg0"] * p["P0"] ** (1.0 / p["n"]) / (p["n"] * Pv ** (1.0 + 1.0 / p["n"]))
        dy[i] = (Ql - qs) / C

    def atol(self, name):
        return 10.0


class ValveHysteresis(Effect):
    name = "valve_hysteresis"
    form = ("magnetic hysteresis of the torque motor as a SMOOTH Dahl loop on the spool: metering "
            "opening x_e = x_v - z, dz/dt = sigma * dx_v/dt * (1 - (z/h) tanh((dx_v/dt)/eps)) "
            "(not a sharp play/backlash)")
    custom_valve = True

    def setup(self, model):
        model.layout.add("zh")

    def valve_flows(self, model, xv, Ps, y):
        return model.valve_flows(xv - y[model.n_base], Ps, y[3], y[4])

    def more_derivatives(self, model, t, y, dy, qs):
        p = self.params
        i = model.n_base
        rate = y[2]                                   # spool velocity [%/s]
        dy[i] = p["sigma"] * rate * (1.0 - (y[i] / p["h"]) * math.tanh(rate / p["eps"]))

    def atol(self, name):
        return 1e-6 if name == "zh" else 1e-8


class LineDynamics(Effect):
    name = "line_dynamics"
    form = ("hoses A and B between valve and cylinder: valve-side oil volume V_h (node "
            "pressure) + fluid inertance I = rho L / a with laminar R_l and turbulent R_t|q|q "
            "resistance (one lumped T-section per hose)")

    def setup(self, model):
        model.layout.add("PvA", "PvB", "qLA", "qLB")

    def init_state(self, model, y, x0, P0):
        i = model.n_base
        y[i] = y[i + 1] = P0

    def port_pressures(self, model, y):
        i = model.n_base
        return y[i], y[i + 1]

    def chamber_inflows(self, model, y, qa, qb, dy):
        i = model.n_base
        p = self.params
        PvA, PvB, qA, qB = y[i], y[i + 1], y[i + 2], y[i + 3]
        beta = model.p["beta"]
        dy[i] = beta * (qa - qA) / p["V_h"]
        dy[i + 1] = beta * (qb - qB) / p["V_h"]
        dy[i + 2] = (PvA - y[3] - p["R_l"] * qA - p["R_t"] * abs(qA) * qA) / p["I"]
        dy[i + 3] = (PvB - y[4] - p["R_l"] * qB - p["R_t"] * abs(qB) * qB) / p["I"]
        return qA, qB

    def atol(self, name):
        return 10.0 if name.startswith("Pv") else 1e-9


EFFECTS = {c.name: c for c in [
    InternalLeakage, ExternalLeakage, CoulombFriction, StribeckFriction,
    PressureDependentFriction, EntrainedAir, ValveOverlap, ValveAsymmetry, InputDelay,
    SensorLag, EndStop, LoadCompliance, SupplyPressureDrop, LineDynamics, ValveHysteresis]}


def make_effect(name: str, params: dict):
    if name == "none":
        return None
    return EFFECTS[name](**params)
