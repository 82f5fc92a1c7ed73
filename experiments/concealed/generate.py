"""Generate the project's own concealed-effect recordings (issue 6).

    python -m experiments.concealed.generate [--only CASE ...] [--jobs 2] [--list] [--readme]

For every case: perturb seed 004's identified parameters (seeded RNG, up to +-15 %), run the
bench (slow PI position controller + feed-forward + multi-sine dither, supply with ripple and
droop, sine + random external force) in closed loop on the truth model WITH the effect to get
the inputs u, Ps, Fext; then replay those recorded inputs open loop with the effect on (the
recording) and off (for effect_esr_percent), add sensor noise, write CSV + JSON sidecar.
Deterministic: same command, same files. Every run (and `--readme` alone) also rewrites
README.md (from README_HEAD / README_NOTES here and the sidecars) and each case's base.yaml
(machines/eha_testbench.yaml without the concealed effect, BASE_EDITS).
"""
from __future__ import annotations

import argparse
import bisect
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # allow `python experiments/concealed/generate.py`
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from experiments.concealed.truth.eha import (NOMINAL_BASE, PERTURBED, P_TAU, EHATruth,
                                             Inputs)
from experiments.concealed.truth.effects import make_effect

HERE = Path(__file__).resolve().parent
FS = 1000.0
DT = 1.0 / FS
DURATION = 20.0
PREROLL = 1.5
PD = 1e5
BENCH = {"Ps0": 1.0e7, "ripple_amp": 5.0e4, "ripple_freq": 25.0, "droop_gain": 3.0e8,
         "droop_tau": 0.02, "ctrl_Kp": 500.0, "ctrl_Ki": 250.0, "u_max": 60.0,
         "x_home": 0.07, "x_bounds": [-0.08, 0.25], "setpoint_range": [0.045, 0.195]}
SENSORS = {"P_sigma": 1.5e4, "P_quant": 1.0e3, "P_tau": P_TAU, "x_sigma": 2e-6,
           "x_quant": 5e-6, "v_sigma": 1e-3, "v_quant": 1e-4, "u_quant": 1e-3, "Ps_quant": 1e3,
           "F_quant": 1.0,
           "note": ("u, Ps, Fext are written exactly as applied to the truth (after "
                    "quantisation); noise is added to P1, P2 (after the 1 ms lag), x, v")}
ESR_DEF = ("100*var(y_on - y_off)/var(y_on), noise-free sensor signals, y_off = same truth "
           "model and parameters with the effect switched off, same recorded u, Ps, Fext")

# documented range of the effect size: max(effect ESR on dp, effect ESR on v) of every effect
# case, train AND validate, lies in this band [%] (tests/concealed checks it); null cases 0.
ESR_RANGE = (1.0, 15.0)

# case -> effect, seed, effect params (sizes tuned for an effect ESR of ~1-10 % on dp or v).
# Optional keys:
#   base_extra: known base properties of this bench added to the truth base (not perturbed) and
#               written into the case's base.yaml (external_leakage: valve centre leakage)
#   setpoint_max: operator's setpoint sequence clipped at this position [m] (end_stop: the
#               targets near the top of the range press lightly against the stop)
#   off_effect: model used as "effect off" for effect_esr_percent instead of the bare base
#               (end_stop: the cylinder keeps its head stop at the end of the stroke)
CASES = {
    "none_a": {"effect": "none", "seed": 101, "params": {}},
    "none_b": {"effect": "none", "seed": 102, "params": {}},
    "internal_leakage": {"effect": "internal_leakage", "seed": 103,
                         "params": {"K_t": 2.5e-8, "dp_t": 2.0e5}},
    # worn rod seals (about 1.4 L/min and 0.5 L/min at 45 bar) on a valve with a known centre
    # leakage of G_leak*(Ps - Pd) ~ 3 L/min at 100 bar (holds the chamber pressure level)
    "external_leakage": {"effect": "external_leakage", "seed": 104,
                         "params": {"K_e1": 1.1e-8, "K_e2": 4.0e-9, "dp_t": 1.0e5},
                         "base_extra": {"G_leak": 5.0e-12}},
    "coulomb_friction": {"effect": "coulomb_friction", "seed": 105,
                         "params": {"Fc_p": 380.0, "Fc_m": 480.0, "v_c": 2.0e-3}},
    "stribeck_friction": {"effect": "stribeck_friction", "seed": 106,
                          "params": {"Fs_p": 600.0, "Fs_m": 450.0, "vs_p": 6e-3,
                                     "vs_m": 4e-3}},
    "pressure_dependent_friction": {"effect": "pressure_dependent_friction", "seed": 117,
                                    "params": {"mu": 0.22, "eps2": 1e-3}},
    "entrained_air": {"effect": "entrained_air", "seed": 108,
                      "params": {"alpha0": 0.8, "P_sat": 1.5e7}},
    "valve_overlap": {"effect": "valve_overlap", "seed": 109,
                      "params": {"overlap": 1.5, "edge_radius": 0.6}},
    "valve_asymmetry": {"effect": "valve_asymmetry", "seed": 110,
                        "params": {"g_PA": 1.25, "g_BT": 1.15, "g_PB": 0.80, "g_AT": 0.85}},
    "input_delay": {"effect": "input_delay", "seed": 111, "params": {"T_d": 0.010}},
    "sensor_lag": {"effect": "sensor_lag", "seed": 112, "params": {"f_c": 5.0, "zeta": 0.7}},
    # stroke-limiter stop at 0.128 m, setpoints clipped 1 mm beyond it: three light contacts per
    # experiment; effect off = the cylinder head stop at the end of the stroke (x = 0.25 m)
    "end_stop": {"effect": "end_stop", "seed": 113,
                 "params": {"x_stop": 0.128, "k": 6.0e10, "lam": 15.0},
                 "setpoint_max": 0.129,
                 "off_effect": {"effect": "end_stop",
                                "params": {"x_stop": 0.25, "k": 6.0e10, "lam": 15.0}}},
    "load_compliance": {"effect": "load_compliance", "seed": 114,
                        "params": {"frac_p": 0.35, "k": 8.0e5, "k3": 1.6e11, "c": 700.0}},
    # clogged pressure filter (~10 bar drop at 6 L/min) + small 0.02 L accumulator + 0.2 L line
    "supply_pressure_drop": {"effect": "supply_pressure_drop", "seed": 115,
                             "params": {"K_s": 1.0e-7, "P0": 6.0e6, "Vg0": 2.0e-5, "n": 1.4,
                                        "V_l": 2.0e-4, "Pv0": 1.0e7}},
    # 6 m hoses, 6 mm bore: V_h = a L, I = rho L / a, R_l = 128 mu L / (pi d^4), R_t fittings
    # torque-motor hysteresis: a smooth loop of half-width 0.8 % of spool stroke, closing
    # over ~0.5 % of spool travel
    "valve_hysteresis": {"effect": "valve_hysteresis", "seed": 119,
                         "params": {"h": 0.8, "sigma": 6.0, "eps": 0.5}},
    "line_dynamics": {"effect": "line_dynamics", "seed": 116,
                      "params": {"V_h": 1.7e-4, "I": 1.85e8, "R_l": 7.6e9, "R_t": 1.2e12}},
}


# ------------------------------------------------------------------------------------------
def base_params(seed: int, overrides: dict):
    rng = np.random.default_rng([seed, 0])
    fac = {k: float(rng.uniform(0.85, 1.15)) for k in PERTURBED}
    p = dict(NOMINAL_BASE)
    for k, f in fac.items():
        p[k] = NOMINAL_BASE[k] * f
    p.update(overrides)
    return p, fac


def min_jerk(s):
    s = min(max(s, 0.0), 1.0)
    return s ** 3 * (10 - 15 * s + 6 * s * s), 30 * s * s * (1 - s) ** 2


class Excitation:
    """Setpoint, dither, supply ripple/noise and external force for one experiment."""

    def __init__(self, seed: int, kind: str, setpoint_max: float | None = None):
        rng = np.random.default_rng([seed, 1 if kind == "train" else 2])
        lo, hi = BENCH["setpoint_range"]
        # setpoint: sequence of minimum-jerk moves (fast, slow, small reversals) with holds
        segs, t, x = [], 0.0, BENCH["x_home"]
        while t < DURATION:
            kind_move = rng.choice(["big", "big", "slow", "small", "small"])
            if kind_move == "big":
                tgt = float(rng.uniform(lo, hi)) if abs(x - hi) > 0.05 else float(rng.uniform(lo, lo + 0.04))
                T = abs(tgt - x) / rng.uniform(0.08, 0.14) * 1.875
            elif kind_move == "slow":
                tgt = float(np.clip(x + rng.choice([-1, 1]) * rng.uniform(0.008, 0.025), lo, hi))
                T = abs(tgt - x) / rng.uniform(0.008, 0.02) * 1.875
            else:
                tgt = float(np.clip(x + rng.choice([-1, 1]) * rng.uniform(0.001, 0.006), lo, hi))
                T = rng.uniform(0.3, 0.8)
            T = max(T, 0.2)
            hold = float(rng.uniform(0.2, 0.8))
            segs.append((t, T, x, tgt))
            t += T + hold
            x = tgt
        if setpoint_max is not None:  # same random sequence, targets clipped at setpoint_max
            segs = [(t0, T, min(a, setpoint_max), min(b, setpoint_max)) for t0, T, a, b in segs]
        self.segs = segs
        self.seg_tl = [s[0] for s in segs]
        # dither multi-sine on u [%]
        nd = 7
        self.d_f = np.exp(rng.uniform(math.log(0.5), math.log(18.0), nd))
        self.d_a = rng.uniform(0.4, 1.0, nd) * 2.2 / math.sqrt(nd)
        self.d_ph = rng.uniform(0, 2 * math.pi, nd)
        # external force: amplitude-modulated sine + band-limited random
        self.f_F = float(rng.uniform(1.2, 2.0))
        self.F_amp = float(rng.uniform(1200, 1700))
        self.F_ph = float(rng.uniform(0, 2 * math.pi))
        self.F_mod_f = float(rng.uniform(0.03, 0.08))
        n = int((DURATION + PREROLL) * FS) + 1
        w = rng.standard_normal(n)
        a = math.exp(-2 * math.pi * 2.0 * DT)  # ~2 Hz first-order, applied twice
        for _ in range(2):
            y = np.empty(n)
            acc = 0.0
            for i in range(n):
                acc = a * acc + (1 - a) * w[i]
                y[i] = acc
            w = y
        self.F_rand = 250.0 * w / np.std(w)
        self._dl = [(float(a), 2 * math.pi * float(f), float(ph))
                    for a, f, ph in zip(self.d_a, self.d_f, self.d_ph)]
        self.F_randl = [float(a) for a in self.F_rand]
        self.Ps_ph = float(rng.uniform(0, 2 * math.pi))
        self.Ps_slow = (float(rng.uniform(0.05, 0.2)), float(rng.uniform(0, 2 * math.pi)))
        self.t_grid = -PREROLL + DT * np.arange(n)

    def setpoint(self, t):
        if t <= 0.0:
            return BENCH["x_home"], 0.0
        k = bisect.bisect_right(self.seg_tl, t) - 1
        t0, T, x0, x1 = self.segs[k]
        s, ds = min_jerk((t - t0) / T)
        return x0 + (x1 - x0) * s, (x1 - x0) * ds / T if (t - t0) < T else 0.0

    def dither(self, t):
        if t <= 0.0:
            return 0.0
        ramp = min(t / 0.5, 1.0)
        return ramp * sum(a * math.sin(w * t + ph) for a, w, ph in self._dl)

    def force(self, t):
        on = 0.5 * (1 - math.cos(math.pi * min(max((t + PREROLL) / 1.0, 0.0), 1.0)))
        k = min(max(int(round((t + PREROLL) * FS)), 0), len(self.F_rand) - 1)
        mod = 0.65 + 0.35 * math.sin(2 * math.pi * self.F_mod_f * max(t, 0.0))
        return on * (self.F_amp * mod * math.sin(2 * math.pi * self.f_F * t + self.F_ph)
                     + self.F_randl[k])

    def Ps_open(self, t):
        a, ph = self.Ps_slow
        return (BENCH["Ps0"] + BENCH["ripple_amp"] * math.sin(2 * math.pi * BENCH["ripple_freq"] * t
                                                               + self.Ps_ph)
                + 3.0e4 * math.sin(2 * math.pi * a * t + ph))


class LiveInputs:
    """Inputs object whose values the closed-loop wrapper sets before each rhs call."""
    u = du = Ps = F = 0.0

    def at(self, t):
        return self.u, self.Ps, self.F

    def u_and_slope(self, t):
        return self.u, 0.0


def closed_loop(model: EHATruth, exc: Excitation, y0):
    """Bench in closed loop (continuous PI + feed-forward + dither, supply droop state)."""
    from scipy.integrate import solve_ivp
    live = LiveInputs()
    model.inputs = live
    n = len(y0)
    Kq = NOMINAL_BASE["Kv"] * math.sqrt(BENCH["Ps0"] / 2 - PD) / 100.0 / NOMINAL_BASE["A"]
    B = BENCH

    # exogenous signals precomputed on the sample grid (linear interpolation in between)
    tg = exc.t_grid
    sp = [exc.setpoint(t) for t in tg]
    ext = Inputs(tg[0], DT, [a[0] for a in sp], [exc.Ps_open(t) for t in tg],
                 [exc.force(t) for t in tg])
    ffd = Inputs(tg[0], DT, [a[1] / Kq + exc.dither(t) for a, t in zip(sp, tg)],
                 [0.0] * len(tg), [0.0] * len(tg))

    def ctrl(t, y):
        r, Pso, F = ext.at(t)
        ff = ffd.at(t)[0]
        u = B["ctrl_Kp"] * (r - y[5]) + B["ctrl_Ki"] * y[n] + ff
        return min(max(u, -B["u_max"]), B["u_max"]), r, Pso, F

    def rhs(t, y):
        u, r, Pso, F = ctrl(t, y)
        live.u = u
        live.Ps = Pso - y[n + 1]
        live.F = F
        dy = model.rhs(t, y[:n])
        xv = y[1]
        qa, qb, qs = model.valve_flows(xv, live.Ps, y[3], y[4])
        zdot = r - y[5]
        # anti-windup: freeze the integrator when u saturates in the same direction
        uu = B["ctrl_Kp"] * (r - y[5]) + B["ctrl_Ki"] * y[n]
        if abs(uu) > B["u_max"] and zdot * uu > 0:
            zdot = 0.0
        dy.append(zdot)
        dy.append((B["droop_gain"] * max(qs, 0.0) - y[n + 1]) / B["droop_tau"])
        return dy

    Y0 = np.concatenate([y0, [0.0, 0.0]])
    atol = np.concatenate([model.default_atol(), [1e-6, 10.0]])
    sol = solve_ivp(rhs, (exc.t_grid[0], exc.t_grid[-1]), Y0, method="LSODA",
                    t_eval=exc.t_grid, rtol=1e-4, atol=atol, max_step=2e-3)
    if not sol.success:
        raise RuntimeError(f"closed loop failed: {sol.message}")
    u = np.empty(len(sol.t))
    Ps = np.empty(len(sol.t))
    F = np.empty(len(sol.t))
    for i, t in enumerate(sol.t):
        c = ctrl(t, sol.y[:, i])
        u[i] = c[0]
        Ps[i] = c[2] - sol.y[n + 1, i]
        F[i] = c[3]
    return u, Ps, F


def quant(a, q):
    return np.round(np.asarray(a) / q) * q


def esr(y, yhat):
    return float(100.0 * np.var(y - yhat) / np.var(y))


def run_experiment(case: str, kind: str, write: bool = True) -> dict:
    spec = CASES[case]
    t_start = time.time()
    eff_name = spec["effect"]
    effect = make_effect(eff_name, spec["params"])
    overrides = effect.base_overrides if effect is not None else {}
    p, fac = base_params(spec["seed"], overrides)
    p.update(spec.get("base_extra", {}))
    exc_seed = spec["seed"] * 10 + (1 if kind == "train" else 2)
    exc = Excitation(exc_seed, kind, spec.get("setpoint_max"))

    # 1) bench in closed loop on the truth with the effect -> applied inputs
    m_cl = EHATruth(p, make_effect(eff_name, spec["params"]))
    x0, P0 = BENCH["x_home"], 5.0e6
    u, Ps, F = closed_loop(m_cl, exc, m_cl.initial_state(x0, P0))
    u = quant(u, SENSORS["u_quant"])
    Ps = quant(Ps, SENSORS["Ps_quant"])
    F = quant(F, SENSORS["F_quant"])
    inputs = Inputs(exc.t_grid[0], DT, u, Ps, F)

    # 2) replay the recorded inputs, effect on (the recording) and off
    m_on = EHATruth(p, effect, inputs)
    sol_on = m_on.simulate(exc.t_grid, m_on.initial_state(x0, P0))
    checks = {"solver_status_effect_on": "ok" if sol_on.success else sol_on.message}
    y_on = m_on.measured(sol_on.y)
    i0 = int(round(PREROLL * FS))
    off_spec = spec.get("off_effect")
    if effect is not None:
        m_off = EHATruth(p, make_effect(off_spec["effect"], off_spec["params"])
                         if off_spec else None, inputs)
        sol_off = m_off.simulate(exc.t_grid, m_off.initial_state(x0, P0))
        checks["solver_status_effect_off"] = "ok" if sol_off.success else sol_off.message
        y_off = m_off.measured(sol_off.y)
    else:
        sol_off, y_off = None, None
        checks["solver_status_effect_off"] = "not run (effect none)"

    sl = slice(i0, None)
    on = {k: v[sl] for k, v in y_on.items()}
    on["dp"] = on["P1"] - on["P2"]
    if y_off is not None:
        off = {k: v[sl] for k, v in y_off.items()}
        off["dp"] = off["P1"] - off["P2"]
        eff_esr = {k: esr(on[k], off[k]) for k in ("dp", "v", "P1", "x")}
    else:
        eff_esr = {k: 0.0 for k in ("dp", "v", "P1", "x")}

    # 3) sensors
    rng = np.random.default_rng([spec["seed"], 3 if kind == "train" else 4])
    N = len(on["x"])
    P1m = quant(on["P1"] + SENSORS["P_sigma"] * rng.standard_normal(N), SENSORS["P_quant"])
    P2m = quant(on["P2"] + SENSORS["P_sigma"] * rng.standard_normal(N), SENSORS["P_quant"])
    xm = quant(on["x"] + SENSORS["x_sigma"] * rng.standard_normal(N), SENSORS["x_quant"])
    vm = quant(on["v"] + SENSORS["v_sigma"] * rng.standard_normal(N), SENSORS["v_quant"])
    noise_esr = {"dp": esr(on["dp"], P1m - P2m), "v": esr(on["v"], vm)}

    # 4) checks
    Yon = sol_on.y[:, sl]
    A = p["A"]
    xs = Yon[5]
    xb = BENCH["x_bounds"]
    Pmin = float(min(Yon[3].min(), Yon[4].min()))
    Pmax = float(max(Yon[3].max(), Yon[4].max()))
    checks.update({
        "all_finite": bool(np.all(np.isfinite(sol_on.y))),
        "x_min_m": float(xs.min()), "x_max_m": float(xs.max()),
        "x_inside_bounds": bool(xs.min() > xb[0] and xs.max() < xb[1]),
        "min_chamber_volumes_m3": [float((p["V10"] + A * xs).min()),
                                   float((p["V20"] - A * xs).min())],
        "P_min_bar": Pmin / 1e5, "P_max_bar": Pmax / 1e5,
        "Ps_min_bar": float(Ps[i0:].min() / 1e5),
        "pressures_between_tank_and_supply": bool(Pmin > PD and Pmax < Ps.max()),
        "solver_steps_effect_on": int(len(sol_on.t)),
        "rhs_evals_effect_on": int(sol_on.nfev),
    })
    if sol_off is not None:
        xo = sol_off.y[5, sl]
        checks["x_range_effect_off_m"] = [float(xo.min()), float(xo.max())]
        checks["x_inside_bounds_effect_off"] = bool(xo.min() > xb[0] and xo.max() < xb[1])
    if eff_name == "end_stop":
        xst = spec["params"]["x_stop"]
        checks["x_max_effect_off_beyond_stop_m"] = float(sol_off.y[5, sl].max() - xst)
        inside = np.concatenate([[False], xs > xst, [False]])
        starts = np.nonzero(~inside[:-1] & inside[1:])[0]
        ends = np.nonzero(inside[:-1] & ~inside[1:])[0]
        checks["stop_contacts"] = int(len(starts))
        checks["stop_contact_time_s"] = float(np.sum(xs > xst) * DT)
        checks["stop_max_penetration_m"] = float(max(xs.max() - xst, 0.0))
        checks["stop_contact_intervals_s"] = [[round(float(exc.t_grid[i0 + a]), 3),
                                               round(float(exc.t_grid[i0 + b - 1]), 3)]
                                              for a, b in zip(starts, ends)][:50]

    # a few noise-free samples + the state at t = 0 so the case can be re-simulated
    ref_idx = list(range(0, 2001, 100))
    sidecar = {
        "effect": eff_name,
        "case": case,
        "seed": spec["seed"],
        "experiment": kind,
        "csv": f"{kind}.csv",
        "generator": "experiments/concealed (independent truth simulator, truth/eha.py + truth/effects.py)",
        "sampling_rate_hz": FS,
        "n_samples": N,
        "columns": ["t", "u", "Ps", "Fext", "P1", "P2", "x", "v"],
        "units": {"t": "s", "u": "%", "Ps": "Pa", "Fext": "N", "P1": "Pa", "P2": "Pa",
                  "x": "m", "v": "m/s"},
        "conventions": {
            "pressures": "absolute [Pa]; tank pressure Pd = 1 bar",
            "u": "valve command in %, first-order hold; u>0 opens P->A, B->T",
            "x": "piston position [m], V1 = V10 + A x, V2 = V20 - A x",
            "v": "velocity dx/dt [m/s]",
            "Fext": "external force [N], positive in +x",
            "sensors": "P1/P2 at the cylinder ports (1 ms lag); x and v on the load side "
                       "(identical to the piston unless the effect is load_compliance)",
            "time": f"t = 0 after a {PREROLL} s settling pre-roll (load ramped on, no excitation)",
        },
        "true_base_params": p,
        "nominal_base_params": NOMINAL_BASE,
        "perturbation_factors": fac,
        "base_overrides": overrides,
        "base_extra": spec.get("base_extra", {}),
        "effect_form": effect.form if effect is not None else "",
        "effect_params": spec["params"],
        "sensor_model": SENSORS,
        "bench": BENCH,
        "excitation": {
            "kind": kind, "seed": exc_seed, "duration_s": DURATION, "preroll_s": PREROLL,
            "setpoint": "minimum-jerk moves (fast, slow, small reversals) with random holds",
            "n_moves": len(exc.segs),
            "setpoint_max_m": spec.get("setpoint_max"),
            "dither_freqs_hz": [float(f) for f in exc.d_f],
            "fext_sine_hz": exc.f_F, "fext_amp_N": exc.F_amp,
            "controller": "continuous PI on x + velocity feed-forward + multi-sine dither, "
                          "saturated at +-u_max, anti-windup",
        },
        "effect_esr_percent": eff_esr,
        "effect_esr_definition": ESR_DEF,
        "effect_off_model": (f"truth base + {off_spec['effect']} {off_spec['params']} "
                             "(the bench without the concealed effect)" if off_spec else
                             "truth base (effect switched off)" if effect is not None else ""),
        "effect_esr_range_percent": list(ESR_RANGE) if effect is not None else [0.0, 0.0],
        "base_machine": "base.yaml",
        "noise_esr_percent": noise_esr,
        "checks": checks,
        "solver": {"method": "LSODA", "rtol": 1e-7, "max_step": 2e-3},
        "initial_state_t0": {n_: float(sol_on.y[j, i0]) for j, n_ in
                             enumerate(m_on.layout.names)},
        "noise_free_reference": {
            "t": [round(float(exc.t_grid[i0 + i]), 6) for i in ref_idx],
            **{k: [float(on[k][i]) for i in ref_idx] for k in ("P1", "P2", "x", "v")},
        },
    }
    # (the runtime is reported on stdout, not stored: same command, byte-identical files)
    runtime = round(time.time() - t_start, 2)
    if write:
        out = HERE / case
        out.mkdir(parents=True, exist_ok=True)
        tt = exc.t_grid[i0:]
        with open(out / f"{kind}.csv.tmp", "w") as f:
            f.write("t[s],u[%],Ps[Pa],Fext[N],P1[Pa],P2[Pa],x[m],v[m/s]\n")
            for i in range(N):
                f.write(f"{tt[i]:.3f},{u[i0 + i]:.3f},{Ps[i0 + i]:.0f},{F[i0 + i]:.0f},"
                        f"{P1m[i]:.0f},{P2m[i]:.0f},{xm[i]:.6f},{vm[i]:.4f}\n")
        os.replace(out / f"{kind}.csv.tmp", out / f"{kind}.csv")
        with open(out / f"{kind}.json", "w") as f:
            json.dump(sidecar, f, indent=1)
            f.write("\n")
    return {**sidecar, "runtime_s": runtime}


def _job(args):
    case, kind = args
    s = run_experiment(case, kind)
    return case, kind, s["effect_esr_percent"], s["noise_esr_percent"], s["checks"], s["runtime_s"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", action="append", help="case name (repeatable)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--readme", action="store_true", help="only rewrite README.md")
    a = ap.parse_args(argv)
    if a.readme:
        write_bases()
        write_readme()
        return 0
    if a.list:
        for c, s in CASES.items():
            print(c, s["effect"], s["params"])
        return 0
    cases = a.only or list(CASES)
    for c in cases:
        if c not in CASES:
            ap.error(f"unknown case {c!r}; choose from {', '.join(CASES)}")
    jobs = [(c, k) for c in cases for k in ("train", "validate")]
    t0 = time.time()
    if a.jobs > 1:
        from multiprocessing import Pool
        with Pool(a.jobs) as pool:
            results = pool.imap_unordered(_job, jobs)
            for r in results:
                _report(r)
    else:
        for j in jobs:
            _report(_job(j))
    write_bases()
    write_readme()
    print(f"done in {time.time() - t0:.1f} s")
    return 0


README_HEAD = """# Concealed-effect recordings generated by the project (issue 6)

<!-- generated by `python -m experiments.concealed.generate --readme` from generate.py
     (README_HEAD, README_NOTES, the sidecars); edit those, not this file -->

The project's own demonstration data for `hydro diagnose`: recordings of seed 004's
electro-hydraulic actuator test bench (the bench of `machines/eha_testbench.yaml`) produced by
an INDEPENDENT truth simulator (`truth/eha.py`, `truth/effects.py`: seed 004's eqs. 1-13
written by hand with numpy/scipy, no hydrocli builder or components), each with one concealed
effect whose FORM differs from the obvious diagnosis candidate, plus two null cases.

* Layout: `<case>/train.csv`, `<case>/validate.csv` (20 s, 1 kHz, header
  `t[s],u[%],Ps[Pa],Fext[N],P1[Pa],P2[Pa],x[m],v[m/s]` exactly like `../shared/recordings`),
  `<case>/train.json`, `<case>/validate.json` sidecars (keys as in the shared sidecars:
  `effect`, `seed`, `true_base_params`, `effect_params`, `effect_form`, `sensor_model`,
  `effect_esr_percent`, `noise_esr_percent`, `checks`, plus `initial_state_t0` and
  `noise_free_reference` so a case can be re-simulated and checked), and `<case>/base.yaml`,
  the machine file a diagnosis starts from (see below).
* Base parameters: seed 004's identified values perturbed by a seeded factor in [0.85, 1.15]
  (one draw per case, the same for train and validate), so a diagnosis must re-identify them.
  For `internal_leakage`, `coulomb_friction` and `stribeck_friction` the truth base has that
  term ZEROED (`base_overrides`: c_il, kc, ks = 0) and the effect restores it in another form.
* Bench: slow continuous PI position controller (Kp 500 %/m, Ki 250 %/(m s)) with velocity
  feed-forward and a multi-sine dither (0.5-18 Hz), setpoint = minimum-jerk moves (fast
  excursions, slow moves, small reversals) with holds; supply 100 bar with 25 Hz ripple, slow
  variation and flow droop; Fext = amplitude-modulated 1.2-2 Hz sine (1.2-1.7 kN) + 2 Hz
  band-limited random (250 N rms). The loop runs on the truth WITH the effect; the recorded
  inputs are then replayed open loop (effect on = the recording, effect off = reference for
  `effect_esr_percent`). Train and validate use different excitation seeds.
* Inputs in the CSV are exactly what drove the truth (u quantised 0.001 %, Ps 0.01 bar,
  Fext 1 N; first-order hold). Sensors: P1/P2 1 ms first-order lag (part of every case, not
  the effect), sigma 0.15 bar, 0.01 bar quantisation; x sigma 2 um + 5 um quantisation;
  v sigma 1 mm/s.
* Solver: `solve_ivp(LSODA, rtol=1e-7)`, max step 2 ms; checked against rtol=1e-10 in
  `tests/concealed/test_truth_simulator.py`.
* effect ESR = 100 var(y_on - y_off)/var(y_on), noise-free, same recorded inputs; noise ESR =
  100 var(y_meas - y_on)/var(y_on). Documented range (checked by `pytest tests/concealed`):
  for every effect case max(effect ESR dp, effect ESR v) is within {lo:g}-{hi:g} % in BOTH
  train and validate (sizes were tuned for about 1-10 %); null cases 0.

## Base machine of each case (`<case>/base.yaml`)

`base.yaml` is the machine `hydro diagnose` should start from: a standalone copy of
`machines/eha_testbench.yaml` (written by the generator; no `include:`, so a diagnosis can
augment it in place) WITHOUT the concealed effect, with everything else the truth base has:

| case | changes against `machines/eha_testbench.yaml` |
|---|---|
{base_rows}

All other cases use the standard machine unchanged: it already has the other effects off
(valve overlaps 0 and not free, `Kv_neg_ratio` 1, no entrained air, no end stops `k_stop` 0,
friction `mu_p` 0, no delay, lines, load compliance, supply restriction or extra sensor lag).
Check: `hydro check experiments/concealed/<case>/base.yaml`.

## Cases

Regenerate (deterministic): `python -m experiments.concealed.generate --jobs 2`
(some cases: `--only CASE --only CASE ...`; list: `--list`; README and base.yaml only:
`--readme`). Tests: `pytest tests/concealed`.

| case | effect | form of the truth | effect params | effect ESR dp / v [%] train | effect ESR dp / v [%] validate | noise ESR dp / v [%] train |
|---|---|---|---|---|---|---|
"""

README_NOTES = """
## Notes on the effect sizes (physical reading of the parameters)

* `internal_leakage`: K_t = 2.5e-8 m^3/s/Pa^0.5 passes 1.5 L/min at 10 bar across the piston
  (seed 004's laminar c_il passes 1.3 L/min at 10 bar), laminar below dp_t = 2 bar.
* `external_leakage`: badly worn rod seals, K_e1 = 1.1e-8 and K_e2 = 4e-9 m^3/s/Pa^0.5, i.e.
  about 1.4 and 0.5 L/min at 45 bar to the drain. The truth valve of this case has a known
  laminar clearance leakage G_leak = 5e-12 m^3/s/Pa per metering edge (centre leakage
  G_leak (Ps - Pd) = 3 L/min at 100 bar, about 6 % of rated flow; in `base.yaml` as the
  valve's `G_leak`, fixed): without it the seal leaks would drain the chambers to tank pressure
  during holds; with it the pressure level sags by 10-15 bar and the effect shows in dp, not
  only in the P1 level.
* `valve_asymmetry`: metering-edge gains 1.25 / 1.15 (P->A, B->T) and 0.80 / 0.85
  (P->B, A->T): series gain +20 % for x_v > 0 and -18 % for x_v < 0 (a worn / unmatched spool);
  the candidate `Kv_neg_ratio` can only scale two edges together.
* `supply_pressure_drop`: a clogged pressure filter / thin supply line, K_s = 1e-7
  m^3/s/Pa^0.5 (10 bar drop at 6 L/min), with a small accumulator (0.02 L gas at 60 bar
  precharge) and 0.2 L of line oil between the restriction and the valve P port.
* `line_dynamics`: 6 m hoses of 6 mm bore between valve and cylinder: V_h = a L = 1.7e-4 m^3,
  I = rho L / a = 1.85e8 kg/m^4, R_l = 128 mu L / (pi d^4) = 7.6e9 Pa s/m^3 (mu = 0.04 Pa s),
  R_t = 1.2e12 Pa s^2/m^6 for fittings.
* `end_stop`: a stroke-limiter stop at x = 0.128 m with a stiff Hunt-Crossley contact
  (k = 6e10 N/m^1.5, penetration < 0.1 mm); the operator's setpoints are clipped at 0.129 m,
  so the piston presses lightly (1 mm of setpoint beyond the stop) against it three times per
  experiment
  (`checks.stop_contacts`, `checks.stop_contact_intervals_s`). For `effect_esr_percent` the
  effect-off model keeps the cylinder-head stop at the end of the stroke (x = 0.25 m, same
  contact law; `effect_off_model` in the sidecar): without any stop the replayed command would
  drive the piston out of the stroke.
* `sensor_lag`: only v is affected (second-order 5 Hz sensor, zeta 0.7); its effect ESR is on
  v alone (train 7.7 %, validate 3.3 %: the validate experiment has less fast motion).
* The other sizes are as handed over: valve overlap 1.5 % with 0.6 % edge rounding, 10 ms
  command delay, Coulomb 380/480 N, Stribeck 600/450 N, mu = 0.22, free-air volume fraction
  alpha0 = 0.8 at 1 bar (isothermal and dissolving up to 150 bar: about 1.1 % at 50 bar, the
  working level; an isentropic candidate needs about 17 % at 1 bar for the same stiffness at
  50 bar), load-side spring 8e5 N/m with cubic hardening.
"""

# case -> list of (line pattern key, replacement YAML value, comment) edits of the standard
# machine; keys are the parameter names of machines/eha_testbench.yaml (unique in that file)
BASE_EDITS = {
    "internal_leakage": [("c_il", "{value: 0.0, free: false}",
                          "concealed case: no internal leakage in the base")],
    "external_leakage": [("c_el", "{value: 0.0, free: false}",
                          "concealed case: no external leakage in the base"),
                         ("+valve.G_leak", "5.0e-12",
                          "known valve centre leakage of this bench (per edge)")],
    "coulomb_friction": [("kc_p", "{value: 0.0, free: false}",
                          "concealed case: no Coulomb friction in the base"),
                         ("kc_m", "{value: 0.0, free: false}",
                          "concealed case: no Coulomb friction in the base")],
    "stribeck_friction": [("ks_p", "{value: 0.0, free: false}",
                           "concealed case: no Stribeck friction in the base"),
                          ("ks_m", "{value: 0.0, free: false}",
                           "concealed case: no Stribeck friction in the base"),
                          ("vs_p", "{value: 3.41e-3, free: false}",
                           "fixed: not identifiable without a Stribeck term"),
                          ("vs_m", "{value: 1.96e-3, free: false}",
                           "fixed: not identifiable without a Stribeck term")],
}
STANDARD_MACHINE = HERE.parents[1] / "machines" / "eha_testbench.yaml"


def base_machine_text(case: str) -> str:
    """The standard machine with the case's concealed effect removed (see BASE_EDITS)."""
    import re
    lines = STANDARD_MACHINE.read_text().splitlines()
    for key, value, comment in BASE_EDITS.get(case, []):
        if key.startswith("+"):  # add a parameter to a component, after its last line
            comp, par = key[1:].split(".")
            i0 = next(i for i, ln in enumerate(lines) if re.match(rf"^  {comp}:\s*$", ln))
            i = i0 + 1
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                i += 1
            while not lines[i - 1].strip():
                i -= 1
            lines.insert(i, f"    {par}: {value}   # {comment}")
            continue
        hits = [i for i, ln in enumerate(lines) if re.match(rf"^\s+{key}:", ln)]
        if len(hits) != 1:
            raise RuntimeError(f"base.yaml of {case}: '{key}' found {len(hits)} times")
        i = hits[0]
        indent = lines[i][:len(lines[i]) - len(lines[i].lstrip())]
        lines[i] = f"{indent}{key}: {value}   # {comment}"
    what = ("; ".join(f"{k.lstrip('+')}: {v}" for k, v, _ in BASE_EDITS[case])
            if case in BASE_EDITS else "unchanged")
    head = [f"# Base machine for `hydro diagnose` on experiments/concealed/{case}: "
            "machines/eha_testbench.yaml",
            f"# WITHOUT the concealed effect ({what}).",
            "# Written by `python -m experiments.concealed.generate --readme`; do not edit.",
            ""]
    return "\n".join(head + lines) + "\n"


def write_bases():
    for case in CASES:
        d = HERE / case
        if d.is_dir():
            (d / "base.yaml").write_text(base_machine_text(case))


def _md(text: str) -> str:
    return text.replace("|", "\\|")


def write_readme():
    from experiments.concealed.truth.effects import EFFECTS
    rows = []
    for case, spec in CASES.items():
        try:
            tr = json.loads((HERE / case / "train.json").read_text())
            va = json.loads((HERE / case / "validate.json").read_text())
        except FileNotFoundError:
            continue
        e, ev, n = tr["effect_esr_percent"], va["effect_esr_percent"], tr["noise_esr_percent"]
        form = EFFECTS[spec["effect"]].form if spec["effect"] != "none" else "base only"
        par = ", ".join(f"{k}={v:g}" for k, v in spec["params"].items())
        if spec.get("base_extra"):
            par += " (base: " + ", ".join(f"{k}={v:g}" for k, v in spec["base_extra"].items()) + ")"
        rows.append(f"| `{case}` | `{spec['effect']}` | {_md(form)} | {_md(par)} | "
                    f"{e['dp']:.2f} / {e['v']:.2f} | {ev['dp']:.2f} / {ev['v']:.2f} | "
                    f"{n['dp']:.3f} / {n['v']:.3f} |")
    base_rows = "\n".join(
        f"| `{c}` | " + "; ".join(f"`{k.lstrip('+')}: {_md(v)}`" for k, v, _ in ed) + " |"
        for c, ed in BASE_EDITS.items())
    head = (README_HEAD.replace("{lo:g}", f"{ESR_RANGE[0]:g}").replace("{hi:g}", f"{ESR_RANGE[1]:g}")
            .replace("{base_rows}", base_rows))
    (HERE / "README.md").write_text(head + "\n".join(rows) + "\n" + README_NOTES)


def _report(r):
    case, kind, e, n, ch, rt = r
    print(f"{case:28s} {kind:8s} effESR dp={e['dp']:6.2f} v={e['v']:6.2f} P1={e['P1']:6.2f} "
          f"x={e['x']:6.2f} | noise dp={n['dp']:.3f} v={n['v']:.3f} | x=[{ch['x_min_m']:.3f},"
          f"{ch['x_max_m']:.3f}] P=[{ch['P_min_bar']:.1f},{ch['P_max_bar']:.1f}] bar "
          f"{ch['solver_status_effect_on']} {rt:.1f}s", flush=True)


if __name__ == "__main__":
    sys.exit(main())
