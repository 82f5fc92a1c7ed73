"""``hydro check``, ``hydro components`` and ``hydro schema`` through the real CLI app."""
from __future__ import annotations

import json

from pathlib import Path

import pytest
from typer.testing import CliRunner

from hydrocli.cli.main import app
from hydrocli.components import registry

EHA = str(Path(__file__).parents[2] / "machines" / "eha_testbench.yaml")


@pytest.fixture()
def run():
    runner = CliRunner(env={"COLUMNS": "250"})
    return lambda *args: runner.invoke(app, list(args))


def _row(output: str, first_cell: str) -> list[str]:
    for line in output.splitlines():
        cells = [c.strip() for c in line.strip("│ ").split("│")]
        if cells and cells[0] == first_cell:
            return cells
    raise AssertionError(f"no row '{first_cell}' in\n{output}")


def test_check_lists_nodes_states_inputs_outputs_parameters(run):
    r = run("check", EHA)
    assert r.exit_code == 0, r.output
    out = r.stdout
    assert _row(out, "chamber_1")[1:3] == ["hydraulic", "state"]
    assert "valve.A, cylinder.A" in _row(out, "chamber_1")[3]
    assert _row(out, "piston")[1] == "translational"
    assert _row(out, "u")[2] == "machine input"
    assert _row(out, "chamber_1.p")[1:3] == ["Pa", "5e+06"]         # initial: "50 bar"
    assert _row(out, "piston.x")[1:3] == ["m", "0.07"]              # initial: "70 mm"
    assert _row(out, "dp")[1:3] == ["chamber_1.p - chamber_2.p", "bar"]
    assert _row(out, "* valve.Kv")[1] == "4.68e-07"                 # free, with bounds
    assert _row(out, "* valve.Kv")[3] == "[1e-07, 2e-06]"
    assert _row(out, "* cylinder.beta")[1:4] == ["1.73", "GPa", "[0.3, 2.5]"]   # in the file's unit
    assert _row(out, "valve.tau")[1:3] == ["4", "ms"]               # fixed: no star
    assert "15 free" in out


def test_check_with_set_and_bad_set(run):
    r = run("check", EHA, "--set", "valve.tau=6 ms", "--set", "load.m=80")
    assert r.exit_code == 0, r.output
    assert _row(r.stdout, "valve.tau")[1] == "6"
    r = run("check", EHA, "--set", "valve.tauu=6 ms")
    assert r.exit_code == 2 and "did you mean 'tau'" in r.stderr and "Traceback" not in r.output


def test_check_reports_warnings(run, tmp_path):
    m = tmp_path / "m.yaml"
    m.write_text("inputs: {Ps: {unit: bar}, unused: {unit: N}}\n"
                 "components:\n  s: {type: pressure_source, ports: {P: n, ref: Ps}}\n"
                 "  o: {type: orifice, ports: {A: n, B: ground}}\n")
    r = run("check", str(m))
    assert r.exit_code == 0, r.output
    assert "warning: machine input 'unused' drives no signal port" in r.stdout


def test_check_bad_file_exit_3_with_location(run, tmp_path):
    m = tmp_path / "m.yaml"
    m.write_text("components:\n  v: {type: volume, ports: {P: n}, Vv: 1}\n  w: {type: volumee}\n")
    r = run("check", str(m))
    assert r.exit_code == 3
    assert f"{m}:2:" in r.stderr and f"{m}:3:" in r.stderr and "2 problems" in r.stderr


def test_components_lists_every_type(run):
    r = run("components")
    assert r.exit_code == 0
    for name, cls in registry.all_types().items():
        assert _row(r.stdout, name)[1] == cls.family


def test_components_type_table(run):
    r = run("components", "valve_4_3")
    assert r.exit_code == 0, r.output
    cls = registry.get("valve_4_3")
    assert _row(r.stdout, "cmd")[1] == "signal"
    kv = _row(r.stdout, "Kv")
    assert kv[1] == "m^3/s/Pa^0.5" and kv[2] == f"{cls.param('Kv').default:.4g}"
    for s in cls.states:
        assert _row(r.stdout, s.name)[1] == s.unit
    assert "equations" in r.stdout and "seed 004" in r.stdout


def test_components_unknown_type_is_a_usage_error_with_suggestion(run):
    r = run("components", "volumee")
    assert r.exit_code == 2 and "did you mean 'volume'" in r.stderr


def test_schema_print_and_write(run, tmp_path):
    r = run("schema")
    assert r.exit_code == 0
    schema = json.loads(r.stdout)
    assert "type_valve_4_3" in schema["$defs"]
    out = tmp_path / "machine.schema.json"
    r = run("schema", "--out", str(out))
    assert r.exit_code == 0 and json.loads(out.read_text()) == schema
