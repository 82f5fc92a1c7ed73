"""The fourth truth forms (experiments/family/truth/fourth_forms.py) against independent
references: a poppet relief's flow (nothing below cracking, (P - P_cr) sqrt(P - Pd) above), the
cube law of an elastically opened clearance, a tight spot's friction levels, the invariant of
a closed chamber whose free air dissolves (P/beta - g P_atm/P), Hagen-Poiseuille and volume
continuity of a pipe, an underlapped spool's null flows, a variable delay's shifted input, a
second-order transducer's unit gain and step overshoot, a flow-limited pump's pressure deficit
and a bilinear mount's slopes. Then every form switched off (its zero, or its limit) against the
base truth, and switched on at its nominal size against it."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from experiments.concealed.truth.eha import Inputs, flow_law
from experiments.family import catalogue as cat
from experiments.family.generate import all_cases
from experiments.family.machines import MACHINES
from experiments.family.truth import fourth_forms as QF
from experiments.family.truth.actuator import ActuatorTruth
from truthruns import deviation, esr, sine_run, still_inputs, truth_model

FOURTH = sorted(cat.FOURTH_FORMS.items())


# ---- registration -----------------------------------------------------------------------------
def test_fourth_forms_are_registered_after_the_third_and_only_generated_when_named():
    assert 8 <= len(FOURTH) <= 10
    for form, effect in FOURTH:
        assert form in cat.FORMS[effect] and cat.FORMS[effect][form][0].name == effect
        earlier = [f for f in cat.FORMS[effect] if f not in cat.FOURTH_FORMS and f not in cat.FIFTH_FORMS]
        assert list(cat.FORMS[effect])[:len(earlier)] == earlier        # appended last
        assert form not in cat.THIRD_FORMS
        assert cat.FORMS[effect][form][2], form                        # calibrated in size
    assert {m for f, e in FOURTH for m in cat.FORMS[e][f][1]} == set(MACHINES)
    assert sum("winch" in cat.FORMS[e][f][1] for f, e in FOURTH) >= 8
    machines = list(MACHINES)
    default = all_cases(machines, [140, 141], "all")
    assert default and not [c for c in default if c[2] in cat.FOURTH_FORMS]
    named = all_cases(machines, [140], "all", forms=[f for f, _ in FOURTH])
    assert {c[2] for c in named} == set(cat.FOURTH_FORMS)


# ---- (a) the laws -----------------------------------------------------------------------------
def test_cracking_drain_is_shut_below_cracking_and_an_orifice_above():
    prm = cat.scaled_params("lift", "external_leakage", "cracking_drain", 1.0)
    eff = cat.make("external_leakage", "cracking_drain", prm)
    m = truth_model("lift", eff, still_inputs())
    Pcr, K, Pd = prm["P_cr"], prm["K_r"], m.p["Pd"]
    for P in (1e6, 0.5 * Pcr, Pcr - 1.0, Pcr):
        assert eff.drain(m, P) == 0.0
    for P in (Pcr + 1e5, Pcr + 2e6):
        assert eff.drain(m, P) == pytest.approx(K * (P - Pcr) * math.sqrt(P - Pd), rel=1e-12)
    assert eff.leakages(m, Pcr + 1e6, Pcr - 1e6) == (0.0, pytest.approx(K * 1e6 * math.sqrt(Pcr + 1e6 - Pd)), 0.0)
    # the leak drains chamber A in the truth: dP_A/dt drops by beta q / V_A, chamber B unchanged
    base = ActuatorTruth(dict(m.p), None, still_inputs())
    y = m.initial_state(0.2, Pcr + 1e6, 2e6)
    d_on, d_off = m.rhs(0.1, y.copy()), base.rhs(0.1, y.copy())
    V_A = m.p["V10"] + m.p["A_A"] * 0.2
    assert d_off[3] - d_on[3] == pytest.approx(m.p["beta"] * eff.drain(m, Pcr + 1e6) / V_A, rel=1e-9)
    assert d_on[4] == d_off[4]


def test_elastic_gap_leak_is_the_cube_of_the_opened_clearance():
    eff = cat.make("internal_leakage", "elastic_gap", {"c0": 2e-12, "p_h": 3e6})
    for dp in (1e3, 1.5e6, 3e6, -6e6):
        q = eff.leakages(None, 5e6 + dp, 5e6)[0]
        assert q == pytest.approx(2e-12 * (1 + abs(dp) / 3e6) ** 3 * dp, rel=1e-12)
    assert eff.leakages(None, 8e6, 5e6)[0] == pytest.approx(8 * 2e-12 * 3e6, rel=1e-12)   # h doubled
    assert eff.leakages(None, 5e6, 8e6)[0] == -eff.leakages(None, 8e6, 5e6)[0]
    assert eff.leakages(None, 5e6 + 10.0, 5e6)[0] == pytest.approx(2e-12 * 10.0, rel=1e-5)  # laminar near 0


def test_tight_spot_raises_the_directional_coulomb_level_over_its_band():
    prm = cat.scaled_params("lift", "coulomb_friction", "tight_spot", 1.0)
    eff = cat.make("coulomb_friction", "tight_spot", prm)
    fake = SimpleNamespace(_y=np.zeros(9))
    v = 0.05                                       # v >> v_c: tanh = 1
    mid = 0.5 * (prm["x1"] + prm["x2"])
    w_mid = (1 + math.exp(-(mid - prm["x1"]) / prm["d"])) ** -2    # both logistic edges
    assert w_mid > 0.998
    for x, w in ((0.12, 0.0), (0.40, 0.0), (mid, w_mid)):
        fake._y[5] = x
        assert eff.extra_friction(fake, v, 0, 0) == pytest.approx(prm["Fc_p"] * (1 + prm["a"] * w), rel=1e-4)
        assert eff.extra_friction(fake, -v, 0, 0) == pytest.approx(-prm["Fc_m"] * (1 + prm["a"] * w), rel=1e-4)
    fake._y[5] = prm["x1"]
    assert eff.extra_friction(fake, v, 0, 0) == pytest.approx(prm["Fc_p"] * (1 + 0.5 * prm["a"]), rel=1e-3)
    # the winch: once per drum revolution
    pw = cat.scaled_params("winch", "coulomb_friction", "tight_spot", 1.0)
    ew = cat.make("coulomb_friction", "tight_spot", pw)
    for th, w in ((0.0, 1.0), (math.pi, 0.0), (4 * math.pi, 1.0), (2.5 * math.pi, 0.5)):
        assert ew.level(1.0, th) == pytest.approx(pw["Fc_p"] * (1 + pw["a"] * w), abs=1e-12)


def test_dissolving_air_decays_at_tau_a_and_keeps_the_closed_chamber_invariant():
    prm = {"alpha0": 0.05, "B": 0.09, "P_sat": 1e5, "tau_r": 0.2, "tau_a": 0.5}
    eff = cat.make("entrained_air", "dissolving_free_air", prm)
    # valve closed, piston locked (huge mass, no weight), no leak: the free air dissolves and the
    # pressure falls; oil + gas fill the fixed chamber: the oil's compression V P/beta equals the
    # gas volume's growth, V P/beta - g V P_atm/P = const
    m = truth_model("lift", eff, still_inputs(2.0), m=1e20, W=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    y0 = m.initial_state(0.2, 6e6, 3e6)
    t = np.linspace(0.0, 1.5, 151)
    sol = m.simulate(t, y0, rtol=1e-10, atol=1e-4 * m.default_atol())
    assert sol.success
    i, beta = m.n_base, m.p["beta"]
    np.testing.assert_allclose(sol.y[i], 0.05 * np.exp(-t / 0.5), rtol=1e-5)     # above P_sat: g_eq = 0
    for k in (0, 1):
        inv = sol.y[3 + k] / beta - sol.y[i + k] * 1e5 / sol.y[3 + k]
        np.testing.assert_allclose(inv, inv[0], rtol=1e-7)
    assert sol.y[3, -1] < 6e6 - 1e5                                             # it did fall
    # below P_sat the air comes out, fast (tau_r), towards B (P_sat - P)/P_sat
    assert eff.g_dot(0.0, 0.5e5) == pytest.approx(0.09 * 0.5 / 0.2, rel=1e-12)
    assert eff.g_dot(0.01, 2e5) == pytest.approx(-0.01 / 0.5, rel=1e-12)


def test_rigid_pipe_is_hagen_poiseuille_in_steady_flow_and_conserves_volume():
    prm = cat.scaled_params("lift", "line_dynamics", "rigid_pipes_fdf", 1.0)
    eff = cat.make("line_dynamics", "rigid_pipes_fdf", prm)
    r, L, rho, nu = prm["r"], prm["L"], prm["rho"], prm["nu"]
    assert eff.R == pytest.approx(128 * rho * nu * L / (math.pi * (2 * r) ** 4), rel=1e-12)
    assert eff.I == pytest.approx(rho * L / (math.pi * r * r), rel=1e-12)
    q = 2e-4                                      # steady: drop R q, no unsteady friction left
    d = eff.pipe_derivs(1.5e9, q, 8e6 + eff.R * q, q, [0.0, 0.0, 0.0], 8e6)
    assert d[0] == 0.0 and abs(d[1]) * eff.I < 1e-9 * eff.R * q
    assert d[2:] == pytest.approx([m * d[1] for m in QF.TRIKHA_M], abs=1e-12)
    # a sudden pressure difference: all three unsteady states start at m_k dq/dt
    d = eff.pipe_derivs(1.5e9, 0.0, 9e6, 0.0, [0.0, 0.0, 0.0], 8e6)
    assert d[1] == pytest.approx(1e6 / eff.I) and d[2:] == pytest.approx([m * d[1] for m in QF.TRIKHA_M])
    # valve closed, piston locked: oil only moves between the valve-end node and the chamber
    m = truth_model("lift", eff, still_inputs(3.0), m=1e20, W=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    y0 = m.initial_state(0.2, 4e6, 1e6)
    i = m.n_base
    y0[i] = 5e6
    sol = m.simulate(np.linspace(0.0, 3.0, 301), y0, rtol=1e-10, atol=1e-3 * m.default_atol())
    assert sol.success
    V_A = m.p["V10"] + m.p["A_A"] * 0.2
    stored = 0.5 * eff.V * sol.y[i] + (V_A + 0.5 * eff.V) * sol.y[3]
    np.testing.assert_allclose(stored, stored[0], rtol=1e-8)
    P_end = stored[0] / (V_A + eff.V)
    assert sol.y[3, -1] == pytest.approx(P_end, abs=500.0) and sol.y[i, -1] == pytest.approx(P_end, abs=500.0)


def test_underlapped_spool_leaks_supply_to_tank_at_null_and_is_the_base_valve_at_zero():
    m = truth_model("lift", cat.make("valve_overlap", "underlap", {"U": 1.0}), still_inputs())
    Ps, PA, PB, Pd, dl, Kv = 1.6e7, 8e6, 6e6, m.p["Pd"], m.p["dp_lam"], m.p["Kv"]
    y = m.initial_state(0.2, PA, PB)
    qa, qb, qs = m.effect.valve_flows(m, 0.0, Ps, y)
    a = Kv * 1.0 / 100
    assert qa == pytest.approx(a * (flow_law(Ps - PA, dl) - flow_law(PA - Pd, dl)), rel=1e-12)
    assert qb == pytest.approx(a * (flow_law(Ps - PB, dl) - flow_law(PB - Pd, dl)), rel=1e-12)
    assert qs == pytest.approx(a * (flow_law(Ps - PA, dl) + flow_law(Ps - PB, dl)), rel=1e-12)
    qa, qb, qs = m.effect.valve_flows(m, 3.0, Ps, y)            # beyond U: shifted by U
    assert qa == pytest.approx(Kv * 4.0 / 100 * flow_law(Ps - PA, dl), rel=1e-12)
    assert qb == pytest.approx(-Kv * 4.0 / 100 * flow_law(PB - Pd, dl), rel=1e-12)
    off = cat.make("valve_overlap", "underlap", {"U": 0.0})
    for mach in ("lift", "winch"):
        mo = truth_model(mach, off, still_inputs())
        bo = ActuatorTruth(dict(mo.p), None, still_inputs())
        yo = mo.initial_state(0.2, PA, PB)
        for xv in (-30.0, -0.2, 0.0, 0.3, 40.0):
            assert off.valve_flows(mo, xv, Ps, yo) == pytest.approx(bo.valve_flows(xv, Ps, PA, PB), rel=1e-13, abs=1e-22)


def test_jitter_delay_shifts_the_input_by_the_drawn_delay():
    dt, T = 1e-3, 0.5
    n = int(T / dt) + 2
    t = dt * np.arange(n)
    u = 20.0 * np.sin(2 * math.pi * 4.0 * t) + 5.0 * np.cos(2 * math.pi * 11.0 * t)
    inp = Inputs(0.0, dt, u, [1.6e7] * n, [0.0] * n)
    prm = {"T_d": 0.01, "j": 0.4, "seed": 54}
    eff = cat.make("input_delay", "network_jitter", prm)
    m = truth_model("lift", eff, inp)
    ds = []
    for k in range(5, 40):                        # at the packets: d_k = T_d (1 + j r_k), r_k in [-1, 1)
        r = QF._unit(54, k)
        assert -1.0 <= r < 1.0
        d = eff.delay_and_rate(k * 0.01)[0]
        assert d == pytest.approx(0.01 * (1 + 0.4 * r), rel=1e-12)
        ds.append(d)
    assert min(ds) >= 0.006 and max(ds) <= 0.014 and np.std(ds) > 0.001
    for tq in (0.0567, 0.1234, 0.2999, 0.41):
        d, dd = eff.delay_and_rate(tq)
        assert abs(dd) <= 0.8
        ud, _ = eff.command(m, tq, None, 0.0, 0.0)
        assert ud == pytest.approx(float(np.interp(tq - d, t, u)), abs=1e-9)
    # seeded and counter-based: another instance, asked in another order, draws the same
    other = cat.make("input_delay", "network_jitter", prm)
    assert [other.delay_and_rate(x)[0] for x in (0.41, 0.0567)] == [eff.delay_and_rate(x)[0] for x in (0.41, 0.0567)]


@pytest.mark.parametrize("zeta", [0.1, 0.3])
def test_resonant_transducer_has_unit_gain_and_the_second_order_overshoot(zeta):
    f_n = 150.0
    eff = cat.make("sensor_lag", "resonant_pressure", {"f_n": f_n, "zeta": zeta})
    fake = SimpleNamespace(n_base=9)
    step = 1e6

    def rhs(t, s):
        y = np.zeros(13)
        y[7] = y[8] = step
        y[9:] = s
        dy = [0.0] * 13
        eff.more_derivatives(fake, t, y, dy, 0.0)
        return dy[9:]

    wd = 2 * math.pi * f_n * math.sqrt(1 - zeta ** 2)
    t = np.linspace(0.0, 0.2, 20001)
    sol = solve_ivp(rhs, (0, 0.2), [0.0] * 4, t_eval=t, rtol=1e-10, atol=1e-6)
    P = sol.y[0]
    assert P.max() / step - 1 == pytest.approx(math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2)), rel=1e-4)
    assert t[np.argmax(P)] == pytest.approx(math.pi / wd, abs=2e-5)
    assert P[-1] == pytest.approx(step, rel=1e-6)                   # unit static gain
    np.testing.assert_allclose(sol.y[2], P)                         # both transducers alike


def test_flow_limited_pump_deficit_grows_at_the_excess_flow_and_recovers_at_tau_c():
    prm = {"Q_max": 4.5e-4, "V_l": 1e-3, "tau_c": 0.02}
    eff = cat.make("supply_pressure_drop", "flow_limited_pump", prm)
    fake = SimpleNamespace(n_base=9, p={"beta": 1.5e9})
    C = 1e-3 / 1.5e9

    def dD(D, qs):
        y = np.zeros(10)
        y[9] = D
        dy = [0.0] * 10
        eff.more_derivatives(fake, 0.0, y, dy, qs)
        return dy[9]

    assert dD(0.0, 3e-4) == 0.0                    # the pump keeps up: no deficit
    assert dD(0.0, 5e-4) == pytest.approx(5e-5 / C, rel=1e-12)
    assert dD(2e5, 3e-4) == pytest.approx(-2e5 / 0.02, rel=1e-12)
    assert dD(2e5, 5e-4) == pytest.approx(5e-5 / C, rel=1e-12)      # still short: keeps falling
    assert eff.supply_at_valve(fake, np.r_[np.zeros(9), 3e5], 1.6e7) == 1.6e7 - 3e5
    # recovery of a deficit at low demand: D0 exp(-t/tau_c)
    sol = solve_ivp(lambda t, s: [dD(s[0], 1e-4)], (0, 0.05), [1e6], rtol=1e-10, atol=1e-6, t_eval=[0.02, 0.05])
    np.testing.assert_allclose(sol.y[0], 1e6 * np.exp(-np.array([1.0, 2.5])), rtol=1e-6)


def test_bilinear_mount_is_continuous_at_its_knee_with_the_two_slopes():
    for mach in ("eha", "lift"):
        prm = cat.scaled_params(mach, "structural_flexibility", "bilinear_mount", 1.0)
        eff = cat.make("structural_flexibility", "bilinear_mount", prm)
        k, r, Fk = prm["k_b"], prm["r"], prm["F_k"]
        dk = -Fk / k
        assert eff.mount_force(dk, 0.0) == pytest.approx(-Fk, abs=1e-9 * max(Fk, 1.0))
        h = 1e-6
        assert eff.mount_force(dk + h, 0.0) - eff.mount_force(dk, 0.0) == pytest.approx(k * h, rel=1e-6)
        assert eff.mount_force(dk, 0.0) - eff.mount_force(dk - h, 0.0) == pytest.approx(r * k * h, rel=1e-6)
        assert eff.mount_force(dk, 0.01) - eff.mount_force(dk, 0.0) == pytest.approx(prm["c_b"] * 0.01)
    e0 = cat.make("structural_flexibility", "bilinear_mount", cat.scaled_params("eha", "structural_flexibility",
                                                                                  "bilinear_mount", 1.0))
    assert e0.mount_force(0.0, 0.0) == 0.0                          # F_k = 0: tension vs compression
    assert e0.mount_force(-1e-4, 0.0) == pytest.approx(3 * e0.mount_force(1e-4, 0.0) * -1, rel=1e-12)


# ---- (b) off and (c) on against the base truth -------------------------------------------------
def _drive(form, machine):
    """A short open-loop run that reaches the form's regime: the chambers above the cracking
    pressure, the spool open far enough to draw more than the pump's limit, the stroke on the
    tight spot."""
    mt = MACHINES[machine]
    prm = cat.scaled_params(machine, cat.FOURTH_FORMS[form], form, 1.0)
    B = mt.bench
    x0, P0, PB0, amp = B["x_home"], B["P0"], B["PB0"], 8.0
    if form == "cracking_drain":
        P0 = PB0 = 1.1 * prm["P_cr"]
    if form == "flow_limited_pump":
        amp = 60.0
    if form == "tight_spot" and "x2" in prm:
        x0 = 0.5 * (prm["x1"] + prm["x2"])
    return x0, P0, PB0, amp


def _run(machine, effect, form, T=0.4):
    x0, P0, PB0, amp = _drive(form, machine)
    return sine_run(machine, effect, form, (x0, P0, PB0), amp, T)


OFF = {"cracking_drain": {"K_r": 0.0}, "elastic_gap": {"c0": 0.0}, "tight_spot": {"Fc_p": 0.0, "Fc_m": 0.0},
       "dissolving_free_air": {"alpha0": 0.0, "B": 0.0}, "underlap": {"U": 0.0}, "network_jitter": {"T_d": 0.0},
       "flow_limited_pump": {"Q_max": math.inf}}
# forms whose size is a limit: off is that limit, approached (the error shrinks with it)
LIMIT = {"rigid_pipes_fdf": ("L", 0.3), "resonant_pressure": ("f_n", 4.0), "bilinear_mount": ("k_b", 100.0)}
ONE_MACHINE = {"cracking_drain": "winch", "elastic_gap": "lift", "tight_spot": "lift_cbv",
               "dissolving_free_air": "rotary", "rigid_pipes_fdf": "eha", "underlap": "lift",
               "network_jitter": "winch", "resonant_pressure": "rotary", "flow_limited_pump": "eha",
               "bilinear_mount": "lift_cbv"}


def test_every_form_has_an_off_check():
    assert set(OFF) | set(LIMIT) == set(cat.FOURTH_FORMS) == set(ONE_MACHINE)


@pytest.mark.parametrize("form", sorted(OFF))
def test_switched_off_the_form_is_the_base_truth(form):
    effect = cat.FOURTH_FORMS[form]
    machine = ONE_MACHINE[form]
    prm = {**cat.scaled_params(machine, effect, form, 1.0), **OFF[form]}
    on, Y = _run(machine, cat.make(effect, form, prm), form)
    off, Y0 = _run(machine, None, form)
    np.testing.assert_allclose(Y, Y0, rtol=1e-9, atol=1e-9 * np.max(np.abs(Y0)))
    for k in ("P1", "P2", "x", "v"):
        np.testing.assert_allclose(on[k], off[k], rtol=1e-9, atol=1e-12 + 1e-9 * np.max(np.abs(off[k])))


def _err(form, machine, prm):
    return deviation(_run, machine, form, prm)


@pytest.mark.parametrize("form", sorted(LIMIT))
def test_towards_its_limit_the_form_approaches_the_base_truth(form):
    effect, machine = cat.FOURTH_FORMS[form], ONE_MACHINE[form]
    key, f = LIMIT[form]
    prm = cat.scaled_params(machine, effect, form, 1.0)
    e1 = _err(form, machine, prm)
    e2 = _err(form, machine, {**prm, key: prm[key] * f})
    e3 = _err(form, machine, {**prm, key: prm[key] * f * f})
    assert e3 < e2 < e1 and e3 < 0.25 * e1, (e1, e2, e3)


def _esr(form, machine):
    return esr(_run, machine, form)


@pytest.mark.parametrize("form", sorted(ONE_MACHINE))
def test_at_its_nominal_size_the_form_changes_the_recording(form):
    esr = _esr(form, ONE_MACHINE[form])
    assert max(esr.values()) > 0.02, esr                 # percent


@pytest.mark.slow
@pytest.mark.parametrize("machine,form", [(m, f) for f, e in FOURTH for m in cat.FORMS[e][f][1]],
                         ids=[f"{m}/{f}" for f, e in FOURTH for m in cat.FORMS[e][f][1]])
def test_fourth_form_runs_and_acts_on_every_machine_that_carries_it(machine, form):
    esr = _esr(form, machine)
    assert max(esr.values()) > 0.01, (machine, form, esr)
