"""`hydro identify` end to end: identified YAML reloads with the new values, HDF5 has /identify,
several experiments, stages and steady mode; bad data exits 3."""
from __future__ import annotations

import h5py
import numpy as np
from typer.testing import CliRunner

from synth import EHA, synthetic, write_csv


def _invoke(*args):
    from hydrocli.cli.main import app
    return CliRunner().invoke(app, [str(a) for a in args])


def _recording(tmp_path, model, name="rec", kv_factor=1.1, duration=1.5, seed=3):
    p = model.p0.copy()
    p[model.param_index("valve.Kv")] *= kv_factor
    return write_csv(tmp_path / f"{name}.csv", synthetic(model, p, duration=duration, seed=seed), model), p


def test_identify_writes_yaml_that_reloads_and_hdf5_with_identify(tmp_path, eha):
    from hydrocli.runner import load_machine
    _, model = eha
    csv, truth = _recording(tmp_path, model)
    out, h5 = tmp_path / "id.yaml", tmp_path / "run.h5"
    r = _invoke("identify", EHA, "--experiment", csv, "--free", "valve.Kv", "--free", "load.m=20:300",
                "--outputs", "P1,P2,v", "--out", out, "--results", h5, "--max-evals", "40", "--rtol", "1e-7")
    assert r.exit_code == 0, r.output
    assert "+++ b/eha_testbench.yaml" in r.output and "std error" in r.output
    _, m2 = load_machine(out)
    kv = m2.params[m2.param_index("valve.Kv")].value
    assert abs(kv / truth[model.param_index("valve.Kv")] - 1) < 0.01
    assert "# q_n/sqrt(dP_n), seed 004" in out.read_text()          # comments kept
    with h5py.File(h5) as h:
        g = h["identify"]
        names = [n.decode() if isinstance(n, bytes) else n for n in g["names"][()]]
        assert names == ["valve.Kv", "load.m"]
        assert g["estimates"][0] == np.float64(kv) or abs(g["estimates"][0] / kv - 1) < 1e-5
        assert g["correlation"].shape == (2, 2) and g["cost_history"].size > 3
        assert "measured" in h and "outputs" in h


def test_several_experiments_write_one_result_per_experiment(tmp_path, eha):
    _, model = eha
    a, _ = _recording(tmp_path, model, "runA", seed=4, duration=1.0)
    b, _ = _recording(tmp_path, model, "runB", seed=5, duration=1.0)
    r = _invoke("identify", EHA, "-e", a, "-e", b, "--free", "valve.Kv", "--out", tmp_path / "id.yaml",
                "--results", tmp_path / "run.h5", "--max-evals", "20")
    assert r.exit_code == 0, r.output
    assert (tmp_path / "run_runA.h5").exists() and (tmp_path / "run_runB.h5").exists()


def test_stages_file_runs_stages_in_order(tmp_path, eha, monkeypatch):
    import hydrocli.experiments.experiment_file as ef
    _, model = eha
    loads = []
    real = ef.load_all
    monkeypatch.setattr(ef, "load_all", lambda path, m: loads.append(str(path)) or real(path, m))
    csv, truth = _recording(tmp_path, model, kv_factor=1.15)
    exp = tmp_path / "e.yaml"
    exp.write_text(f"data: {csv.name}\ninputs: {{u: u, Ps: Ps, Fext: Fext}}\noutputs: {{P1: P1, P2: P2, v: v}}\n")
    stages = tmp_path / "stages.yaml"
    stages.write_text("stages:\n"
                      "  - {name: valve gain, free: [valve.Kv], experiments: [e.yaml], outputs: [v], max_evals: 30}\n"
                      "  - {name: mass, free: {load.m: [20, 300]}, experiments: [e.yaml], max_evals: 30}\n")
    r = _invoke("identify", EHA, "--stages", stages, "--out", tmp_path / "id.yaml", "--results", tmp_path / "r.h5",
                "--rtol", "1e-7")
    assert r.exit_code == 0, r.output
    assert "== stage: valve gain" in r.output and "== stage: mass" in r.output
    assert loads == [str(exp)]                      # two stages on one file: loaded once, not three times
    with h5py.File(tmp_path / "r.h5") as h:
        assert set(h["identify/stages"].keys()) == {"1_valve gain", "2_mass"}
        est = dict(zip([n.decode() if isinstance(n, bytes) else n for n in h["identify/names"][()]],
                       h["identify/estimates"][()]))
    assert abs(est["valve.Kv"] / truth[model.param_index("valve.Kv")] - 1) < 0.01


def test_bad_data_exits_3_with_file_and_row(tmp_path, eha):
    _, model = eha
    csv, _ = _recording(tmp_path, model, duration=0.2)
    lines = csv.read_text().splitlines()
    lines[5] = lines[5].replace(lines[5].split(",")[1], "nan", 1)
    csv.write_text("\n".join(lines) + "\n")
    r = _invoke("identify", EHA, "-e", csv, "--free", "valve.Kv", "--out", tmp_path / "id.yaml")
    assert r.exit_code == 3
    assert f"{csv}:6" in r.output and "NaN" in r.output and "Traceback" not in r.output


def test_usage_errors_exit_2(tmp_path):
    r = _invoke("identify", EHA, "--out", tmp_path / "x.yaml")
    assert r.exit_code == 2


def test_batch_cli_writes_the_table(tmp_path, eha):
    _, model = eha
    for i in (1, 2):
        csv, _ = _recording(tmp_path, model, name=f"rep{i}", kv_factor=1.0 + 0.05 * i, duration=0.6, seed=20 + i)
        (tmp_path / f"rep{i}.yaml").write_text(f"name: rep{i}\ndata: {csv.name}\ninputs: {{u: u, Ps: Ps, Fext: Fext}}\n"
                                               "outputs: {P1: P1, P2: P2, v: v}\n")
    table = tmp_path / "table.csv"
    r = _invoke("identify", EHA, "--batch", str(tmp_path / "rep*.yaml"), "--free", "valve.Kv", "--jobs", "2",
                "--max-evals", "15", "--out", table)
    assert r.exit_code == 0, r.output
    rows = [line.split(",") for line in table.read_text().splitlines()]
    assert [row[0] for row in rows] == ["experiment", "rep1", "rep2", "mean", "std", "min", "max"]
    kv = model.p0[model.param_index("valve.Kv")]
    assert abs(float(rows[1][1]) / kv - 1.05) < 0.01 and abs(float(rows[2][1]) / kv - 1.10) < 0.01
    assert "mean" in r.output


def test_batch_with_unreachable_scheduler_exits_4(tmp_path, eha):
    _, model = eha
    csv, _ = _recording(tmp_path, model, duration=0.2)
    r = _invoke("identify", EHA, "--batch", str(csv), "--free", "valve.Kv", "--scheduler", "tcp://127.0.0.1:9",
                "--out", tmp_path / "t.csv")
    assert r.exit_code == 4 and "cannot connect" in r.output


def test_nelder_mead_seed004_cost_and_free_bounds_with_units(tmp_path, eha):
    _, model = eha
    csv, truth = _recording(tmp_path, model, kv_factor=1.2, duration=0.6, seed=7)
    r = _invoke("identify", EHA, "-e", csv, "--free", "valve.Kv=1e-7:2e-6", "--free", "cylinder.beta=0.5 GPa:2.5 GPa",
                "--method", "nelder-mead", "--cost", "seed004", "--outputs", "P1,P2,v", "--max-evals", "80",
                "--rtol", "1e-7", "--out", tmp_path / "id.yaml", "--results", tmp_path / "r.h5")
    assert r.exit_code == 0, r.output
    with h5py.File(tmp_path / "r.h5") as h:
        assert np.allclose(h["identify/lower"][()], [1e-7, 0.5e9]) and h["identify"].attrs["method"] == "nelder-mead"
        kv = h["identify/estimates"][0]
    assert abs(kv / truth[model.param_index("valve.Kv")] - 1) < 0.02


def test_bad_free_option_is_a_usage_error(tmp_path, eha):
    r = _invoke("identify", EHA, "-e", "x.csv", "--free", "valve.Kvv", "--out", tmp_path / "id.yaml")
    assert r.exit_code == 2 and "valve.Kv" in r.output          # did-you-mean
    r = _invoke("identify", EHA, "-e", "x.csv", "--free", "valve.Kv=1", "--out", tmp_path / "id.yaml")
    assert r.exit_code == 2 and "lo:hi" in r.output
    r = _invoke("identify", EHA, "-e", "x.csv", "--free", "valve.Kv=1 kg:2 kg", "--out", tmp_path / "id.yaml")
    assert r.exit_code == 2 and "Traceback" not in r.output


def test_profile_option_prints_and_stores_intervals_that_bracket_the_truth(tmp_path, eha):
    _, model = eha
    csv, truth = _recording(tmp_path, model)
    h5 = tmp_path / "run.h5"
    r = _invoke("identify", EHA, "-e", csv, "--free", "valve.Kv", "--outputs", "P1,P2,v", "--out",
                tmp_path / "id.yaml", "--results", h5, "--profile", "valve.Kv")
    assert r.exit_code == 0, r.output
    assert "profile-likelihood 95 % intervals" in r.output and "valve.Kv:" in r.output
    with h5py.File(h5) as h:
        lo, hi = h["identify"]["profile_lower"][0], h["identify"]["profile_upper"][0]
    assert lo <= truth[model.param_index("valve.Kv")] <= hi
    r = _invoke("identify", EHA, "-e", csv, "--free", "valve.Kv", "--out", tmp_path / "id2.yaml",
                "--profile", "load.m")
    assert r.exit_code == 2 and "not a free parameter" in r.output
