"""Batch over a process pool and over a Dask LocalCluster give the same table; steady-state
identification from plateau averages."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.solve.simulate import InputTable, SolverOptions

from synth import synthetic

OPTS = dict(max_evals=20, opts=SolverOptions(rtol=1e-6), outputs=["P1", "P2", "v"])


def _repeats(model, n=3):
    exps = []
    for i in range(n):
        p = model.p0.copy()
        p[model.param_index("valve.Kv")] *= 1.0 + 0.05 * i
        exps.append(synthetic(model, p, duration=0.8, seed=10 + i, name=f"rep{i + 1}"))
    return exps


def test_batch_process_pool_and_local_cluster_give_the_same_table(eha):
    distributed = pytest.importorskip("distributed")
    from hydrocli.identify.batch import run_batch
    _, model = eha
    exps = _repeats(model)
    pool = run_batch(model, exps, ["valve.Kv"], jobs=2, options=OPTS)
    kv = model.p0[model.param_index("valve.Kv")]
    assert np.allclose(pool.matrix()[:, 0] / kv, [1.0, 1.05, 1.10], rtol=0.01)
    s = pool.summary()
    assert np.isclose(s["mean"][0], pool.matrix()[:, 0].mean()) and s["std"][0] > 0
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        dask = run_batch(model, exps, ["valve.Kv"], scheduler=cluster.scheduler_address, options=OPTS)
    assert dask.csv_text() == pool.csv_text()
    rows = pool.csv_text().splitlines()
    assert rows[0].startswith("experiment,valve.Kv,cost") and [r.split(",")[0] for r in rows[-4:]] == ["mean", "std", "min", "max"]


def test_detect_plateaus_finds_the_flat_parts():
    from hydrocli.identify.steady import detect_plateaus
    t = np.arange(0, 3, 1e-3)
    y = np.where(t < 1, 0.0, np.where(t < 2, 1.0, 3.0)) + 0.001 * np.sin(50 * t)
    pl = detect_plateaus(t, {"y": y}, min_duration=0.2, tol=0.02, skip=0.0)
    assert len(pl) == 3
    assert [round(t[i0], 1) for i0, _ in pl] == [0.0, 1.0, 2.0]


LEVELS = [5, 10, 15, -5, -10, -15, 8, -8]


def _staircase(model, p):
    """Staircase valve command (both directions), constant supply and load: velocity plateaus."""
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.solve.simulate import simulate
    t = np.arange(0, 4.0, 1e-3)
    u = 0.01 * np.array(LEVELS)[np.minimum((t / 0.5).astype(int), len(LEVELS) - 1)]
    cols = {"u": u, "Ps": np.full_like(t, 100e5), "Fext": np.zeros_like(t)}
    inputs = InputTable(t, np.column_stack([cols[n] for n in model.input_names]))
    tr = simulate(model, inputs, t, p=p, opts=SolverOptions(rtol=1e-8))
    meas = {o: tr.Y[:, j] for j, o in enumerate(model.output_names)}
    return Experiment("stairs", "<synthetic>", inputs, t, meas, fit_outputs=["v", "dp"])


def test_steady_fit_recovers_valve_gain_and_viscous_friction_from_plateaus(eha):
    from hydrocli.identify.steady import fit_steady
    _, model = eha
    truth = model.p0.copy()
    exp = _staircase(model, truth)
    start = truth.copy()
    start[model.param_index("valve.Kv")] *= 1.3
    start[model.param_index("friction.kv_p")] *= 0.7
    res, plateaus = fit_steady(model, [exp], ["valve.Kv", "friction.kv_p"], p_start=start, settle=0.2,
                               min_duration=0.15, max_evals=60, opts=SolverOptions(rtol=1e-7))
    assert len(plateaus) == len(LEVELS)
    for n, v in zip(res.names, res.estimates):
        assert abs(v / truth[model.param_index(n)] - 1) < 0.02, (n, v)


def test_steady_mode_on_the_command_line(tmp_path, eha):
    from typer.testing import CliRunner
    from hydrocli.cli.main import app
    from synth import EHA, write_csv
    _, model = eha
    p = model.p0.copy()
    p[model.param_index("valve.Kv")] *= 0.8
    write_csv(tmp_path / "stairs.csv", _staircase(model, p), model)
    r = CliRunner().invoke(app, ["identify", str(EHA), "-e", str(tmp_path / "stairs.csv"), "--mode", "steady",
                                 "--free", "valve.Kv", "--outputs", "v", "--max-evals", "30",
                                 "--out", str(tmp_path / "id.yaml")])
    assert r.exit_code == 0, r.output
    assert f"steady-state fit on {len(LEVELS)} plateau(s)" in r.output
    from hydrocli.runner import load_machine
    _, m2 = load_machine(tmp_path / "id.yaml")
    assert abs(m2.params[m2.param_index("valve.Kv")].value / p[model.param_index("valve.Kv")] - 1) < 0.02
