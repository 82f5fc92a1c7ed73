"""The family's truth simulators against closed forms, and the generator's determinism.

References: static equilibrium A_A P_A - A_B P_B = m g; closed-valve chamber continuity with
a constant bulk modulus, P - P0 = -beta ln(V/V0); small-angle period of a pendulum on a
hydraulically locked vane actuator, T = 2 pi sqrt(J / (W + beta D^2 (1/V1 + 1/V2))), and with
the actuator decoupled, 2 pi sqrt(J/W); counterbalance-valve cracking at p_L + C1 p_x = p_cr.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from experiments.concealed.truth.eha import Inputs
from experiments.family import catalogue as cat
from experiments.family.generate import all_cases, run_case
from experiments.family.machines import G, MACHINES
from experiments.family.split import split_of
from experiments.family.truth.actuator import ActuatorTruth, cbv_flows


def _closed_valve(T: float, dt: float = 1e-3) -> Inputs:
    n = int(T / dt) + 2
    return Inputs(0.0, dt, [0.0] * n, [1.6e7] * n, [0.0] * n)


def _lift(**over):
    p = dict(MACHINES["lift"].nominal)
    p.update(over)
    return p


def test_static_equilibrium_holds_the_weight():
    p = _lift()
    PB = 1e5
    PA = (p["m"] * G + p["A_B"] * PB) / p["A_A"]          # A_A P_A - A_B P_B = m g
    m = ActuatorTruth(p, None, _closed_valve(1.0))
    y0 = m.initial_state(0.2, PA, PB)
    sol = m.simulate(np.linspace(0, 1.0, 101), y0, rtol=1e-10)
    assert sol.success
    assert np.max(np.abs(sol.y[3] - PA)) < 1.0            # Pa
    assert np.max(np.abs(sol.y[5] - 0.2)) < 1e-9


def test_closed_valve_continuity_log_law():
    p = _lift(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    m = ActuatorTruth(p, None, _closed_valve(0.3))
    PA0, PB0 = 4.0e6, 1.0e6                               # off equilibrium: it oscillates
    y0 = m.initial_state(0.2, PA0, PB0)
    sol = m.simulate(np.linspace(0, 0.3, 301), y0, rtol=1e-10)
    x = sol.y[5]
    VA, VA0 = p["V10"] + p["A_A"] * x, p["V10"] + p["A_A"] * 0.2
    VB, VB0 = p["V20"] - p["A_B"] * x, p["V20"] - p["A_B"] * 0.2
    assert np.ptp(x) > 5e-5                               # it did move
    np.testing.assert_allclose(sol.y[3], PA0 - p["beta"] * np.log(VA / VA0), atol=50.0)
    np.testing.assert_allclose(sol.y[4], PB0 - p["beta"] * np.log(VB / VB0), atol=50.0)


def _period(theta, t):
    s = np.sign(theta - theta.mean())
    up = t[1:][(s[:-1] < 0) & (s[1:] >= 0)]
    return float(np.mean(np.diff(up)))


@pytest.mark.parametrize("locked", [True, False])
def test_pendulum_small_angle_period(locked):
    p = dict(MACHINES["rotary"].nominal)
    p.update(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    if not locked:                                        # hydraulically decoupled arm
        p.update(A_A=1e-12, A_B=1e-12)
    m = ActuatorTruth(p, None, _closed_valve(4.0))
    y0 = m.initial_state(0.0, 5e6, 5e6)
    y0[6] = 0.01                                          # small kick [rad/s]
    t = np.linspace(0, 4.0, 40001)
    sol = m.simulate(t, y0, rtol=1e-10, max_step=1e-3)
    K = p["W"] + p["beta"] * p["A_A"] ** 2 * (1 / p["V10"] + 1 / p["V20"])
    T_ref = 2 * math.pi * math.sqrt(p["m"] / K)
    assert _period(sol.y[5], sol.t) == pytest.approx(T_ref, rel=2e-3)
    assert np.max(np.abs(sol.y[5])) < 0.05                # small angle


def test_cbv_cracks_on_its_line():
    p = dict(MACHINES["lift_cbv"].nominal)
    Pd = p["Pd"]
    for px in (0.0, 5e5, 1e6):                            # gauge pilot pressure
        pl_cr = p["p_cr"] - p["C1"] * px                  # gauge load pressure at cracking
        assert cbv_flows(p, Pd + 0.995 * pl_cr, Pd, Pd + px) == 0.0
        assert cbv_flows(p, Pd + 1.05 * pl_cr, Pd, Pd + px) > 0.0
    # the check valve passes V -> L when the valve side is 5 bar higher
    assert cbv_flows(p, Pd + 2e6, Pd + 2.5e6, Pd) < 0.0


def test_cbv_holds_the_load_with_the_valve_closed():
    p = dict(MACHINES["lift_cbv"].nominal)
    PB = 1e5
    PA = (p["m"] * G + p["A_B"] * PB) / p["A_A"]          # below cracking (p_cr 42 bar)
    m = ActuatorTruth(p, None, _closed_valve(1.0))
    y0 = m.initial_state(0.2, PA, PB)
    y0[9] = 1e5                                           # valve-side line at tank pressure
    sol = m.simulate(np.linspace(0, 1.0, 101), y0, rtol=1e-10)
    assert np.max(np.abs(sol.y[5] - 0.2)) < 1e-9


def test_split_is_balanced_and_every_effect_is_on_both_sides():
    cases = all_cases(list(MACHINES), [0, 1, 2])
    dev = [c for c in cases if split_of(*c) == "dev"]
    assert 0.4 < len(dev) / len(cases) < 0.6
    for e in cat.FORMS:
        sides = {split_of(*c) for c in cases if c[1] == e}
        assert sides == {"dev", "heldout"}, e
    assert all(split_of(*c) == split_of(*c) for c in cases[:20])


def test_every_effect_has_two_forms_on_every_machine_that_carries_it():
    """Two forms (plus at most one third form, catalogue.THIRD_FORMS, on some machines, and
    at most one fourth, catalogue.FOURTH_FORMS, and one fifth, catalogue.FIFTH_FORMS)."""
    for m in MACHINES:
        for e in cat.FORMS:
            fs = [f for f in cat.forms_of(m, e) if f not in cat.FOURTH_FORMS and f not in cat.FIFTH_FORMS]
            assert len([f for f in cat.forms_of(m, e) if f in cat.FOURTH_FORMS]) <= 1, (m, e)
            assert len([f for f in cat.forms_of(m, e) if f in cat.FIFTH_FORMS]) <= 1, (m, e)
            n = len([f for f in fs if f not in cat.THIRD_FORMS])
            assert n in (0, 2), (m, e, n)
            assert len(fs) - n <= (1 if n else 0), (m, e, fs)


@pytest.mark.slow
@pytest.mark.parametrize("machine, effect, form, header", [
    ("lift", "internal_leakage", "orifice", None),
    ("winch", "payload_swing", "drum_rope", "t[s],u[%],Ps[Pa],P1[Pa],P2[Pa],theta[rad],w[rad/s]"),
], ids=["lift", "winch"])
def test_generator_is_deterministic(tmp_path, machine, effect, form, header):
    a, b = tmp_path / "a", tmp_path / "b"
    run_case(machine, effect, form, 0, a, duration=1.0)
    run_case(machine, effect, form, 0, b, duration=1.0)
    fa = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    fb = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    assert fa == fb and len(fa) == 5
    for f in fa:
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    if header is not None:
        assert (a / fa[0].parent / "train.csv").read_text().splitlines()[0] == header


def test_rope_pendulum_payload_conserves_energy():
    """Arm + rope payload, no hydraulics, friction or damping: E = T + V is constant."""
    from experiments.family.truth.forms import RopePendulum
    p = dict(MACHINES["rotary"].nominal)
    p.update(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0, A_A=1e-12, A_B=1e-12)
    eff = RopePendulum(m_p=3.0, r=0.6, L=0.5, c_r=0.0)
    m = ActuatorTruth(p, eff, _closed_valve(3.0))
    y0 = m.initial_state(0.3, 5e6, 5e6)
    y0[m.n_base] = -0.2                                   # rope angle
    sol = m.simulate(np.linspace(0, 3.0, 3001), y0, rtol=1e-10, max_step=1e-3)
    th, thd, ph, phd = sol.y[5], sol.y[6], sol.y[m.n_base], sol.y[m.n_base + 1]
    mp, r, L, g, J, W = 3.0, 0.6, 0.5, 9.81, p["m"], p["W"]
    T = 0.5 * J * thd ** 2 + 0.5 * mp * (r * r * thd ** 2 + L * L * phd ** 2
                                         + 2 * r * L * thd * phd * np.cos(th - ph))
    V = -W * np.cos(th) - mp * g * (r * np.cos(th) + L * np.cos(ph))
    E = T + V
    assert np.ptp(th) > 0.3 and np.ptp(ph) > 0.2          # it swings
    assert np.ptp(E) < 1e-6 * abs(E[0])


@pytest.mark.parametrize("form", ["RopeBouncePayload", "SheaveFrictionPayload"])
def test_hanging_payload_shares_the_weight_and_bounces_on_its_rope(form):
    """A load held by a constant force equal to its weight W (an ideal cylinder), part of it
    (m_frac) hanging on the rope: at the rope's static stretch nothing moves (the payload's
    weight is part of W, not added); released 2 mm off it, load and payload bounce at
    sqrt(k (1/m_p + 1/m_r)) (two free masses on a spring, k = m_p (2 pi f)^2) about a
    centre of mass that stays put; the sheave form's dry friction mu T takes 4 mu T / k of
    amplitude per cycle (Coulomb damping, linear decay)."""
    from types import SimpleNamespace

    from scipy.integrate import solve_ivp

    from experiments.family.truth import forms as F
    mr, W = 1000.0, 1000.0 * G
    sheave = form.startswith("Sheave")
    params = {"m_frac": 0.3, "f_hz": 2.0, "zeta": 0.0, **({"mu": 0.0005} if sheave else {})}
    eff = getattr(F, form)(**params)
    model = SimpleNamespace(p={"m": mr, "W": W}, n_base=2)
    mp = 0.3 * mr
    k = mp * (2 * math.pi * 2.0) ** 2

    def rhs(t, y):
        dy = [y[1], 0.0, 0.0, 0.0]
        dy[1] = eff.piston_accel(model, y, W, -W, 0.0, dy)
        return dy
    t = np.linspace(0, 4.0, 8001)
    for ds in (0.0, 2e-3):
        sol = solve_ivp(rhs, (0, 4.0), [0.3, 0.0, ds, 0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=1e-3)
        x, s = sol.y[0], sol.y[2]
        x_cm = x - (mp / mr) * (s - s[0])
        assert np.abs(x_cm - 0.3).max() < 1e-9
        if ds == 0.0:
            assert np.abs(s).max() < 1e-12 and np.abs(x - 0.3).max() < 1e-12
            continue
        f = math.sqrt(k * (1 / mp + 1 / (mr - mp))) / (2 * math.pi)
        up = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0))
        assert len(up) >= 6
        assert 1.0 / np.mean(np.diff(t[up])) == pytest.approx(f, rel=5e-3)
        peaks = [s[a:b].max() for a, b in zip(up[:-1], up[1:])]
        loss = 4 * 0.0005 * 0.3 * W / k if sheave else 0.0          # amplitude lost per cycle
        assert np.diff(peaks) == pytest.approx(-loss * np.ones(len(peaks) - 1), abs=0.05 * 4 * 0.0005 * 0.3 * W / k)


def test_a_mounted_vanes_arm_weighs_at_its_absolute_angle():
    """A vane on a compliant mount: the encoder reads the stroke (arm relative to housing), the
    arm hangs at stroke + housing deflection and its weight acts there. Arm and housing without
    hydraulics, friction or damping: ½J(θ̇+θ̇_b)² + ½J_b θ̇_b² + ½k_b θ_b² + W(1 − cos(θ + θ_b)) is
    constant (with the weight at the stroke alone it is not: session 45)."""
    from experiments.family.truth.forms import CompliantMount
    p = dict(MACHINES["rotary"].nominal)
    p.update(kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0, A_A=1e-12, A_B=1e-12)
    eff = CompliantMount(m_b=0.2, k_b=300.0, c_b=0.0)
    m = ActuatorTruth(p, eff, _closed_valve(3.0))
    y0 = m.initial_state(0.4, 5e6, 5e6)
    y0[m.n_base] = 0.05                                    # housing deflected
    sol = m.simulate(np.linspace(0, 3.0, 3001), y0, rtol=1e-10, max_step=1e-3)
    x, v, xb, vb = sol.y[5], sol.y[6], sol.y[m.n_base], sol.y[m.n_base + 1]
    E = (0.5 * p["m"] * (v + vb) ** 2 + 0.5 * 0.2 * vb ** 2 + 0.5 * 300.0 * xb ** 2
         + p["W"] * (1.0 - np.cos(x + xb + p["theta0"])))
    assert np.ptp(xb) > 0.05 and np.ptp(x) > 0.3
    assert np.ptp(E) < 1e-6 * np.max(E)
