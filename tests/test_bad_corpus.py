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


# -- the generated corpus (tests/bad_corpus.py): hostile inputs, output paths, usage errors -----
import hashlib  # noqa: E402

import bad_corpus  # noqa: E402

CASES = bad_corpus.all_cases()
FAST_EVERY = 4      # the fast lane (-m "not slow") runs every 4th case; the full suite runs all


def _params():
    for i, case in enumerate(CASES):
        marks = [] if i % FAST_EVERY == 0 and not case.slow else [pytest.mark.slow]
        yield pytest.param(case, id=case.name, marks=marks)


def test_generated_corpus_is_large_and_covers_every_family():
    assert len(CASES) >= 300
    prefixes = {c.name.split("_")[0] for c in CASES}
    assert {"machine", "experiment", "output", "usage"} <= prefixes


@pytest.mark.parametrize("case", list(_params()))
def test_generated_bad_input_is_refused(case, tmp_path):
    argv = bad_corpus.materialise(case, tmp_path)
    before = {f: hashlib.sha256((tmp_path / f).read_bytes()).hexdigest() for f in case.keep}
    result = runner.invoke(app, argv)
    out = result.output
    assert result.exit_code == case.exit, f"{case.name}: exit {result.exit_code}, expected {case.exit}\n{out[-2000:]}"
    assert "Traceback" not in out and "internal error" not in out, out[-2000:]
    if case.where:
        assert case.where in result.stderr, f"{case.name}: '{case.where}' not named\n{result.stderr[-2000:]}"
        if case.line:
            assert re.search(re.escape(case.where) + r":\d+", result.stderr), f"{case.name}: no line\n{result.stderr[-2000:]}"
    for f, sha in before.items():
        assert hashlib.sha256((tmp_path / f).read_bytes()).hexdigest() == sha, f"{case.name}: input {f} was changed"
    for f in case.absent:
        assert not (tmp_path / f).exists(), f"{case.name}: {f} was written"
    leftovers = [p.name for p in tmp_path.rglob(".*.tmp*")]
    assert not leftovers, f"{case.name}: temporary files left: {leftovers}"
