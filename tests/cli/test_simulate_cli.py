"""`hydro simulate`: HDF5 as DESIGN.md, --set overrides, solver failures exit 4 with a hint."""
from pathlib import Path

import h5py
import numpy as np
from typer.testing import CliRunner

from hydrocli.cli.main import app

ROOT = Path(__file__).parents[2]
EHA = str(ROOT / "machines" / "eha_testbench.yaml")

OVERRUN = """
name: overrun
inputs: {}
components:
  supply: {type: pressure_source, ports: {P: s}, p: 100 bar}
  tank: {type: tank, ports: {T: t}}
  valve: {type: valve_4_3, ports: {P: s, T: t, A: a, B: b, cmd: u}, Kv: 1e-6}
  cmd: {type: constant, ports: {out: u}, value: 1.0}
  cyl: {type: cylinder_double_rod, ports: {A: a, B: b, rod: rod, body: ground}, A: 1e-3, V_A0: 1e-4, V_B0: 1e-4}
  load: {type: mass, ports: {m: rod}, m: 10}
outputs: {x: rod.x}
"""

EXPERIMENT = """
name: open
signals:
  dummy: {type: step, at: 0.0, to: 0.0}
duration: 2.0
rate: 100
"""


def _short_csv(tmp_path: Path) -> Path:
    src = (ROOT / "experiments" / "quickstart" / "train.csv").read_text().splitlines()
    path = tmp_path / "short.csv"
    path.write_text("\n".join(src[:2001]) + "\n")  # 2 s
    return path


def test_simulate_writes_the_design_layout(tmp_path):
    out = tmp_path / "r.h5"
    res = CliRunner().invoke(app, ["simulate", EHA, "--experiment", str(_short_csv(tmp_path)), "--out", str(out)])
    assert res.exit_code == 0, res.output
    with h5py.File(out) as h:
        assert {"meta", "time", "inputs", "outputs", "states", "measured", "parameters"} <= set(h)
        assert h["meta"].attrs["machine"] == "eha_testbench"
        assert int(h["meta"].attrs["solver_steps_accepted"]) > 0
        assert h["outputs/P1"].attrs["unit"] == "Pa" and h["outputs/P1"].attrs["display_unit"] == "bar"
        p1 = h["outputs/P1"][()]
        # the model follows the recording: first sample equals the measured initial pressure
        assert abs(p1[0] - h["measured/P1"][0]) < 1.0 and np.all(np.isfinite(p1))


def test_set_overrides_a_parameter(tmp_path):
    csv = _short_csv(tmp_path)
    outs = []
    for extra in ([], ["--set", "load.m=300 kg"]):
        out = tmp_path / f"r{len(outs)}.h5"
        res = CliRunner().invoke(app, ["simulate", EHA, "--experiment", str(csv), "--out", str(out), *extra])
        assert res.exit_code == 0, res.output
        with h5py.File(out) as h:
            pars = {r["name"].decode(): r["value"] for r in h["parameters"][()]}
            outs.append((pars["load.m"], h["outputs/v"][()]))
    assert outs[0][0] == 74.11 and outs[1][0] == 300.0
    assert np.max(np.abs(outs[0][1] - outs[1][1])) > 1e-4   # a heavier load moves differently


def test_stroke_overrun_is_a_solver_failure_with_time_and_hint(tmp_path):
    machine = tmp_path / "overrun.yaml"
    machine.write_text(OVERRUN)
    out = tmp_path / "r.h5"
    t = np.linspace(0, 2, 201)
    csv = tmp_path / "none.csv"
    csv.write_text("t[s]\n" + "\n".join(f"{x:.3f}" for x in t) + "\n")
    res = CliRunner().invoke(app, ["simulate", str(machine), "--experiment", str(csv), "--out", str(out)])
    assert res.exit_code == 4, res.output
    assert "stroke overrun" in res.output and "at t = " in res.output and "end stops" in res.output
    assert "Traceback" not in res.output
    assert not out.exists()   # nothing half-written
