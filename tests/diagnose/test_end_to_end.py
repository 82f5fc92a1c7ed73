"""End to end on a fast synthetic case: a truth bench WITH Coulomb friction is simulated
(6 s train, 6 s validation, different excitation, sensor noise); the base machine has no
Coulomb friction. The diagnosis must name coulomb_friction, improve validation ESR, and
write a machine file that loads, builds and simulates."""
import json
import os
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose import Settings, diagnose
from hydrocli.diagnose.summary import console_summary, write_augmented, write_json
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist, load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

EHA = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"


def _machine(kc: float) -> str:
    """The EHA bench with only Kv and the viscous friction free, and Coulomb force kc."""
    text = EHA.read_text()
    import re
    text = re.sub(r"(\n\s+)(V_A0|V_B0|c_il|m|ks_p|ks_m|vs_p|vs_m): \{value: ([^,]+), free: true, bounds: \[[^]]*\]\}",
                  r"\1\2: \3", text)
    text = text.replace('c_el: {value: 0.0, free: true, bounds: [0.0, 1.0e-11]}', "c_el: 0.0")
    text = re.sub(r"kc_p: \{[^}]*\}", f"kc_p: {kc}", text)
    text = re.sub(r"kc_m: \{[^}]*\}", f"kc_m: {kc}", text)
    text = text.replace('beta: {value: "1.73 GPa", free: true, bounds: ["0.3 GPa", "2.5 GPa"]}', 'beta: "1.73 GPa"')
    return text


def _record(model, t, u, fext, path, rng):
    U = np.column_stack([u, np.full(t.size, 1e7), fext])
    tr = simulate(model, InputTable(t, U), t, opts=SolverOptions(rtol=1e-6))
    Y = {o: tr.Y[:, model.output_names.index(o)] for o in ("P1", "P2", "x", "v")}
    Y["P1"] = Y["P1"] + 1.5e4 * rng.normal(size=t.size)
    Y["P2"] = Y["P2"] + 1.5e4 * rng.normal(size=t.size)
    Y["v"] = Y["v"] + 1e-3 * rng.normal(size=t.size)
    Y["x"] = np.round(Y["x"] / 5e-6) * 5e-6
    data = np.column_stack([t, 100 * u, U[:, 1], fext, Y["P1"], Y["P2"], Y["x"], Y["v"]])
    np.savetxt(path, data, delimiter=",", header="t[s],u[%],Ps[Pa],Fext[N],P1[Pa],P2[Pa],x[m],v[m/s]", comments="")


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    d = tmp_path_factory.mktemp("diag")
    os.environ.setdefault("HYDRO_CACHE_DIR", str(d / "cache"))
    base = d / "base.yaml"
    base.write_text(_machine(0.0))
    truth = build_model(load_netlist_text(_machine(1500.0), str(d / "truth.yaml")))
    rng = np.random.default_rng(1)
    t = np.arange(0, 6.0005, 1e-3)
    u_tr = 0.08 * np.sin(2 * np.pi * 0.5 * t) + 0.03 * np.sin(2 * np.pi * 1.7 * t)
    u_va = 0.06 * np.sin(2 * np.pi * 0.8 * t + 0.5) + 0.04 * np.sign(np.sin(2 * np.pi * 0.3 * t)) * 0.5
    _record(truth, t, u_tr, 300 * np.sin(2 * np.pi * 1.1 * t), d / "train.csv", rng)
    _record(truth, t, u_va, 200 * np.sin(2 * np.pi * 0.7 * t), d / "validate.csv", rng)
    return d, base


SMALL = dict(max_effects=2, top=2, base_evals=15, candidate_evals=12,
             only=("coulomb_friction", "internal_leakage", "entrained_air", "valve_overlap"))


@pytest.fixture(scope="module")
def in_process(case):
    d, base = case
    return diagnose(base, [d / "train.csv"], [d / "validate.csv"], Settings(jobs=1, **SMALL))


def test_diagnose_names_coulomb_friction_and_improves_validation(case, in_process):
    d, base = case
    diag = in_process
    data = diag.data
    assert data["verdict"] == "missing_physics"
    acc = data["accepted"][0]
    assert acc["effect"] == "coulomb_friction"
    kc = {p["name"]: p["value"] for p in acc["parameters"]}
    assert kc["friction.kc_p"] == pytest.approx(1500, rel=0.3)
    before, after = acc["esr_validation_before"], acc["esr_validation_after"]
    assert sum(after.values()) < 0.5 * sum(before.values())
    assert data["ranking"][0]["effect"] == "coulomb_friction"
    # with the friction in, the held-out error is at the noise floor: a second round could not
    # pass rule 2 and is not run (accept.within_reach)
    stop = data["stopped_at_noise_floor"]
    assert stop["round"] == 2 and stop["esr_validation"] < 1.8 * stop["noise_floor"]
    assert all(r["evidence"] for r in data["ranking"])
    # where the time went: every step that ran, in order, adding up to the whole run
    steps = [t["step"] for t in data["timings"]]
    assert steps[0] == "loading and the measurement model" and steps[1].startswith("base fit")
    assert any(s.startswith("round 1") for s in steps) and "round 2" in steps
    assert steps[-1] == "base-fit findings re-checked"
    assert ("restrained" in steps[1]) == ("restrained_base" in data)
    assert sum(t["seconds"] for t in data["timings"]) == pytest.approx(data["runtime_s"], rel=0.02, abs=0.05)
    assert console_summary(diag).splitlines()[-1].startswith(f"Time: {data['runtime_s']:.0f} s — ")
    write_json(diag, d / "diagnosis.json")
    write_augmented(diag, d / "augmented.yaml")
    assert json.loads((d / "diagnosis.json").read_text())["verdict"] == "missing_physics"
    model = build_model(load_netlist(d / "augmented.yaml"))
    assert {"friction.kc_p", "friction.kc_m"} <= set(model.free_params)
    assert "Coulomb friction" in console_summary(diag)
    from hydrocli.report.diagnosis import write_report
    write_report(diag, d / "report.pdf")
    assert (d / "report.pdf").read_bytes()[:4] == b"%PDF"


def _as_another_lab_writes_it(src: Path, dst: Path) -> None:
    """The same recording as another lab's logger writes it: other units (bar, mm, kN), the
    columns in another order with the clock last, and no velocity channel."""
    import pandas as pd
    d = pd.read_csv(src)
    pd.DataFrame({"x[mm]": d["x[m]"] * 1e3, "P2[bar]": d["P2[Pa]"] / 1e5, "Fext[kN]": d["Fext[N]"] / 1e3,
                  "u[%]": d["u[%]"], "P1[bar]": d["P1[Pa]"] / 1e5, "Ps[bar]": d["Ps[Pa]"] / 1e5,
                  "t[ms]": d["t[s]"] * 1e3}).to_csv(dst, index=False)


def test_a_recording_in_other_units_and_order_without_velocity_still_names_it(case, in_process):
    """Units are converted where the recording enters, the clock is found by name, and an output
    the recording lacks is simply not compared: the same effect is named, at the same size."""
    d, base = case
    for part in ("train", "validate"):
        _as_another_lab_writes_it(d / f"{part}.csv", d / f"{part}_lab.csv")
    data = diagnose(base, [d / "train_lab.csv"], [d / "validate_lab.csv"], Settings(jobs=1, **SMALL)).data
    assert "v" not in data["esr_validation_base"]
    assert data["accepted"][0]["effect"] == "coulomb_friction"
    kc = {p["name"]: p["value"] for p in data["accepted"][0]["parameters"]}
    assert kc["friction.kc_p"] == pytest.approx(1500, rel=0.3)
    before, after = data["accepted"][0]["esr_validation_before"], data["accepted"][0]["esr_validation_after"]
    assert sum(after.values()) < 0.5 * sum(before.values())


@pytest.mark.slow
def test_a_dask_cluster_of_worker_processes_gives_the_same_diagnosis(case, in_process):
    """Candidate fits split per start (diagnose/candidate_fits.py) on a Dask scheduler with two
    worker processes on loopback: the record is the in-process one, number for number (to the
    last digits of the linear algebra)."""
    distributed = pytest.importorskip("distributed")
    d, base = case
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        diag = diagnose(base, [d / "train.csv"], [d / "validate.csv"],
                        Settings(jobs=2, scheduler=cluster.scheduler_address, **SMALL))
    assert diag.data["accepted"][0]["effect"] == "coulomb_friction"
    # the workers' BLAS runs on one thread (Dask's default), so a screening score may differ
    # in its last digit from the in-process one; every fit, verdict and text is the same
    _same(diag.data, in_process.data)


def _same(a, b, path="") -> None:
    if isinstance(a, dict):
        assert set(a) == set(b), path
        for k in a:
            if k == "timings":     # wall seconds: the same steps, in the same order
                assert [t["step"] for t in a[k]] == [t["step"] for t in b[k]], path
            elif k != "runtime_s":
                _same(a[k], b[k], f"{path}/{k}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (u, v) in enumerate(zip(a, b)):
            _same(u, v, f"{path}[{i}]")
    elif isinstance(a, float) and np.isfinite(a):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-300), path
    else:
        assert str(a) == str(b), path


def test_cli_usage_errors_exit_2():
    from typer.testing import CliRunner
    from hydrocli.cli.main import app
    res = CliRunner().invoke(app, ["diagnose", str(EHA), "--validate", "v.csv"])
    assert res.exit_code == 2
    assert "--train" in res.output
