"""Seed 001 §4.2.3, the actuator identification experiments reproduced on the model:
* leakage test (load braced, port 2 to a graduated cylinder at atmosphere, constant currents):
  the straight line through the (P_p1 − P_atm, Q) points gives back R_v (eq. 20);
* displacement from the torque/load-pressure plot (Fig. 7b, unbraced sine): the slope of the
  inclined segments is D_v (eq. 12), their offsets the vane's Coulomb friction."""
from hydrocli.experiments.initial import initial_state
from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_all
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]


def test_leakage_experiment_recovers_r_v():
    model = build_model(load_netlist(ROOT / "machines" / "sarcos_elbow_leakage.yaml"))
    r_v = model.p0[model.param_index("vane.R_v")]
    dp, q = [], []
    for exp in load_all(ROOT / "experiments" / "sarcos" / "leakage.yaml", model):
        tr = simulate(model, exp.inputs, exp.t_out, x0=initial_state(model, exp), opts=SolverOptions(rtol=1e-8))
        dp.append(tr.Y[-1, model.output_names.index("P_p1")] - 1e5)
        q.append(tr.Y[-1, model.output_names.index("Q_leak")])
        assert abs(tr.X[-1, model.state_names.index("vane_node.w")]) < 1e-6      # braced: at rest
    assert np.ptp(dp) > 20e5                                                     # distinct pressures
    slope, intercept = np.polyfit(dp, q, 1)
    assert slope == pytest.approx(r_v, rel=1e-4)                                 # eq. 20
    assert abs(intercept) < 1e-4 * max(q)


def test_torque_versus_load_pressure_gives_the_displacement():
    model = build_model(load_netlist(ROOT / "machines" / "sarcos_elbow.yaml"))
    d_v, tau_c = model.p0[model.param_index("vane.D_v")], model.p0[model.param_index("vane_friction.tau_c")]
    exp, = load_all(ROOT / "experiments" / "sarcos" / "dynamic.yaml", model)
    tr = simulate(model, exp.inputs, exp.t_out, x0=initial_state(model, exp), opts=SolverOptions(rtol=1e-7))
    tau = tr.Y[:, model.output_names.index("tau_shaft")]
    p_load = tr.Y[:, model.output_names.index("P_load")]
    u = np.column_stack([np.interp(exp.t_out, exp.inputs.t, exp.inputs.U[:, k])
                         for k in range(exp.inputs.U.shape[1])])
    w = model.evaluate_along(exp.t_out, tr.X, u)["vane.w"]
    offsets = []
    for sign in (1, -1):                              # the two inclined segments of Fig. 7b
        moving = sign * w > 1e-3
        assert moving.sum() > 500
        slope, offset = np.polyfit(p_load[moving], tau[moving], 1)
        assert slope == pytest.approx(d_v, rel=0.02)  # eq. 12: τ = D_v·P_load (− friction)
        offsets.append(offset)
    assert offsets[0] < 0 < offsets[1]                # friction opposes the motion
    assert np.mean(np.abs(offsets)) == pytest.approx(tau_c, rel=0.25)
