"""Seed 002/003 harvester: the shipped machine and experiments simulate, the swing responds
to the Fig. 6 triangle with the sign and magnitude the motor/gearbox transduction (eq. 5)
dictates, and the joint PID (Fig. 7) tracks the stick sinusoid better than the open loop."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_experiment_file
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]


def _run(machine, experiment, overrides=None):
    model = build_model(load_netlist(ROOT / "machines" / machine))
    exp = load_experiment_file(ROOT / "experiments" / "harvester" / experiment, model)
    p = model.param_vector(overrides or {})
    tr = simulate(model, exp.inputs, exp.t_out, p=p, x0=model.x0, opts=SolverOptions(rtol=1e-6))
    return model, exp, tr, p


def test_swing_triangle_open_loop():
    model, exp, tr, p = _run("harvester.yaml", "swing_triangle.yaml")
    y = {n: tr.Y[:, i] for i, n in enumerate(model.output_names)}
    # swing follows the command's sign; boom and stick stay hydraulically locked
    k_up = np.argmin(np.abs(exp.t_out - 4.0))
    assert y["w_swing"][k_up] > 0.05
    assert y["q_swing"].max() > 0.3
    assert np.ptp(y["q_boom"]) < 2e-3 and np.ptp(y["q_stick"]) < 2e-3
    # eq. 5: the swing joint receives τ_sw = D_m·N·(p_A − p_B) minus the gear damping B_sw·q̇_sw
    u = np.column_stack([np.interp(exp.t_out, exp.inputs.t, col) for col in exp.inputs.U.T])
    vs = model.evaluate_along(exp.t_out, tr.X, u, p)
    d_m, n = p[model.param_index("sw_motor.D_m")], p[model.param_index("sw_gear.N")]
    w_sw = tr.X[:, model.state_index("arm.w1")]
    tau = d_m * n * (vs["sw_ma.p"] - vs["sw_mb.p"]) - 2.45e4 * w_sw
    assert np.max(np.abs(tau)) > 1e3
    assert np.allclose(vs["arm.tau1"], tau, rtol=1e-9, atol=1e-6 * np.max(np.abs(tau)))


def test_stick_pid_tracks_better_than_open_loop():
    off = {"stick_pid.Kp": 0.0, "stick_pid.Ki": 0.0, "stick_pid.Kd": 0.0}
    model, exp, tr_cl, _ = _run("harvester_closed_loop.yaml", "stick_sine_closed_loop.yaml")
    _, _, tr_ol, _ = _run("harvester_closed_loop.yaml", "stick_sine_closed_loop.yaml", off)
    k = model.output_names.index("stick_error")
    rms_cl = np.sqrt(np.mean(tr_cl.Y[:, k] ** 2))
    rms_ol = np.sqrt(np.mean(tr_ol.Y[:, k] ** 2))
    assert rms_cl < 0.25 * rms_ol
    assert rms_cl < np.radians(1.0)
