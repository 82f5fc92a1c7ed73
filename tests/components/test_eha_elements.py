"""Seed 004 elements against closed forms: the rate limiter of eq. 1 (rising and falling limits),
the friction law of eqs. 9–11 with the paper's identified values, and the vane actuator."""
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from helpers import evaluate, pinned_model
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.runner import load_machine
from simhelpers import col, run

ROOT = Path(__file__).resolve().parents[2]
TAU = 1e-3


def _limiter_exact(t, y0, u, s, tau=TAU):
    """Exact solution of y' = s·tanh((u − y)/(τ s)): with z = (u − y)/(τ s), z' = −tanh(z)/τ,
    so sinh z(t) = sinh z(0)·e^(−t/τ)."""
    z0 = (u - y0) / (tau * s)
    return u - tau * s * np.arcsinh(np.sinh(z0) * np.exp(-t / tau))


def _block(s_max, s_min):
    return f"""
name: rl
inputs: {{u: {{unit: "1"}}}}
components:
  rl: {{type: rate_limiter, ports: {{in: u, out: y}}, s_max: {s_max}, s_min: {s_min}, tau: {TAU}}}
"""


def _valve(s_max, s_min):
    extra = f"    s_min: {s_min}\n" if s_min else ""
    return f"""
name: rlv
inputs: {{u: {{unit: "1"}}}}
components:
  supply: {{type: pressure_source, ports: {{P: ps}}, p: 1.0e7}}
  tank: {{type: tank, ports: {{T: pt}}}}
  valve:
    type: valve_4_3
    ports: {{P: ps, T: pt, A: pa, B: pb, cmd: u}}
    s_max: {s_max}
    tau_rl: {TAU}
{extra}  vol_a: {{type: volume, ports: {{P: pa}}, V: 1.0e-4}}
  vol_b: {{type: volume, ports: {{P: pb}}, V: 1.0e-4}}
"""


@pytest.mark.parametrize("kind, state", [("block", "rl.y"), ("valve", "valve.xr")])
@pytest.mark.parametrize("s_max, s_min", [(20.0, 0.0), (20.0, 5.0)])
def test_rate_limiter_rising_and_falling_limits(kind, state, s_max, s_min):
    """Eq. 1: the reference rises at most at s_v,max and falls at most at |s_v,min|
    (s_min = 0: symmetric, s_max both ways); exact tanh-limiter solution as reference."""
    text = (_block if kind == "block" else _valve)(s_max, s_min)
    s_fall = s_min or s_max
    t_end = 1.5 / s_fall
    for y0, u, s in ((0.0, 1.0, s_max), (1.0, 0.0, s_fall)):
        m, tr, _ = run(text, t_end, n=301, inputs={"u": u}, x0={state: y0})
        y = col(m, tr, state)
        assert np.allclose(y, _limiter_exact(tr.t, y0, u, s), atol=2e-4 * max(1.0, s / s_fall))
        mid = (np.abs(y - 0.5) < 0.3)
        slope = np.polyfit(tr.t[mid], y[mid], 1)[0]
        assert slope == pytest.approx(np.sign(u - y0) * s, rel=1e-3)


@pytest.fixture(scope="module")
def eha():
    _, model = load_machine(ROOT / "machines" / "eha_testbench.yaml", [])
    return model


@pytest.mark.parametrize("v", [0.002, 0.01, 0.05, -0.002, -0.01, -0.05])
def test_eha_friction_is_eqs_9_to_11_with_the_papers_values(eha, v):
    """F = k_v v + k_c sign(v) + k_s sign(v) e^(−|v|/τ_s), coefficients by direction (§V values:
    k_v± 1.21e4/1.37e4 kg/s, k_c± 1.14e3/1.18e3 N, k_s± 244.37/39.36 N, τ_s± 3.41e-3/1.96e-3 m/s);
    |v| ≫ ε (1e-4 m/s) so tanh(v/ε) = sign(v)."""
    paper = {1: (1.21e4, 1.14e3, 244.37, 3.41e-3), -1: (1.37e4, 1.18e3, 39.36, 1.96e-3)}
    kv, kc, ks, vs = paper[int(np.sign(v))]
    x = eha.x0.copy()
    x[eha.state_index("piston.v")] = v
    u = np.zeros((1, len(eha.input_names)))
    f = eha.evaluate_along(np.zeros(1), x[None, :], u, eha.p0)["friction.F"][0]
    assert f == pytest.approx(kv * v + np.sign(v) * (kc + ks * np.exp(-abs(v) / vs)), rel=1e-9)


def test_eha_friction_is_continuous_and_zero_at_rest(eha):
    """tanh smoothing (text after eq. 11): F(0) = 0 and F(±ε·5) already ≥ 99.9 % of the
    Coulomb + Stribeck force, of the sign of v."""
    u = np.zeros((3, len(eha.input_names)))
    X = np.repeat(eha.x0[None, :], 3, axis=0)
    X[:, eha.state_index("piston.v")] = [0.0, 5e-4, -5e-4]
    f = eha.evaluate_along(np.zeros(3), X, u, eha.p0)["friction.F"]
    assert f[0] == 0.0
    assert f[1] > 0.999 * (1.14e3 + 244.37 * np.exp(-5e-4 / 3.41e-3))
    assert f[2] < -0.999 * (1.18e3 + 39.36 * np.exp(-5e-4 / 1.96e-3))


def test_vane_actuator_torque_flow_and_leakage():
    """Seed 001 eqs. 12–13, 20: torque D_v(p_1 − p_2), flow into chamber 1 = D_v ω + R_v(p_1 − p_2)."""
    d_v, r_v = 2e-5, 3e-12
    m = pinned_model(f"""  vane:
    type: vane_actuator
    ports: {{A: n1, B: n2, shaft: sh, body: ground}}
    D_v: {d_v}
    R_v: {r_v}
  load: {{type: inertia, ports: {{r: sh}}, J: 0.1}}""", {"n1": "p1", "n2": "p2"})
    x = np.zeros(len(m.state_names))
    x[m.state_index("sh.w")] = 0.7
    p1, p2 = np.array([80e5, 20e5]), np.array([10e5, 30e5])
    r = evaluate(m, {"p1": p1, "p2": p2}, x=x)
    assert np.allclose(r["vane.tau"], d_v * (p1 - p2), rtol=1e-12)
    assert np.allclose(r["vane.q_leak"], r_v * (p1 - p2), rtol=1e-12)
    assert np.allclose(r["src_n1.q"], d_v * 0.7 + r_v * (p1 - p2), rtol=1e-9)
    assert np.allclose(r["src_n2.q"], -(d_v * 0.7 + r_v * (p1 - p2)), rtol=1e-9)


def test_spool_hysteresis_is_dahls_loop_on_the_spool_position():
    """``hyst_h`` puts Dahl's loop between the spool and its metering lands, driven by the
    spool's own speed: on a monotone spool travel dz/dx_v = σ(1 − z/h) (|ẋ_v| ≫ ε), so from z0
    at x_v0, z = h + (z0 − h)·exp(−σ(x_v − x_v0)/h), mirrored going down. The command ramps up
    and back through a first-order spool (τ 20 ms); z is read from the state against the spool
    state x_v, so the closed form holds whatever the spool's lag."""
    h, sigma = 0.01, 3.0
    text = _valve(1000.0, 0.0).replace("    tau_rl:", f"    order: 1\n    tau: 0.02\n    hyst_h: {h}\n"
                                                      f"    hyst_sigma: {sigma}\n    tau_rl:")

    def ramp(t):
        return {"u": 0.05 * np.where(t < 1.0, t, 2.0 - t)}
    m, tr, _ = run(text, 2.0, n=4001, inputs=ramp)
    xv, z = col(m, tr, "valve.xv"), col(m, tr, "valve.zh")
    t = tr.t
    up = (t > 0.05) & (t < 0.99)
    assert np.max(np.abs(z[up] - h * (1 - np.exp(-sigma * xv[up] / h)))) < 1e-5 * h
    k = np.argmin(np.abs(t - 1.2))            # past the reversal: the spool moves down again
    down = (t > 1.2) & (t < 1.99)
    ref = -h + (z[k] + h) * np.exp(-sigma * (xv[k] - xv[down]) / h)
    assert np.max(np.abs(z[down] - ref)) < 1e-5 * h
    # the metering position trails the spool by h in the direction of motion
    assert z[np.argmin(np.abs(t - 0.9))] == pytest.approx(h, rel=1e-3)
    assert z[np.argmin(np.abs(t - 1.9))] == pytest.approx(-h, rel=1e-3)
    # without hyst_h the valve has no loop state (the plain valve keeps its size)
    assert "valve.zh" not in build_model(load_netlist_text(_valve(1000.0, 0.0))).state_names


def test_spool_play_holds_the_lands_inside_its_band():
    """``play_b`` puts a play between the spool and its metering lands: after the spool
    reverses, the lands (the metering position) stay until the spool has come back by 2b,
    then follow it b behind. Following the spool at speed r, the smooth play's
    s⁺(d) − s⁺(−d − 2b) = τ·r (s⁺(x) = ½(x + √(x² + ε²)), d = |x_v − x_e| − b) fixes the
    lag b + d, solved here by bisection."""
    b, eps, tau, r = 0.01, 1e-4, 2e-4, 0.05
    text = _valve(1000.0, 0.0).replace("    tau_rl:", f"    order: 1\n    tau: 0.02\n    play_b: {b}\n    tau_rl:")

    def ramp(t):
        return {"u": r * np.where(t < 1.0, t, 2.0 - t)}
    m, tr, _ = run(text, 2.0, n=4001, inputs=ramp)
    xv, xe, t = col(m, tr, "valve.xv"), col(m, tr, "valve.xe"), tr.t

    def splus(x):
        return 0.5 * (x + np.sqrt(x * x + eps * eps))
    lag = b + brentq(lambda d: splus(d) - splus(-d - 2 * b) - tau * r, -b, b, xtol=1e-14)
    going = (t > 0.3) & (t < 0.99)                 # the spool moves at r (its lag settled)
    assert np.max(np.abs(xe[going] - (xv[going] - lag))) < 1e-6
    back = (t > 1.5) & (t < 1.99)
    assert np.max(np.abs(xe[back] - (xv[back] + lag))) < 1e-6
    # after the spool's peak the lands hold (to a tenth of the band: the smoothed edges creep)
    # while the spool comes back across most of the band
    k = int(np.argmax(xv))
    inside = (np.arange(len(t)) > k) & (xv > xv[k] - 2 * b + 2e-3)
    assert np.ptp(xv[inside]) > 1.5 * b and np.ptp(xe[inside]) < 0.1 * b
