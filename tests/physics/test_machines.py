"""The example machines of seeds 001 (SARCOS elbow) and the Festo TP511 rig build, simulate and
show the physics they are meant to reproduce."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.errors import SolverError
from hydrocli.experiments.experiment_file import load_experiment_files
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]
MACHINES = ["sarcos_elbow", "sarcos_elbow_braced", "festo_tp511", "festo_tp511_no_endstops"]


def _model(name):
    return build_model(load_netlist(ROOT / "machines" / f"{name}.yaml"))


@pytest.mark.parametrize("name", MACHINES)
def test_machine_builds_without_warnings(name):
    m = _model(name)
    assert m.state_names and not m.warnings


def test_braced_sarcos_decreasing_amplitude_loop_fig2():
    """Seed 001 Fig. 2 / §5: a decaying sinusoidal current traces shrinking hysteresis loops
    between input and virtual current, and the braced load pressure follows them."""
    m = _model("sarcos_elbow_braced")
    t = np.linspace(0.0, 40.0, 4001)
    cur = 0.3 * np.exp(-t / 12.0) * np.sin(t)
    tr = simulate(m, InputTable(t, cur[:, None]), t, opts=SolverOptions(rtol=1e-6))
    ih = tr.Y[:, m.output_names.index("i_hys")]
    pl = tr.Y[:, m.output_names.index("P_load")]
    k = np.where(np.sign(cur[:-1]) != np.sign(cur[1:]))[0][1:]
    widths = np.abs(ih[k])                      # virtual current left when the input crosses 0
    assert widths[0] > 0.01
    # non-increasing (the first loops of 0.3 A are saturated and equal), then shrinking
    assert np.all(np.diff(widths[::2]) < 1e-3) and np.all(np.diff(widths[1::2]) < 1e-3)
    assert widths[-1] < 0.3 * widths[0]
    # load pressure at zero input is the hysteresis offset, not zero, and shrinks with it
    assert abs(pl[k[0]]) > 5 * abs(pl[k[-1]])


def test_sarcos_static_currents_hold_the_load():
    """Constant current → constant load pressure → the load settles where D_v·P_load
    balances W·sin θ within the Coulomb friction (seed 001 §5.2)."""
    m = _model("sarcos_elbow")
    t = np.linspace(0.0, 10.0, 201)
    for i0 in (0.05, 0.1):
        tr = simulate(m, InputTable.constant(m, values={"i": i0}), t, opts=SolverOptions(rtol=1e-6))
        y = dict(zip(m.output_names, tr.Y[-1]))
        d_v, w = m.p0[m.param_index("vane.D_v")], m.p0[m.param_index("gravity.W")]
        tc = m.p0[m.param_index("vane_friction.tau_c")] + m.p0[m.param_index("load_friction.tau_c")]
        assert np.ptp(tr.Y[-20:, m.output_names.index("theta")]) < 5e-3      # (nearly) at rest
        # statics with Coulomb friction: |D_v·P_load − W·sin θ| ≤ τ_c,vane + τ_c,load
        assert abs(d_v * y["P_load"] - w * np.sin(y["theta"])) <= tc
        assert d_v * y["P_load"] > tc                                   # and the load is lifted


def test_festo_step_reaches_end_stop_at_supply_pressure():
    m = _model("festo_tp511")
    t = np.linspace(0.0, 2.0, 201)
    tab = InputTable(np.array([0.0, 0.1, 0.1001, 3.0]), np.array([[0.0], [0.0], [5.0], [5.0]]))
    tr = simulate(m, tab, t, opts=SolverOptions(rtol=1e-6))
    y = dict(zip(m.output_names, tr.Y[-1]))
    ps = m.p0[m.param_index("supply.p")]
    assert y["x"] == pytest.approx(0.2, abs=1e-3)
    assert y["pA"] == pytest.approx(ps, rel=0.01)


@pytest.mark.parametrize("machine, exp", [("sarcos_elbow_braced", "sarcos/braced_sine.yaml"),
                                          ("sarcos_elbow", "sarcos/static.yaml"),
                                          ("sarcos_elbow", "sarcos/dynamic.yaml")])
def test_sarcos_experiments_load(machine, exp):
    es = load_experiment_files(ROOT / "experiments" / exp, _model(machine))
    assert es and all(len(e.t_out) > 100 for e in es)


def test_festo_experiments_reference_the_shared_recordings():
    if not (ROOT.parent / "shared" / "real" / "festo_tp511").is_dir():
        pytest.skip("shared recordings not available")
    m = _model("festo_tp511")
    es = load_experiment_files(ROOT / "experiments" / "festo" / "steps_pA.yaml", m)
    assert [e.name for e in es] == [f"festo_pA_{w}V" for w in range(1, 6)]
    e = es[4]
    # the sensor reads 5.55 mm at the retracted stop (offset removed in the experiment file)
    # and clips at 9.9988 V = 199.98 mm raw, i.e. 194.4 mm after the offset (docs/festo.md)
    assert np.nanmax(e.measured["x"]) == pytest.approx(0.19998 - 0.00555, abs=2e-3)
    assert abs(np.median(e.measured["x"][:40])) < 1e-3


def test_vane_held_against_its_stop_compresses_it_by_the_net_torque_over_the_stiffness(tmp_path):
    """The vane actuator's stop (theta_max, k_stop, off while k_stop = 0): driven open into it at
    constant supply the vane comes to rest where the stop carries the hydraulic torque less
    the weight moment, k·(θ − θ_max) = D_v·(p₁ − p₂) − W·sin θ (± the shaft's Coulomb
    friction), read from the simulated pressures; without the stop it swings past."""
    text = (ROOT / "machines" / "rotary_drive.yaml").read_text().replace(
        "    R_v: {value: 0.0, free: false}",
        "    R_v: {value: 0.0, free: false}\n    theta_max: 0.3\n    k_stop: \"2.0e4 N*m/rad\"\n    c_stop: 500.0")
    (tmp_path / "stopped.yaml").write_text(text)
    t = np.linspace(0.0, 4.0, 401)
    tab = InputTable(np.array([0.0, 0.1, 0.11, 5.0]), np.array([[0.0, 1e7], [0.0, 1e7], [30.0, 1e7], [30.0, 1e7]]))
    free = _model("rotary_drive")
    try:
        y_free = simulate(free, tab, t, opts=SolverOptions(rtol=1e-6)).Y
    except SolverError as err:              # runs on until a chamber empties
        y_free = err.partial.Y
    m = build_model(load_netlist(tmp_path / "stopped.yaml"))
    tr = simulate(m, tab, t, opts=SolverOptions(rtol=1e-6))
    y = dict(zip(m.output_names, tr.Y[-1]))
    P = {n: m.p0[m.param_index(n)] for n in ("vane.D_v", "gravity.W", "friction.tau_c", "vane.k_stop")}
    assert np.ptp(tr.Y[-50:, m.output_names.index("theta")]) < 1e-4                     # at rest on the stop
    net_torque = P["vane.D_v"] * (y["P1"] - y["P2"]) - P["gravity.W"] * np.sin(y["theta"])
    assert net_torque > 10 * P["friction.tau_c"]                                          # pressing into it
    assert P["vane.k_stop"] * (y["theta"] - 0.3) == pytest.approx(net_torque, abs=P["friction.tau_c"])
    assert y_free[:, free.output_names.index("theta")].max() > 0.35                      # free: swings past
