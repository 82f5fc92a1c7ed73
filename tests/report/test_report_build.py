"""`hydro report`: page count, /identify pages, display units, worst windows, bad files."""
import re

import h5py
import numpy as np
import pytest
from typer.testing import CliRunner

from hydrocli.cli.main import app
from hydrocli.report import build as build_mod
from hydrocli.report.build import build_report
from hydrocli.report.data import decimate, display, load, worst_windows
from hydrocli.results import RunResult, write_result

runner = CliRunner()


def pages(pdf) -> int:
    return len(re.findall(rb"/Type\s*/Page\b(?!s)", pdf.read_bytes()))


def make_result(path, experiment="step", identify=False):
    t = np.linspace(0.0, 10.0, 2001)
    p = 50e5 + 10e5 * np.sin(t)
    x = 0.05 + 0.02 * np.sin(0.5 * t)
    bump = np.where((t > 6.0) & (t < 7.0), 0.004, 0.0)          # the model misses something at 6–7 s
    rng = np.random.default_rng(1)
    res = RunResult(
        machine="bench", netlist_sha="ab" * 32, netlist_text="name: bench\n", experiment=experiment, t=t,
        inputs={"u": np.sign(np.sin(t))}, outputs={"p": p, "x": x, "F": 100 * t}, states={"x": x},
        measured={"p": p + 2e4 * rng.standard_normal(t.size), "x": x + bump},
        parameters=[("valve.Kv", 4.68e-7, "m^3/s/Pa^0.5"), ("load.m", 74.0, "kg"), ("fluid.beta", 1.7e9, "Pa")],
        units={"outputs/p": "Pa", "measured/p": "Pa", "outputs/x": "m", "measured/x": "m", "outputs/F": "N",
               "inputs/u": "1"},
        display_units={"outputs/p": "bar", "measured/p": "bar", "outputs/x": "mm", "measured/x": "mm"})
    if identify:
        res.identify = {"names": np.array(["valve.Kv", "load.m"], dtype=object), "initial": [4e-7, 60.0],
                        "estimates": [4.68e-7, 74.0], "lower": [1e-7, 20.0], "upper": [2e-6, 300.0],
                        "stderr": [1e-9, 3.0], "correlation": [[1.0, -0.7], [-0.7, 1.0]],
                        "cost_history": np.geomspace(2.0, 0.01, 40), "cost": 0.01, "cost_initial": 2.0,
                        "method": "least-squares", "message": "ok", "n_evals": 40, "interrupted": 0,
                        "seconds": 1.5, "warnings": np.array([""], dtype=object)}
    write_result(path, res)
    return path


def test_display_units_and_decimation(tmp_path):
    run = load(make_result(tmp_path / "r.h5"))
    values, unit = display(run.res, "outputs", "p", np.array([1e5, 2e5]))
    assert unit == "bar" and values == pytest.approx([1.0, 2.0])
    assert display(run.res, "outputs", "x", np.array([0.063]))[0] == pytest.approx([63.0])
    assert display(run.res, "outputs", "F", np.array([5.0])) == (pytest.approx([5.0]), "N")
    # a display unit the unit registry does not know: the plot falls back to SI, no crash
    run.res.display_units["outputs/p"] = "blorp"
    assert display(run.res, "outputs", "p", np.array([1e5])) == (pytest.approx([1e5]), "Pa")
    t = np.arange(10000.0)
    y = np.sin(t / 300)
    y[4321] = 7.0
    td, yd = decimate(t, y, n=1000)
    assert td.size <= 1002 and yd.max() == 7.0 and yd.min() == pytest.approx(y.min())


def test_worst_windows_find_the_burst():
    t = np.linspace(0, 10, 1001)
    r = 0.01 * np.sin(40 * t)
    r[(t > 6) & (t < 6.4)] += 1.0
    r[(t > 2) & (t < 2.2)] += 0.5
    (a1, b1), (a2, b2) = worst_windows(t, [r], count=2, frac=0.05)
    assert a1 < 2.1 < b1 and a2 < 6.2 < b2            # both bursts, sorted by time, not overlapping
    assert b1 <= a2


def test_nominal_report_page_count(tmp_path):
    out = tmp_path / "sub" / "r.pdf"
    n = build_report([make_result(tmp_path / "r.h5")], out, title="Bench")
    # title + overview (3 outputs) + zoom + nominal parameter table
    assert n == 4 and pages(out) == 4
    assert out.read_bytes().startswith(b"%PDF")


def test_report_with_identify(tmp_path):
    a = make_result(tmp_path / "a.h5", "train", identify=True)
    b = make_result(tmp_path / "b.h5", "check", identify=True)         # same identification: shown once
    out = tmp_path / "r.pdf"
    r = runner.invoke(app, ["report", str(a), str(b), "--out", str(out), "--title", "Identified bench"])
    assert r.exit_code == 0, r.output
    # title + 2 × (overview + zoom) + identified parameters + correlation/cost
    assert pages(out) == 7 and "7 pages" in r.output


def test_bad_files_exit_3_and_leave_nothing(tmp_path):
    good = make_result(tmp_path / "ok.h5")
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"\x89HDF garbage")
    foreign = tmp_path / "foreign.h5"
    with h5py.File(foreign, "w") as h:
        h["data"] = [1.0, 2.0]
    half = tmp_path / "half.h5"
    with h5py.File(half, "w") as h:
        h.create_group("meta")
        h["time"] = [0.0, 1.0]
    out = tmp_path / "out" / "r.pdf"
    for bad in (junk, foreign, half, tmp_path / "missing.h5"):
        r = runner.invoke(app, ["report", str(good), str(bad), "--out", str(out)])
        assert r.exit_code == 3, (bad, r.output)
        assert "Traceback" not in r.output and "internal error" not in r.output
    assert not out.exists()


def test_crash_while_drawing_leaves_old_pdf(tmp_path, monkeypatch):
    out = tmp_path / "r.pdf"
    out.write_bytes(b"%PDF old")

    def boom(*a, **k):
        raise RuntimeError("drawing failed")

    monkeypatch.setattr(build_mod, "experiment_pages", boom)
    with pytest.raises(RuntimeError):
        build_report([make_result(tmp_path / "r.h5")], out)
    assert out.read_bytes() == b"%PDF old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.h5", "r.pdf"]
