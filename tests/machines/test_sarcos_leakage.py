"""Seed 001 §4.2.3: the actuator leakage test (load braced, port 2 to a graduated cylinder at
atmosphere, constant currents). The straight line through the (P_p1 − P_atm, Q) points of the
three currents must give back the vane's R_v (eq. 20), and the braced vane must be at rest."""
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
        tr = simulate(model, exp.inputs, exp.t_out, x0=exp.x0(model), opts=SolverOptions(rtol=1e-8))
        dp.append(tr.Y[-1, model.output_names.index("P_p1")] - 1e5)
        q.append(tr.Y[-1, model.output_names.index("Q_leak")])
        assert abs(tr.X[-1, model.state_names.index("vane_node.w")]) < 1e-6      # braced: at rest
    assert np.ptp(dp) > 20e5                                                     # distinct pressures
    slope, intercept = np.polyfit(dp, q, 1)
    assert slope == pytest.approx(r_v, rel=1e-4)                                 # eq. 20
    assert abs(intercept) < 1e-4 * max(q)
