"""The fifth truth forms (experiments/family/truth/fifth_forms.py) against independent
references: a seal film's leak (nothing at standstill, growing as sqrt|v|), the warming of the
oil (factor 1 at the cold start, exp(+-k_T dT_max) once warm, the first-order closed form), a
gas pocket behind a restriction (the closed chamber's volume invariant, the RC step response),
a clearance's dead zone (no force inside the band, k (d -+ b/2) outside), a moving average
(a ramp delayed by T/2, the analytic average of a sine), a differenced velocity (a ramp's slope,
the analytic difference of a sine) and a lagging compensator (P_set in steady flow, a dip
k q exp(-t/tau_c) after a step of demand). Then every form switched off against the base
truth, and switched on at its nominal size against it."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from experiments.concealed.truth.eha import Inputs
from experiments.family import catalogue as cat
from experiments.family.bench import _Live
from experiments.family.generate import all_cases
from experiments.family.machines import MACHINES
from experiments.family.truth import fifth_forms as VF
from experiments.family.truth.actuator import ActuatorTruth
from truthruns import deviation, esr, sine_run, still_inputs, truth_model

FIFTH = sorted(cat.FIFTH_FORMS.items())


# ---- registration -----------------------------------------------------------------------------
def test_fifth_forms_are_registered_after_the_fourth_and_only_generated_when_named():
    assert len(FIFTH) == 8
    for form, effect in FIFTH:
        assert form in cat.FORMS[effect] and cat.FORMS[effect][form][0].name == effect
        assert list(cat.FORMS[effect])[-1] == form                     # appended last
        assert form not in cat.THIRD_FORMS and form not in cat.FOURTH_FORMS
        assert cat.FORMS[effect][form][2], form                        # calibrated in size
    assert {m for f, e in FIFTH for m in cat.FORMS[e][f][1]} == set(MACHINES)
    for m in MACHINES:
        assert sum(m in cat.FORMS[e][f][1] for f, e in FIFTH) >= 6, m
    machines = list(MACHINES)
    default = all_cases(machines, [140, 141], "all")
    assert default and not [c for c in default if c[2] in cat.FIFTH_FORMS]
    named = all_cases(machines, [172], "all", forms=[f for f, _ in FIFTH])
    assert {c[2] for c in named} == set(cat.FIFTH_FORMS)


def test_the_viscous_form_runs_on_a_base_without_its_viscous_term():
    cls = cat.FORMS["viscous_friction"]["warming_viscous"][0]
    assert cls.base_overrides == {"kv_p": 0.0, "kv_m": 0.0}
    for m in MACHINES:
        assert [k for k, _, _ in cat.BASE_ZERO[m]["viscous_friction"]] == ["kv_p", "kv_m"]


# ---- (a) the laws -----------------------------------------------------------------------------
def test_film_leak_is_zero_at_standstill_and_grows_as_the_root_of_the_speed():
    v_ref, v_eps = 0.1, 1e-3
    assert VF.film_factor(0.0, v_ref, v_eps) == 0.0
    for v in (v_eps, 0.004, 0.1, 0.25, -0.04):
        assert VF.film_factor(v, v_ref, v_eps) == pytest.approx(math.sqrt(abs(v) / v_ref), rel=1e-12)
    assert VF.film_factor(0.04, v_ref, v_eps) == pytest.approx(2.0 * VF.film_factor(0.01, v_ref, v_eps), rel=1e-12)
    h = 1e-9                                                     # value and slope continuous at v_eps
    lo, hi = VF.film_factor(v_eps - h, v_ref, v_eps), VF.film_factor(v_eps + h, v_ref, v_eps)
    assert hi - lo == pytest.approx(2 * h * 0.5 / math.sqrt(v_eps * v_ref), rel=1e-3)
    assert 0.0 < VF.film_factor(0.5 * v_eps, v_ref, v_eps) < math.sqrt(0.5 * v_eps / v_ref)
    # in the truth: the lift's rod-side chamber loses beta q / V_B, chamber A nothing; the vane both
    for mach, both in (("lift", False), ("rotary", True)):
        prm = cat.scaled_params(mach, "external_leakage", "film_drag_out", 1.0)
        eff = cat.make("external_leakage", "film_drag_out", prm)
        m = truth_model(mach, eff, still_inputs())
        base = ActuatorTruth(dict(m.p), None, still_inputs())
        x = 0.2 if mach == "lift" else 0.1
        y = m.initial_state(x, 8e6, 3e6)
        d0_on, d0_off = m.rhs(0.1, y.copy()), base.rhs(0.1, y.copy())
        assert d0_on == pytest.approx(d0_off, rel=1e-14, abs=1e-12)          # standstill: no leak
        v = 2.0 * prm["v_ref"]
        y[6] = v
        d_on, d_off = m.rhs(0.1, y.copy()), base.rhs(0.1, y.copy())
        V1, V2 = m.chamber_volumes(x)
        beta, f = m.p["beta"], math.sqrt(2.0)
        q2 = prm["c"] * f * (3e6 - m.p["Pd"])
        assert d_off[4] - d_on[4] == pytest.approx(beta * q2 / V2, rel=1e-9)
        q1 = prm["c"] * f * (8e6 - m.p["Pd"]) if both else 0.0
        assert d_off[3] - d_on[3] == pytest.approx(beta * q1 / V1, rel=1e-9, abs=1e-6)


@pytest.mark.parametrize("form", ["warming_bypass", "warming_viscous"])
def test_the_oil_warms_from_the_start_of_the_record_by_the_closed_form(form):
    effect = cat.FIFTH_FORMS[form]
    prm = cat.scaled_params("lift", effect, form, 1.0)
    eff = cat.make(effect, form, prm)
    k, dTm, tau = prm["k_T"], prm["dT_max"], prm["tau_T"]
    sign = 1.0 if form == "warming_bypass" else -1.0
    assert eff.factor(0.0) == 1.0                                   # the cold start
    assert eff.factor(dTm) == pytest.approx(math.exp(sign * k * dTm), rel=1e-12)
    # the state: nothing before t = 0, then dT_max (1 - exp(-t/tau_T)); held still for 40 s
    m = truth_model("lift", eff, Inputs(-2.0, 1e-2, [0.0] * 4202, [1.6e7] * 4202, [0.0] * 4202))
    y0 = m.initial_state(0.2, 3.5e6, 0.8e6)
    i = m.n_base

    def rhs(t, s):
        y = y0.copy()
        y[i] = s[0]
        dy = [0.0] * len(y)
        eff.more_derivatives(m, t, y, dy, 0.0)
        return [dy[i]]

    t = np.array([-2.0, -0.5, 0.0, 5.0, 15.0, 40.0])
    sol = solve_ivp(rhs, (-2.0, 40.0), [0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=0.05)
    ref = np.where(t > 0, dTm * (1 - np.exp(-np.maximum(t, 0) / tau)), 0.0)
    np.testing.assert_allclose(sol.y[0], ref, atol=1e-6)
    assert sol.y[0, 4] == pytest.approx(dTm * (1 - math.exp(-1)), rel=1e-6)   # 63 % at tau_T
    # the law the truth sees, at a warmed state
    y = y0.copy()
    y[i], y[6] = 12.0, 0.05
    m._y = y
    if form == "warming_bypass":
        q = eff.leakages(m, 9e6, 2e6)
        assert q == (pytest.approx(prm["c0"] * math.exp(k * 12.0) * 7e6, rel=1e-12), 0.0, 0.0)
    else:
        F = eff.extra_friction(m, 0.05, 0.0, 0.0)
        assert F == pytest.approx(prm["b0"] * math.exp(-k * 12.0) * 0.05, rel=1e-12)


def test_gas_pocket_keeps_the_closed_chamber_volume_and_charges_as_an_rc_branch():
    prm = {"V_gA": 1e-4, "R_A": 5e10, "V_gB": 3e-5, "R_B": 8e10}
    eff = cat.make("entrained_air", "pocket_behind_orifice", prm)
    # valve closed, piston locked (huge mass, no weight), no leak: the oil the chamber loses
    # compresses the gas by as much, V_A P_A / beta - V_g P_ref / P_g = const (isothermal gas),
    # and both pressures meet
    m = truth_model("lift", eff, still_inputs(3.0), m=1e20, W=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    y0 = m.initial_state(0.2, 6e6, 2e6)
    i, beta = m.n_base, m.p["beta"]
    y0[i], y0[i + 1] = 4e6, 3e6                                  # the pockets start off balance
    t = np.linspace(0.0, 3.0, 301)
    sol = m.simulate(t, y0, rtol=1e-10, atol=1e-4 * m.default_atol())
    assert sol.success
    V = m.chamber_volumes(0.2)
    for k, Vg in ((0, 1e-4), (1, 3e-5)):
        inv = V[k] * sol.y[3 + k] / beta - Vg * 1e5 / sol.y[i + k]
        np.testing.assert_allclose(inv, inv[0], rtol=1e-9)
        assert sol.y[3 + k, -1] == pytest.approx(sol.y[i + k, -1], abs=20.0)
    assert sol.y[3, -1] < 6e6 - 5e5 and sol.y[4, -1] > 2e6 + 2e5
    # held chamber pressure, a small step: the pocket follows at 1/(R C_g), C_g = V_g P_ref / P^2
    fake = SimpleNamespace(n_base=9)
    P, Pg0 = 5e6, 5e6 * 0.999
    tau = prm["R_A"] * prm["V_gA"] * 1e5 / P ** 2

    def rhs(tt, s):
        y = np.zeros(11)
        y[3] = y[4] = P
        y[9:] = s
        dy = [0.0] * 11
        eff.more_derivatives(fake, tt, y, dy, 0.0)
        return dy[9:]

    tq = np.array([0.5, 1.0, 2.0]) * tau
    sol = solve_ivp(rhs, (0, tq[-1]), [Pg0, P], t_eval=tq, rtol=1e-11, atol=1e-6)
    np.testing.assert_allclose(P - sol.y[0], (P - Pg0) * np.exp(-tq / tau), rtol=2e-3)
    assert np.all(sol.y[1] == P)                                     # B balanced: no flow
    assert eff.leakages(SimpleNamespace(n_base=9, _y=np.r_[np.zeros(3), P, P, np.zeros(4), Pg0, P]),
                        P, P) == (0.0, pytest.approx((P - Pg0) / prm["R_A"]), 0.0)


def test_clearance_carries_no_force_inside_the_band_and_k_beyond_it():
    prm = cat.scaled_params("eha", "load_compliance", "pin_clearance", 1.0)
    eff = cat.make("load_compliance", "pin_clearance", prm)
    k, c, b = prm["k"], prm["c"], prm["b"]
    w = b / 20.0
    assert eff.joint_force(0.0, 0.0) == 0.0 and abs(eff.joint_force(0.0, 0.3)) < 1e-3 * c * 0.3
    for d in (0.1 * b, 0.25 * b, -0.25 * b):                          # inside: < 1 % of k w
        assert abs(eff.joint_force(d, 0.0)) < 1e-2 * k * w
        assert abs(eff.joint_force(d, 0.01) - eff.joint_force(d, 0.0)) < 1e-2 * c * 0.01
    for d in (b, 2 * b, -b, -3 * b):                                  # beyond: k (d -+ b/2), damped
        ref = k * (d - math.copysign(0.5 * b, d))
        assert eff.joint_force(d, 0.0) == pytest.approx(ref, rel=1e-4)
        assert eff.joint_force(d, 0.01) - eff.joint_force(d, 0.0) == pytest.approx(c * 0.01, rel=1e-4)
    assert eff.dead_zone(0.5 * b) == (pytest.approx(w * math.log(2.0)), pytest.approx(0.5, abs=1e-4))
    stiff = cat.make("load_compliance", "pin_clearance", {**prm, "b": 0.0})
    assert stiff.joint_force(1e-5, 2e-3) == pytest.approx(k * 1e-5 + c * 2e-3, rel=1e-12)
    # the truth: at rest with no load the joint stays where it is (no force), on both sides
    m = truth_model("eha", eff, still_inputs(), kc_p=0.0, kc_m=0.0, ks_p=0.0, ks_m=0.0)
    y = m.initial_state(0.07, 5e6)
    y[m.n_base] = 0.07 - 0.2 * b
    dy = m.rhs(0.1, y.copy())
    assert abs(dy[m.n_base + 1]) < 1e-2 * k * w / m.p["m"]


def test_moving_average_of_a_ramp_is_the_ramp_delayed_by_half_the_window():
    dt, T = 1e-3, 0.023
    n = 1001
    t = dt * np.arange(n)
    u = 40.0 * t - 3.0
    inp = Inputs(0.0, dt, u, [1.6e7] * n, [0.0] * n)
    eff = cat.make("input_delay", "moving_average", {"T": T})
    m = truth_model("lift", eff, inp)
    for tq in (0.1, 0.2345, 0.9):
        ud, dud = eff.command(m, tq, None, 0.0, 0.0)
        assert ud == pytest.approx(40.0 * (tq - 0.5 * T) - 3.0, abs=1e-9)
        assert dud == pytest.approx(40.0, rel=1e-9)
    # before the record the command is its first value: half the window at -3
    ud, _ = eff.command(m, 0.5 * T, None, 0.0, 0.0)
    assert ud == pytest.approx((-3.0 * 0.5 * T + (-3.0 + 0.5 * 40.0 * 0.5 * T) * 0.5 * T) / T, abs=1e-9)
    # a sine (finely sampled): the analytic mean over the window
    dt = 1e-4
    n = 10001
    t = dt * np.arange(n)
    w = 2 * math.pi * 7.0
    inp = Inputs(0.0, dt, 10.0 * np.sin(w * t), [1.6e7] * n, [0.0] * n)
    m = truth_model("lift", eff, inp)
    for tq in (0.31, 0.777):
        ref = 10.0 * (math.cos(w * (tq - T)) - math.cos(w * tq)) / (w * T)
        assert eff.command(m, tq, None, 0.0, 0.0)[0] == pytest.approx(ref, abs=2e-5)
    # the closed loop's command history (bench._Live): the same mean of its points
    live = _Live()
    for tt in np.linspace(0.0, 0.2, 137):
        live.push(float(tt), 40.0 * float(tt) - 3.0)
        live.u = 40.0 * float(tt) - 3.0
    m.inputs = live
    assert eff.command(m, 0.2, None, 0.0, 0.0)[0] == pytest.approx(40.0 * (0.2 - 0.5 * T) - 3.0, abs=1e-9)
    off = cat.make("input_delay", "moving_average", {"T": 0.0})
    assert off.command(m, 0.1, None, 1.25, 3.0) == (1.25, 3.0)


def test_differenced_velocity_is_the_slope_of_a_ramp_and_the_difference_of_a_sine():
    T = 0.02
    eff = cat.make("sensor_lag", "differenced_velocity", {"T": T})
    t = 1e-3 * np.arange(500)
    v = eff.differenced(t, 0.3 * t + 0.05)
    np.testing.assert_allclose(v[20:], 0.3, rtol=1e-9)
    np.testing.assert_allclose(v[:20], 0.3 * t[:20] / T, rtol=1e-9, atol=1e-12)   # held before the start
    w = 2 * math.pi * 9.0
    v = eff.differenced(t, np.sin(w * t))
    np.testing.assert_allclose(v[20:], (np.sin(w * t[20:]) - np.sin(w * (t[20:] - T))) / T, atol=1e-9)
    # in the truth: v from the simulated position, the rest as the base truth records it
    dt, Tr = 1e-3, 0.4
    n = int(Tr / dt) + 2
    tt = dt * np.arange(n)
    inp = Inputs(0.0, dt, 8.0 * np.sin(2 * math.pi * 3.0 * tt), [1.6e7] * n, [0.0] * n)
    m = truth_model("lift", eff, inp)
    sol = m.simulate(tt[:-1], m.initial_state(0.15, 3.5e6, 0.8e6))
    out = m.measured(sol.y)
    np.testing.assert_allclose(out["v"], eff.differenced(tt[:-1], sol.y[5]), rtol=1e-12)
    base = ActuatorTruth(dict(m.p), None, inp)
    ref = base.measured(base.simulate(tt[:-1], base.initial_state(0.15, 3.5e6, 0.8e6)).y)
    for k in ("P1", "P2", "x"):
        np.testing.assert_allclose(out[k], ref[k], rtol=1e-12)
    with pytest.raises(ValueError):
        m.measured(sol.y[:, :50])


def test_compensator_holds_the_set_pressure_in_steady_flow_and_dips_by_k_q_after_a_step():
    prm = {"k": 2e10, "tau_c": 0.1}
    eff = cat.make("supply_pressure_drop", "compensator_dip", prm)
    q = 3e-4
    fake = SimpleNamespace(n_base=9, valve_flows=lambda xv, Ps, PA, PB: (0.0, 0.0, q))
    Ps = 1.6e7

    def P_valve(z):
        return eff.valve_pressure(fake, np.r_[np.zeros(9), z], Ps)

    assert P_valve(q) == pytest.approx(Ps, abs=1e-2)                  # steady: no droop
    assert P_valve(0.0) == pytest.approx(Ps - 2e10 * q, abs=1e-2)     # the step: k q

    def rhs(t, s):
        y = np.r_[np.zeros(9), s]
        dy = [0.0] * 10
        eff.more_derivatives(fake, t, y, dy, q)
        return dy[9:]

    tq = np.array([0.05, 0.1, 0.3])
    sol = solve_ivp(rhs, (0, 0.3), [0.0], t_eval=tq, rtol=1e-11, atol=1e-14)
    dips = [Ps - P_valve(z) for z in sol.y[0]]
    np.testing.assert_allclose(dips, 2e10 * q * np.exp(-tq / 0.1), rtol=1e-7)
    # on the lift truth: the valve's pressure and its supply flow solve P = Ps - k (q(P) - z)
    m = truth_model("lift", eff, still_inputs())
    y = m.initial_state(0.2, 5e6, 1e6)
    y[1], y[m.n_base] = 30.0, 1e-4
    Pv = eff.valve_pressure(m, y, Ps)
    qv = m.valve_flows(30.0, Pv, y[3], y[4])[2]
    assert Pv == pytest.approx(Ps - 2e10 * (qv - 1e-4), abs=1.0)
    assert Pv < Ps - 1e6
    assert cat.make("supply_pressure_drop", "compensator_dip", {"k": 0.0, "tau_c": 0.1}).valve_pressure(m, y, Ps) == Ps


# ---- (b) off and (c) on against the base truth -------------------------------------------------
def _run(machine, effect, form, T=0.4):
    B = MACHINES[machine].bench
    return sine_run(machine, effect, form, (B["x_home"], B["P0"], B["PB0"]), 8.0, T)


OFF = {"film_drag_out": {"c": 0.0}, "warming_bypass": {"c0": 0.0}, "warming_viscous": {"b0": 0.0},
       "pocket_behind_orifice": {"V_gA": 0.0, "V_gB": 0.0}, "moving_average": {"T": 0.0},
       "differenced_velocity": {"T": 0.0}, "compensator_dip": {"k": 0.0}}
# the clearance: at b = 0 a stiff pin (its mode far above the recordings' band) is left
LIMIT = {"pin_clearance": ("b", (0.1, 0.0))}
ONE_MACHINE = {"film_drag_out": "lift", "warming_bypass": "eha", "warming_viscous": "winch",
               "pocket_behind_orifice": "rotary", "pin_clearance": "eha", "moving_average": "lift_cbv",
               "differenced_velocity": "rotary", "compensator_dip": "winch"}


def test_every_form_has_an_off_check():
    assert set(OFF) | set(LIMIT) == set(cat.FIFTH_FORMS) == set(ONE_MACHINE)


@pytest.mark.parametrize("form", sorted(OFF))
def test_switched_off_the_form_is_the_base_truth(form):
    effect = cat.FIFTH_FORMS[form]
    machine = ONE_MACHINE[form]
    prm = {**cat.scaled_params(machine, effect, form, 1.0), **OFF[form]}
    on, Y = _run(machine, cat.make(effect, form, prm), form)
    off, Y0 = _run(machine, None, form)
    # the oil's warming is a state that evolves whatever the coefficient: the solver's steps differ
    # (by far less than its tolerances: atol 1e-7 m/s on v)
    rtol = 1e-6 if form.startswith("warming") else 1e-9
    np.testing.assert_allclose(Y, Y0, rtol=rtol, atol=rtol * np.max(np.abs(Y0)))
    for k in ("P1", "P2", "x", "v"):
        np.testing.assert_allclose(on[k], off[k], rtol=rtol, atol=1e-12 + rtol * np.max(np.abs(off[k])))


def _err(form, machine, prm):
    return deviation(_run, machine, form, prm)


@pytest.mark.parametrize("form", sorted(LIMIT))
def test_towards_its_limit_the_form_approaches_the_base_truth(form):
    effect, machine = cat.FIFTH_FORMS[form], ONE_MACHINE[form]
    key, (f2, f3) = LIMIT[form]
    prm = cat.scaled_params(machine, effect, form, 1.0)
    e1 = _err(form, machine, prm)
    e2 = _err(form, machine, {**prm, key: prm[key] * f2})
    e3 = _err(form, machine, {**prm, key: prm[key] * f3})
    assert e3 < e2 < e1 and e3 < 0.25 * e1, (e1, e2, e3)


def _esr(form, machine):
    return esr(_run, machine, form)


@pytest.mark.parametrize("form", sorted(ONE_MACHINE))
def test_at_its_nominal_size_the_form_changes_the_recording(form):
    esr = _esr(form, ONE_MACHINE[form])
    assert max(esr.values()) > 0.02, esr                 # percent


@pytest.mark.slow
@pytest.mark.parametrize("machine,form", [(m, f) for f, e in FIFTH for m in cat.FORMS[e][f][1]],
                         ids=[f"{m}/{f}" for f, e in FIFTH for m in cat.FORMS[e][f][1]])
def test_fifth_form_runs_and_acts_on_every_machine_that_carries_it(machine, form):
    esr = _esr(form, machine)
    assert max(esr.values()) > 0.01, (machine, form, esr)
