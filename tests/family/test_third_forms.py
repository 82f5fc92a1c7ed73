"""The third truth forms (experiments/family/truth/third_forms.py) against independent
references: the isothermal gas law, the laminar leak law inside / outside a scored band, the
seal-friction and exponential Stribeck formulas, a zero-order hold with one sample of delay, a
first-order lag's 63 % point, volume continuity of a closed hose + chamber, a spring's static
deflection F/k and two orifices in series."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from experiments.concealed.truth.eha import K_RL, Inputs
from experiments.family import catalogue as cat
from experiments.family.generate import _truth
from experiments.family.machines import MACHINES
from experiments.family.truth.actuator import ActuatorTruth
from truthruns import still_inputs, truth_model

THIRD = sorted(cat.THIRD_FORMS.items())


def test_third_forms_are_in_the_catalogue_after_the_first_two():
    later = {**cat.FOURTH_FORMS, **cat.FIFTH_FORMS}
    for form, effect in THIRD:        # (the fourth and fifth forms, catalogue.FOURTH/FIFTH_FORMS, come after)
        assert [f for f in cat.FORMS[effect] if f not in later][-1] == form
        for m in MACHINES:
            fs = [f for f in cat.forms_of(m, effect) if f not in later]
            assert len([f for f in fs if f not in cat.THIRD_FORMS]) in (0, 2)
        assert "winch" not in cat.FORMS[effect][form][1]
        assert cat.FORMS[effect][form][0].name == effect


def test_the_third_forms_are_generated_only_when_named():
    """The commands that wrote the earlier dev and held-out sets must write the same cases:
    without ``--forms`` no third form is listed; named, only those forms are."""
    from experiments.family.generate import all_cases
    machines = ["lift", "lift_cbv", "rotary", "eha"]
    default = all_cases(machines, [88, 89], "all")
    assert default and not [c for c in default if c[2] in cat.THIRD_FORMS]
    named = all_cases(machines, [95], "all", forms=["scored_bore", "rounded"])
    assert {c[2] for c in named} == {"scored_bore", "rounded"}
    assert {c[1] for c in named} == {"internal_leakage", "valve_overlap"}


@pytest.mark.parametrize("P", [3e6, 1.2e7])
def test_air_pocket_capacitance_is_the_isothermal_gas_law(P):
    eff = cat.make("entrained_air", "pocket_chamber_A", {"V_g0": 2e-4})
    m = truth_model("lift", eff, still_inputs())
    x = 0.2
    V_A = m.p["V10"] + m.p["A_A"] * x
    h = 1e-4 * P                                  # -dV_g/dP of V_g = V_g0 p_ref / P (central difference)
    dVg = -(2e-4 * 1e5 / (P + h) - 2e-4 * 1e5 / (P - h)) / (2 * h)
    assert eff.capacitance_A(m, x, P) == pytest.approx(V_A / m.p["beta"] + dVg, rel=1e-6)
    # the truth's chamber A follows dP_A/dt = (net inflow) / C_A; chamber B is untouched
    ref = ActuatorTruth(dict(m.p), None, still_inputs())
    y = ref.initial_state(x, P, 2e6)
    y[6] = 0.03
    d_on, d_off = m.rhs(0.1, y.copy()), ref.rhs(0.1, y.copy())
    net = d_off[3] * V_A / m.p["beta"]
    assert d_on[3] == pytest.approx(net / eff.capacitance_A(m, x, P), rel=1e-9)
    assert d_on[4] == d_off[4]


def test_scored_bore_leaks_laminar_inside_the_band_and_not_outside():
    prm = cat.scaled_params("lift", "internal_leakage", "scored_bore", 1.0)
    eff = cat.make("internal_leakage", "scored_bore", prm)
    fake = SimpleNamespace(_y=np.zeros(9))
    P1, P2 = 9e6, 2e6
    fake._y[5] = 0.5 * (prm["x1"] + prm["x2"])
    assert eff.leakages(fake, P1, P2)[0] == pytest.approx(prm["c"] * (P1 - P2), rel=1e-4)
    for x in (0.08, 0.12, 0.38, 0.42):
        fake._y[5] = x
        assert abs(eff.leakages(fake, P1, P2)[0]) < 1e-5 * prm["c"] * (P1 - P2)
    fake._y[5] = prm["x1"]                        # an edge: half open
    assert eff.leakages(fake, P1, P2)[0] == pytest.approx(0.5 * prm["c"] * (P1 - P2), rel=1e-3)
    # the band is the middle third of the setpoint range, the edges ~1 % of the stroke
    lo, hi = MACHINES["lift"].bench["setpoint_range"]
    assert prm["x1"] == pytest.approx(lo + (hi - lo) / 3, abs=2e-3)
    assert prm["x2"] == pytest.approx(hi - (hi - lo) / 3, abs=2e-3)


def test_both_seals_friction_is_the_gauge_pressure_formula():
    eff = cat.make("pressure_dependent_friction", "both_seals_gauge", {"mu": 0.02, "eps2": 0.002})
    m = truth_model("lift", eff, still_inputs())
    AA, AB, Pd = m.p["A_A"], m.p["A_B"], m.p["Pd"]
    PA, PB, v = 8e6, 1.5e6, 0.004
    ref = 0.02 * (AA * (PA - Pd) + AB * (PB - Pd)) * math.tanh(v / 0.002)
    assert eff.extra_friction(m, v, PA, PB) == pytest.approx(ref, rel=1e-12)
    assert eff.extra_friction(m, -v, PA, PB) == pytest.approx(-ref, rel=1e-12)
    # a rotary vane: one displacement on both sides
    mr = truth_model("rotary", eff, still_inputs(Ps=1e7))
    D = mr.p["A_A"]
    assert eff.extra_friction(mr, 1.0, 5e6, 4e6) == pytest.approx(0.02 * D * (9e6 - 2e5), rel=1e-9)


def test_exponential_stribeck_is_fs_over_e_at_vs():
    Fs, vs = 800.0, 0.005
    eff = cat.make("stribeck_friction", "exponential", {"Fs": Fs, "vs": vs, "v_eps": 1e-5})
    assert eff.extra_friction(None, vs, 0.0, 0.0) == pytest.approx(Fs / math.e, rel=1e-9)
    assert eff.extra_friction(None, -2 * vs, 0.0, 0.0) == pytest.approx(-Fs * math.exp(-2.0), rel=1e-9)
    assert eff.extra_friction(None, 0.0, 0.0, 0.0) == 0.0
    # the EHA's own (exponential) Stribeck term is zeroed in its base for this effect
    assert {k for k, *_ in cat.BASE_ZERO["eha"]["stribeck_friction"] if k} == {"ks_p", "ks_m"}


def test_sampled_controller_holds_the_one_sample_delayed_samples():
    dt, Ts, T = 1e-3, 0.01, 0.3
    n = int(T / dt) + 2
    t = dt * np.arange(n)
    u = 20.0 * np.sin(2 * math.pi * 4.0 * t) + 5.0 * np.cos(2 * math.pi * 11.0 * t)
    inp = Inputs(0.0, dt, u, [1.6e7] * n, [0.0] * n)
    eff = cat.make("input_delay", "sampled_controller", {"T_s": Ts})
    m = truth_model("lift", eff, inp)
    for tq in (0.0234, 0.05, 0.0999, 0.1731, 0.25):
        k = int(math.floor(tq / Ts + 1e-9))
        held = u[max(10 * (k - 1), 0)]            # the sample taken one period before the current one
        assert eff.command(m, tq, None, 0.0, 0.0) == (pytest.approx(held, abs=1e-12), 0.0)
    # integrated interval by interval, the spool reference follows the staircase through the
    # rate limiter (d xrl/dt = clip(K_RL (u_held - xrl), +-s_max)); reference: that ODE alone,
    # integrated over each hold interval
    y0 = m.initial_state(0.2, 3.5e6, 8e5)
    tt = t[:-1]
    sol = m.simulate(tt, y0)
    assert sol.success and sol.y.shape == (len(y0), len(tt))
    np.testing.assert_array_equal(sol.t, tt)
    smax = m.p["s_max"]
    xr, ref = 0.0, [0.0]
    for k in range(len(tt) // 10):
        held = u[max(10 * (k - 1), 0)]
        r = solve_ivp(lambda _, z: [min(max(K_RL * (held - z[0]), -smax), smax)], (k * Ts, (k + 1) * Ts),
                      [xr], t_eval=dt * np.arange(10 * k + 1, 10 * k + 11), rtol=1e-10, atol=1e-10)
        ref += list(r.y[0])
        xr = r.y[0, -1]
    np.testing.assert_allclose(sol.y[0], ref[:len(tt)], atol=5e-4)


def test_position_lag_reaches_63_percent_at_tau():
    tau = 0.015
    eff = cat.make("sensor_lag", "position_1st_order", {"tau_x": tau})
    fake = SimpleNamespace(n_base=9)
    x_step = 0.05

    def rhs(t, s):
        y = np.zeros(10)
        y[5], y[9] = x_step, s[0]
        dy = [0.0] * 10
        eff.more_derivatives(fake, t, y, dy, 0.0)
        return [dy[9]]

    sol = solve_ivp(rhs, (0.0, tau), [0.0], rtol=1e-10, atol=1e-14, t_eval=[0.5 * tau, tau])
    assert sol.y[0, -1] / x_step == pytest.approx(1 - math.exp(-1.0), rel=1e-6)
    Y = np.zeros((10, 2))
    Y[5], Y[9] = x_step, sol.y[0]
    out = {"x": None, "v": None, "P1": Y[7], "P2": Y[8]}
    eff.sensor_outputs(fake, Y, out)
    np.testing.assert_allclose(out["x"], sol.y[0])
    # the velocity read from the same transducer: d/dt of the lagged step, x_step/tau e^(-t/tau)
    np.testing.assert_allclose(out["v"], x_step / tau * np.exp(-np.array([0.5, 1.0])), rtol=1e-6)
    assert "rotary" not in cat.FORMS["sensor_lag"]["position_1st_order"][1]


def test_hose_on_line_a_conserves_volume_and_equalises():
    prm = cat.scaled_params("lift", "line_dynamics", "hose_A_only", 1.0)
    eff = cat.make("line_dynamics", "hose_A_only", prm)
    # valve closed (u = 0), piston locked (huge mass, no weight): the oil in the valve-end node
    # and in chamber A (+ the hose's cylinder-end half) only moves between them
    m = truth_model("lift", eff, still_inputs(3.0), m=1e20, W=0.0, kv_p=0.0, kv_m=0.0, kc_p=0.0, kc_m=0.0)
    x = 0.2
    y0 = m.initial_state(x, 4e6, 1e6)
    i = m.n_base
    y0[i] = 5e6                                   # valve-end node 10 bar above the chamber
    t = np.linspace(0.0, 3.0, 3001)
    sol = m.simulate(t, y0, rtol=1e-10)
    assert sol.success
    Ch = prm["V_h"] / prm["beta_h"]
    C1, CA = 0.5 * Ch, (m.p["V10"] + m.p["A_A"] * x) / m.p["beta"] + 0.5 * Ch
    stored = C1 * sol.y[i] + CA * sol.y[3]        # continuity: constant (in m^3 of oil)
    np.testing.assert_allclose(stored, stored[0], rtol=1e-6)
    P_end = (C1 * 5e6 + CA * 4e6) / (C1 + CA)
    assert sol.y[i, -1] == pytest.approx(P_end, abs=200.0)
    assert sol.y[3, -1] == pytest.approx(P_end, abs=200.0)
    assert np.ptp(sol.y[4]) < 1.0                 # line B is rigid and closed


def test_dry_damped_mount_static_deflection_is_f_over_k():
    prm = cat.scaled_params("lift", "structural_flexibility", "mount_dry_damped", 1.0)
    eff = cat.make("structural_flexibility", "mount_dry_damped", prm)
    F = 2.0e4
    assert eff.mount_force(F / prm["k_b"], 0.0) == pytest.approx(F, rel=1e-12)
    # the body under a constant piston force settles at F/k (dry friction does not hold it:
    # smoothed, it only creeps) and, in the truth's hook, sits still there
    sol = solve_ivp(lambda t, s: [s[1], (F - eff.mount_force(s[0], s[1])) / prm["m_b"]], (0, 3.0),
                    [0.0, 0.0], method="LSODA", rtol=1e-10, atol=1e-12)
    assert sol.y[0, -1] == pytest.approx(F / prm["k_b"], rel=1e-6)
    fake = SimpleNamespace(n_base=9, p={"m": 1500.0})
    y = np.zeros(11)
    y[9] = -F / prm["k_b"]                        # piston force Fp = F pushes the body back
    dy = [0.0] * 11
    eff.piston_accel(fake, y, F, 0.0, 0.0, dy)
    assert dy[10] == pytest.approx(0.0, abs=1e-9)


def test_cushion_is_two_orifices_in_series_on_the_outflow_only():
    prm = cat.scaled_params("lift", "end_stop", "hydraulic_cushion", 1.0)
    eff = cat.make("end_stop", "hydraulic_cushion", prm)
    m = truth_model("lift", eff, still_inputs())
    base = ActuatorTruth(dict(m.p), None, still_inputs())
    Ps, PA, PB = 1.6e7, 5e6, 1e7
    y = m.initial_state(prm["x_stop"], PA, PB)
    xv = 20.0
    a = m.p["Kv"] * xv / 100.0
    dp = PB - m.p["Pd"]
    # fully in the cushion: q = sqrt(dp) / sqrt(1/a^2 + 1/K_end^2)
    qb = eff.valve_flows(m, xv, Ps, y)[1]
    assert qb == pytest.approx(-math.sqrt(dp) / math.sqrt(a ** -2 + prm["K_end"] ** -2), rel=1e-3)
    assert -qb < 0.3 * a * math.sqrt(dp)          # the cushion throttles: chamber B's pressure rises
    # before the cushion (and for the inflow, through its check valve): the plain valve
    y[5] = prm["x_stop"] - prm["L_c"] - 1e-4
    assert eff.valve_flows(m, xv, Ps, y) == base.valve_flows(xv, Ps, PA, PB)
    y[5] = prm["x_stop"]
    assert eff.valve_flows(m, -xv, Ps, y) == base.valve_flows(-xv, Ps, PA, PB)


@pytest.mark.parametrize("form,effect", THIRD, ids=[f for f, _ in THIRD])
def test_third_form_runs_on_every_machine_that_carries_it(form, effect):
    """Each machine's nominal third form integrates (0.3 s, a moving valve)."""
    for machine, prm in cat.FORMS[effect][form][1].items():
        mt = MACHINES[machine]
        dt, n = 1e-3, 302
        t = dt * np.arange(n)
        u = 6.0 * np.sin(2 * math.pi * 3.0 * t)
        inp = Inputs(0.0, dt, u, [mt.bench["Ps0"]] * n, [0.0] * n)
        m = _truth(mt, dict(mt.nominal), cat.make(effect, form, prm), inp)
        B = mt.bench
        x0 = prm.get("x_stop", B["x_home"] + 0.01) - 0.01 if effect == "end_stop" else B["x_home"]
        y0 = (m.initial_state(x0, B["P0"], B["PB0"]) if isinstance(m, ActuatorTruth)
              else m.initial_state(x0, B["P0"]))
        sol = m.simulate(t[:-1], y0)
        assert sol.success and np.all(np.isfinite(sol.y)), (machine, form)
