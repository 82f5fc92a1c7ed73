"""Every file of the bad-input corpus (tests/data/bad) goes through the CLI and is refused
with exit code 3, a message naming the file (and the line, for machine files), and no
traceback. Each corpus file is named after what it breaks; machine files say so on line 1."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from hydrocli.cli.main import app

BAD = Path(__file__).parent / "data" / "bad"
MACHINES = sorted(BAD.glob("*.yaml"))
DATA = sorted(BAD.glob("data_*.csv"))
EHA = Path(__file__).parents[1] / "machines" / "eha_testbench.yaml"
runner = CliRunner()


def test_corpus_is_complete():
    assert len(MACHINES) >= 30 and len(DATA) >= 6
    for path in MACHINES:
        assert path.read_text().startswith("# BAD: "), f"{path.name}: first line must say what is wrong"


def _assert_refused(result, path: Path, line_required: bool):
    out = result.output
    assert result.exit_code == 3, f"{path.name}: exit {result.exit_code}\n{out}"
    assert "Traceback" not in out and "internal error" not in out, out
    assert path.name in result.stderr, out
    if line_required:
        assert re.search(re.escape(path.name) + r":\d+", result.stderr), f"{path.name}: no line number\n{out}"


@pytest.mark.parametrize("path", MACHINES, ids=lambda p: p.stem)
def test_bad_machine_file_is_refused_with_a_located_message(path):
    result = runner.invoke(app, ["check", str(path)])
    cycle_partner = path.name.startswith("include_cycle")  # the message may point at the other file
    _assert_refused(result, path if not cycle_partner else path.with_name(
        {"include_cycle_a.yaml": "include_cycle_b.yaml", "include_cycle_b.yaml": "include_cycle_a.yaml"}[path.name]),
        line_required=True)
    assert "hint:" in result.stderr or "did you mean" in result.stderr, result.stderr


@pytest.mark.parametrize("path", DATA, ids=lambda p: p.stem)
def test_bad_recording_is_refused(path, tmp_path):
    result = runner.invoke(app, ["simulate", str(EHA), "--experiment", str(path), "--out", str(tmp_path / "r.h5")])
    _assert_refused(result, path, line_required=path.stat().st_size > 0 and "single" not in path.name)
    assert not (tmp_path / "r.h5").exists()
