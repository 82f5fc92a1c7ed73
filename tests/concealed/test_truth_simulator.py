"""The independent truth simulator (experiments/concealed/truth) against closed forms, and the
generated concealed-effect cases against their own sidecars."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from experiments.concealed.truth.eha import NOMINAL_BASE, EHATruth, Inputs  # noqa: E402
from experiments.concealed.truth.effects import InputDelay, make_effect  # noqa: E402

CASE_DIR = ROOT / "experiments" / "concealed"
DT = 1e-3


def bare_params(**kw):
    """Seed 004 nominal values with friction and leakage switched off."""
    p = dict(NOMINAL_BASE)
    p.update(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0, ks_p=0.0, ks_m=0.0, c_il=0.0, c_el=0.0)
    p.update(kw)
    return p


def const_inputs(T, u=0.0, Ps=1e7, F=0.0):
    n = int(round(T / DT)) + 1
    return Inputs(0.0, DT, [u] * n, [Ps] * n, [F] * n)


def test_closed_valve_hydraulic_natural_frequency():
    p = bare_params()
    T = 0.3
    m = EHATruth(p, None, const_inputs(T))
    x0, P0, dP = 0.07, 5e6, 2e4
    y0 = m.initial_state(x0, P0)
    y0[3] += dP  # small pressure imbalance, valve closed, no friction/leakage
    t = np.arange(0.0, T, 1e-5)
    sol = m.simulate(t, y0, rtol=1e-9, max_step=1e-4)
    assert sol.success
    v = sol.y[6]
    s = np.signbit(v)
    idx = np.nonzero(s[1:] != s[:-1])[0]
    # linear interpolation of the zero crossings
    tz = t[idx] - v[idx] * (t[idx + 1] - t[idx]) / (v[idx + 1] - v[idx])
    period = 2.0 * np.mean(np.diff(tz))
    A, V1, V2 = p["A"], p["V10"] + p["A"] * x0, p["V20"] - p["A"] * x0
    w = math.sqrt(p["beta"] * A * A * (1.0 / V1 + 1.0 / V2) / p["m"])
    assert 2 * math.pi / period == pytest.approx(w, rel=2e-3)
    # undamped: force A*dP released from rest -> velocity amplitude A*dP/(m*w)
    vmax_th = A * dP / (p["m"] * w)
    assert np.max(np.abs(v)) == pytest.approx(vmax_th, rel=5e-3)


def test_steady_velocity_orifice_law():
    kv = 2000.0
    p = bare_params(kv_p=kv, kv_m=kv, dp_lam=1.0)
    Ps, Pd, u = 1e7, p["Pd"], 20.0
    m = EHATruth(p, None, const_inputs(0.8, u=u, Ps=Ps))
    y0 = m.initial_state(0.05, 5e6)
    t = np.arange(0.0, 0.8, 1e-3)
    sol = m.simulate(t, y0, rtol=1e-9)
    assert sol.success
    # closed form: A(P1-P2) = kv v, Ps - P1 = P2 - Pd, v = Kv (u/100) sqrt(Ps - P1) / A
    v = 0.1
    for _ in range(100):
        dp = kv * v / p["A"]
        v = p["Kv"] * u / 100.0 * math.sqrt((Ps - Pd - dp) / 2.0) / p["A"]
    assert sol.y[6, -1] == pytest.approx(v, rel=1e-4)
    assert sol.y[3, -1] - sol.y[4, -1] == pytest.approx(kv * v / p["A"], rel=1e-3)


def test_rate_limiter_slope_and_spool_gain():
    p = bare_params(kv_p=5e4, kv_m=5e4)
    n = 201
    inp = Inputs(0.0, DT, [0.0] * 10 + [50.0] * (n - 10), [1e7] * n, [0.0] * n)
    m = EHATruth(p, None, inp)
    t = np.arange(0.0, 0.2, 1e-4)
    sol = m.simulate(t, m.initial_state(0.07, 5e6), rtol=1e-9, max_step=1e-4)
    xrl = sol.y[0]
    # the command rises 50 % within 1 ms, the limited reference at s_max = 2000 %/s
    k = (t > 0.015) & (t < 0.030)
    slope = np.polyfit(t[k], xrl[k], 1)[0]
    assert slope == pytest.approx(p["s_max"], rel=1e-3)
    assert sol.y[1, -1] == pytest.approx(50.0, rel=1e-4)  # unit DC gain of eq. 2


def test_input_delay_shifts_a_ramp_by_exactly_the_delay():
    p = bare_params(kv_p=5e4, kv_m=5e4)
    Td = 0.012
    n = 301
    ramp = [0.0 if i < 50 else 0.1 * (i - 50) for i in range(n)]  # 100 %/s from t = 50 ms
    inp = Inputs(0.0, DT, ramp, [1e7] * n, [0.0] * n)
    t = np.arange(0.0, 0.3, 1e-4)
    y = {}
    for name, eff in (("plain", None), ("delayed", InputDelay(T_d=Td))):
        m = EHATruth(p, eff, inp)
        sol = m.simulate(t, m.initial_state(0.07, 5e6), rtol=1e-10, max_step=1e-4)
        y[name] = sol.y[0]  # rate-limited reference = the command seen by the valve
    shifted = np.interp(t - Td, t, y["plain"], left=0.0)
    assert np.max(np.abs(y["delayed"] - shifted)) < 1e-6 * 25.0
    k = t > 0.1
    assert np.allclose(y["delayed"][k], 0.1e3 * (t[k] - 0.05 - Td), atol=1e-4)


def test_valve_hysteresis_loop_has_its_half_width():
    """The Dahl loop of the valve_hysteresis case: with the spool moving steadily one way the
    lag z of the metering opening settles at +h, after a reversal at −h (loop width 2h),
    approached as z = −h + 2h·exp(−sigma·Δx/h) over the travel Δx since the reversal."""
    from experiments.concealed.truth.effects import ValveHysteresis
    from scipy.integrate import solve_ivp
    eff = ValveHysteresis(h=0.8, sigma=6.0, eps=0.5)

    class _Model:
        n_base = 3

    def rhs(t, y):
        rate = 10.0 if t < 1.0 else -10.0          # spool velocity, %/s
        state = [0.0, 0.0, rate, y[0]]
        dy = [0.0] * 4
        eff.more_derivatives(_Model, t, state, dy, 0.0)
        return [dy[3]]

    sol = solve_ivp(rhs, (0.0, 2.0), [0.0], t_eval=[0.99, 1.01, 1.05, 1.99], rtol=1e-9, atol=1e-12, max_step=1e-3)
    z = sol.y[0]
    assert z[0] == pytest.approx(0.8, rel=1e-3) and z[3] == pytest.approx(-0.8, rel=1e-3)
    for k, travel in ((1, 0.1), (2, 0.5)):                      # % of spool stroke
        assert z[k] == pytest.approx(-0.8 + 1.6 * np.exp(-6.0 * travel / 0.8), abs=2e-3)


def test_tighter_tolerance_agrees():
    from experiments.concealed.generate import CASES, base_params
    spec = CASES["line_dynamics"]
    p, _ = base_params(spec["seed"], {})
    n = 1001
    tt = np.arange(n) * DT
    u = 15.0 * np.sin(2 * math.pi * 3.0 * tt)
    inp = Inputs(0.0, DT, u, [1e7] * n, 1000.0 * np.sin(2 * math.pi * 1.5 * tt))
    out = []
    for rtol in (1e-7, 1e-10):
        m = EHATruth(p, make_effect("line_dynamics", spec["params"]), inp)
        sol = m.simulate(tt, m.initial_state(0.1, 5e6), rtol=rtol,
                         atol=m.default_atol() * rtol / 1e-7)
        assert sol.success
        out.append(sol.y)
    assert np.max(np.abs(out[0][3] - out[1][3])) < 2e3  # < 0.02 bar
    assert np.max(np.abs(out[0][6] - out[1][6])) < 1e-4  # < 0.1 mm/s


def _cases():
    if not CASE_DIR.is_dir():
        return []
    return sorted(d.name for d in CASE_DIR.iterdir() if (d / "train.json").is_file())


def test_at_least_ten_effects_and_two_null_cases():
    effects = set()
    nulls = 0
    for c in _cases():
        for kind in ("train", "validate"):
            assert (CASE_DIR / c / f"{kind}.csv").is_file()
            assert (CASE_DIR / c / f"{kind}.json").is_file()
        e = json.loads((CASE_DIR / c / "train.json").read_text())["effect"]
        if e == "none":
            nulls += 1
        else:
            effects.add(e)
    assert nulls >= 2 and len(effects) >= 10


@pytest.mark.parametrize("case", _cases())
def test_case_sidecar_reproduces(case):
    """Re-simulate 2 s from the recorded state at t = 0 with the CSV inputs and compare with
    the sidecar's noise-free samples and with the (noisy) CSV."""
    sc = json.loads((CASE_DIR / case / "train.json").read_text())
    with open(CASE_DIR / case / "train.csv") as f:
        header = f.readline().strip()
    assert header == "t[s],u[%],Ps[Pa],Fext[N],P1[Pa],P2[Pa],x[m],v[m/s]"
    data = np.loadtxt(CASE_DIR / case / "train.csv", delimiter=",", skiprows=1, max_rows=2101)
    assert sc["n_samples"] == 20001
    eff = make_effect(sc["effect"], sc["effect_params"])
    inp = Inputs(data[0, 0], DT, data[:, 1], data[:, 2], data[:, 3])
    m = EHATruth(sc["true_base_params"], eff, inp)
    y0 = np.array([sc["initial_state_t0"][n] for n in m.layout.names])
    t = data[:2001, 0]
    sol = m.simulate(t, y0)
    assert sol.success
    out = m.measured(sol.y)
    ref = sc["noise_free_reference"]
    idx = np.round(np.array(ref["t"]) / DT).astype(int)
    assert np.allclose(out["P1"][idx], ref["P1"], atol=3e3)
    assert np.allclose(out["P2"][idx], ref["P2"], atol=3e3)
    assert np.allclose(out["x"][idx], ref["x"], atol=2e-6)
    assert np.allclose(out["v"][idx], ref["v"], atol=3e-4)
    # residual of the CSV against the re-simulation is the documented sensor noise
    sm = sc["sensor_model"]
    rP = data[:2001, 4] - out["P1"]
    assert abs(np.mean(rP)) < 3e3 and 0.7 * sm["P_sigma"] < np.std(rP) < 1.3 * sm["P_sigma"]
    rv = data[:2001, 7] - out["v"]
    assert abs(np.mean(rv)) < 3e-4 and np.std(rv) < 1.3 * sm["v_sigma"]
    assert np.max(np.abs(data[:2001, 6] - out["x"])) < 2e-5
    # sidecar bookkeeping
    assert sc["checks"]["all_finite"] and sc["checks"]["solver_status_effect_on"] == "ok"
    if sc["effect"] != "end_stop":
        assert sc["checks"]["x_inside_bounds"]
    assert sc["checks"]["pressures_between_tank_and_supply"]
    if sc["effect"] == "none":
        assert sc["effect_esr_percent"]["dp"] == 0.0
    else:
        e = sc["effect_esr_percent"]
        assert max(e["dp"], e["v"], e["P1"]) > 0.5


def _sidecars():
    return [(c, k) for c in _cases() for k in ("train", "validate")]


@pytest.mark.parametrize("case,kind", _sidecars())
def test_effect_esr_finite_and_in_documented_range(case, kind):
    """Every sidecar's effect ESR is finite and the effect size lies in the documented band
    (generate.ESR_RANGE, README): max(dp, v) for effect cases, exactly 0 for null cases."""
    from experiments.concealed.generate import ESR_RANGE
    sc = json.loads((CASE_DIR / case / f"{kind}.json").read_text())
    e = sc["effect_esr_percent"]
    assert set(e) >= {"dp", "v", "P1", "x"}
    assert all(math.isfinite(v) and v >= 0.0 for v in e.values()), e
    assert all(math.isfinite(v) for v in sc["noise_esr_percent"].values())
    if sc["effect"] == "none":
        assert all(v == 0.0 for v in e.values())
    else:
        assert ESR_RANGE[0] <= max(e["dp"], e["v"]) <= ESR_RANGE[1], e
        assert sc["effect_esr_range_percent"] == list(ESR_RANGE)
        assert sc["checks"]["solver_status_effect_off"] == "ok"
        assert sc["checks"]["x_inside_bounds_effect_off"]
    if sc["effect"] == "end_stop":
        assert sc["checks"]["stop_contacts"] >= 1
        assert sc["checks"]["stop_max_penetration_m"] < 1e-3


def _param(model, name):
    return next(p for p in model.params if p.name == name)


@pytest.mark.parametrize("case", _cases())
def test_case_base_machine_builds_without_the_effect(case):
    """<case>/base.yaml builds and has the concealed effect removed (fixed at zero)."""
    from experiments.concealed.generate import base_machine_text
    from hydrocli.runner import load_machine
    path = CASE_DIR / case / "base.yaml"
    assert path.is_file()
    assert path.read_text() == base_machine_text(case)  # regenerated, not hand-edited
    _net, model = load_machine(path, [])
    effect = json.loads((CASE_DIR / case / "train.json").read_text())["effect"]
    zero = {"internal_leakage": ["cylinder.c_il"], "external_leakage": ["cylinder.c_el"],
            "coulomb_friction": ["friction.kc_p", "friction.kc_m"],
            "stribeck_friction": ["friction.ks_p", "friction.ks_m"]}.get(effect, [])
    for name in zero:
        p = _param(model, name) if any(q.name == name for q in model.params) else None
        assert p is None or (p.value == 0.0 and not p.free), name
    free = {p.name for p in model.params if p.free}
    assert "valve.Kv" in free and "load.m" in free
    assert not any(n.startswith("valve.overlap") or n == "valve.Kv_neg_ratio" for n in free)
    if effect == "external_leakage":
        g = _param(model, "valve.G_leak")
        sc = json.loads((CASE_DIR / case / "train.json").read_text())
        assert g.value == pytest.approx(sc["true_base_params"]["G_leak"]) and not g.free
