"""The hoist winch (machine type "winch") against closed forms, and its place in the family.

References (D displacement per rad, V10/V20 the constant chamber volumes, J the drum-referred
inertia, W = m g r the constant weight moment):
  holding          D (P1 - P2) = W at rest;
  continuity       with the valve closed, V_i dP_i = -/+ beta D dtheta: P1 and P2 are LINEAR in
                   the angle (a motor's volumes do not change; a vane's log law would not be);
  locked motor     a small disturbance rings at omega_h = sqrt(k_h / J),
                   k_h = beta D^2 (1/V10 + 1/V20) (the constant W adds no stiffness);
  centre leakage   held at rest by the spool offset x = 100 G ((P1 - Pd) - (Ps - P1)) / (Kv sqrt(Ps - P1)),
                   P1 + P2 = Ps + Pd (symmetric meter-in / meter-out);
  hook load        bounces at sqrt(k (1/J_p + 1/(J - J_p))), k = J_p (2 pi f)^2 L0 / (L0 - r theta).
"""
from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from experiments.concealed.truth.eha import Inputs
from experiments.family import catalogue as cat
from experiments.family.generate import all_cases, base_machine_text
from experiments.family.machines import G, MACHINES
from experiments.family.truth.actuator import ActuatorTruth
from experiments.family.truth.winch import DrumRopeBounce, DrumSheaveFriction, holding_dp, hydraulic_stiffness

ROOT = Path(__file__).resolve().parents[2]


def _winch(**over) -> dict:
    p = dict(MACHINES["winch"].nominal)
    p.update(over)
    return p


def _constant(T: float, u: float = 0.0, Ps: float = 1.6e7, dt: float = 1e-3) -> Inputs:
    n = int(T / dt) + 2
    return Inputs(0.0, dt, [u] * n, [Ps] * n, [0.0] * n)


def _period(a, t):
    s = np.sign(a - a.mean())
    up = t[1:][(s[:-1] < 0) & (s[1:] >= 0)]
    return float(np.mean(np.diff(up)))


def test_static_holding_motor_torque_balances_the_weight():
    p = _winch(G_leak=0.0)                                # closed valve, no leakage anywhere
    P2 = 4.0e6
    P1 = P2 + holding_dp(p)                               # D (P1 - P2) = W
    assert p["A_A"] * (P1 - P2) == pytest.approx(p["W"])
    m = ActuatorTruth(p, None, _constant(1.0))
    sol = m.simulate(np.linspace(0, 1.0, 101), m.initial_state(3.0, P1, P2), rtol=1e-10)
    assert sol.success
    assert np.max(np.abs(sol.y[3] - P1)) < 1.0 and np.max(np.abs(sol.y[4] - P2)) < 1.0      # Pa
    assert np.max(np.abs(sol.y[5] - 3.0)) < 1e-9 and np.max(np.abs(sol.y[6])) < 1e-8


def test_closed_valve_continuity_with_constant_volumes_is_linear_in_the_angle():
    p = _winch(G_leak=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0, V20=9.0e-4)
    m = ActuatorTruth(p, None, _constant(0.3))
    P10, P20, th0 = 1.3e7, 3.0e6, 5.0                     # off equilibrium: it rings
    sol = m.simulate(np.linspace(0, 0.3, 301), m.initial_state(th0, P10, P20), rtol=1e-10)
    dth = sol.y[5] - th0
    assert np.ptp(dth) > 1e-3                             # it did turn
    bD = p["beta"] * p["A_A"]
    np.testing.assert_allclose(sol.y[3], P10 - bD * dth / p["V10"], atol=20.0)
    np.testing.assert_allclose(sol.y[4], P20 + bD * dth / p["V20"], atol=20.0)
    # the angle-dependent volumes of a vane would give the log law instead: far off here
    V = p["V10"] + p["A_A"] * dth
    assert np.max(np.abs(sol.y[3] - (P10 - p["beta"] * np.log(V / p["V10"])))) > 1e3


def test_locked_motor_rings_at_the_hydraulic_frequency():
    p = _winch(G_leak=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0, V10=5.0e-4, V20=8.0e-4)
    P2 = 4.0e6
    P1 = P2 + holding_dp(p)
    m = ActuatorTruth(p, None, _constant(1.0))
    y0 = m.initial_state(0.0, P1, P2)
    y0[6] = 0.01                                          # small kick [rad/s]
    t = np.linspace(0, 1.0, 20001)
    sol = m.simulate(t, y0, rtol=1e-10, max_step=2e-4)
    k_h = hydraulic_stiffness(p)
    assert k_h == pytest.approx(p["beta"] * p["A_A"] ** 2 * (1 / 5.0e-4 + 1 / 8.0e-4))
    T_ref = 2 * math.pi * math.sqrt(p["m"] / k_h)
    assert _period(sol.y[5], sol.t) == pytest.approx(T_ref, rel=2e-3)
    assert _period(sol.y[3], sol.t) == pytest.approx(T_ref, rel=2e-3)


def test_the_valve_centre_leakage_holds_the_load_at_its_spool_offset():
    p = _winch(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    Ps, Pd = 1.6e7, p["Pd"]
    dp = holding_dp(p)
    P1 = (Ps + Pd + dp) / 2.0                             # P1 + P2 = Ps + Pd, P1 - P2 = W / D
    P2 = P1 - dp
    x = 100.0 * p["G_leak"] * ((P1 - Pd) - (Ps - P1)) / (p["Kv"] * math.sqrt(Ps - P1))
    assert 0.5 < x < 10.0                                 # a few % of spool stroke
    m = ActuatorTruth(p, None, _constant(1.0, u=x, Ps=Ps))
    y0 = m.initial_state(0.0, P1, P2)
    y0[0] = y0[1] = x                                     # spool already there
    sol = m.simulate(np.linspace(0, 1.0, 101), y0, rtol=1e-10)
    # exact up to the laminar transition of the edges (dp_lam << the edge drops here)
    assert np.max(np.abs(sol.y[6])) < 1e-4
    assert np.max(np.abs(sol.y[3] - P1)) < 2e3 and np.max(np.abs(sol.y[4] - P2)) < 2e3
    # without the offset (spool centred) the leakage lets the load sink
    m0 = ActuatorTruth(p, None, _constant(1.0, u=0.0, Ps=Ps))
    sol0 = m0.simulate(np.linspace(0, 1.0, 101), m0.initial_state(0.0, P1, P2), rtol=1e-8)
    assert sol0.y[5][-1] < -0.05


@pytest.mark.parametrize("cls", [DrumRopeBounce, DrumSheaveFriction])
@pytest.mark.parametrize("theta", [0.0, 12.0])
def test_hook_load_bounces_on_the_rope_the_drum_pays_out(cls, theta):
    """The drum held by a torque equal to the weight (an ideal motor), the hook load (share
    m_frac) released 2 mrad of stretch off its static point: drum and load bounce against
    each other at sqrt(k (1/J_p + 1/J_r)) with the rope's stiffness at its current length."""
    J, W, r, L0, f0 = 10.0, 589.0, 0.15, 6.0, 3.0
    params = {"m_frac": 0.8, "r": r, "L0": L0, "f_hz": f0, "zeta": 0.0}
    if cls is DrumSheaveFriction:
        params["mu"] = 0.0
    eff = cls(**params)
    model = SimpleNamespace(p={"m": J, "W": W}, n_base=2, _y=[0.0] * 5 + [theta])

    def rhs(t, y):
        dy = [y[1], 0.0, 0.0, 0.0]
        dy[1] = eff.piston_accel(model, y, W, -W, 0.0, dy)
        return dy
    t = np.linspace(0, 2.0, 40001)
    sol = solve_ivp(rhs, (0, 2.0), [theta, 0.0, 2e-3, 0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=1e-4)
    Jp = 0.8 * J
    k = Jp * (2 * math.pi * f0) ** 2 * L0 / (L0 - r * theta)
    f = math.sqrt(k * (1 / Jp + 1 / (J - Jp))) / (2 * math.pi)
    assert 1.0 / _period(sol.y[2], sol.t) == pytest.approx(f, rel=2e-3)


def test_the_machine_file_is_the_nominal_truth():
    """machines/hoist_winch.yaml carries the truth's nominal values (SI after parsing)."""
    from hydrocli.netlist.loader import load_netlist
    net = load_netlist(ROOT / "machines" / "hoist_winch.yaml")
    p = MACHINES["winch"].nominal

    def val(comp: str, name: str) -> float:
        return net.components[comp].params[name].value
    assert val("motor", "D_m") == pytest.approx(p["A_A"], rel=1e-4)
    assert val("motor", "V_A") == pytest.approx(p["V10"]) and val("motor", "V_B") == pytest.approx(p["V20"])
    assert val("drum", "J") == pytest.approx(p["m"])
    assert val("load", "tau0") == pytest.approx(-p["W"], rel=1e-4)
    assert p["W"] == pytest.approx(400.0 * G * 0.15)
    assert val("friction", "b") == pytest.approx(p["kv_p"]) and val("friction", "tau_c") == pytest.approx(p["kc_p"])
    assert val("friction", "eps") == pytest.approx(p["eps"])
    assert val("valve", "Kv") == pytest.approx(p["Kv"]) and val("valve", "G_leak") == pytest.approx(p["G_leak"])
    assert val("valve", "tau") == pytest.approx(p["tau_v"])
    assert val("motor", "R_m") >= 1e15 and val("motor", "R_ex") >= 1e15        # no leak


def test_the_winch_has_no_end_stop_and_every_other_effect_in_two_forms():
    assert cat.forms_of("winch", "end_stop") == []
    cases = all_cases(["winch"], [0])
    assert not [c for c in cases if c[1] == "end_stop"]
    for e in cat.FORMS:              # (besides the fourth and fifth forms, generated only when named)
        if e != "end_stop":
            fs = [f for f in cat.forms_of("winch", e) if f not in cat.FOURTH_FORMS and f not in cat.FIFTH_FORMS]
            assert len(fs) == 2, e
    for form in cat.forms_of("winch", "viscous_friction"):
        assert cat.FORMS["viscous_friction"][form][1]["winch"]
    text = base_machine_text("winch", "coulomb_friction", "x")
    assert "tau_c: {value: 0.0, free: false}" in text and text.count("b: {value: 20.0") == 1


def test_perturbation_covers_the_fixed_parameters_and_ties_the_displacement():
    from experiments.family.machines import perturbed_params
    mt = MACHINES["winch"]
    for k in ("tau_v", "s_max", "Kv", "V10", "V20", "beta", "m", "W"):
        assert mt.perturb[k][0] == pytest.approx(0.15), k
    assert mt.perturb["G_leak"][0] == pytest.approx(0.015)       # a known (measured) valve leakage
    p, fac = perturbed_params(mt, np.random.default_rng(3))
    assert p["A_A"] == p["A_B"] and abs(fac["A_A"] - 1.0) <= 0.015
    assert p["kv_p"] == p["kv_m"] and p["kc_p"] == p["kc_m"]
