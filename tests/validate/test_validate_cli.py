"""`hydro validate` end to end on the EHA test bench and its held-out recording.

Nominal parameters on eha_none/validate.csv give ESR(dp) ≈ 0.27 % and ESR(v) ≈ 0.08 %."""
import xml.etree.ElementTree as ET

import h5py
import pytest
from typer.testing import CliRunner

from hydrocli.cli.main import app

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "machines" / "eha_testbench.yaml"
VALIDATE_CSV = ROOT.parent / "shared" / "recordings" / "eha_none" / "validate.csv"

runner = CliRunner()


def hydro(*args):
    return runner.invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def validated(tmp_path_factory):
    """One failing run (v threshold too tight) writing every artefact."""
    d = tmp_path_factory.mktemp("val")
    r = hydro("validate", MACHINE, "-e", VALIDATE_CSV, "--max-esr", "dp=5", "--max-esr", "v=0.01",
              "--junit", d / "j.xml", "--markdown", d / "s.md", "--out-dir", d / "runs")
    return d, r


def test_exit_1_when_a_threshold_fails(validated):
    d, r = validated
    assert r.exit_code == 1, r.output
    assert "FAIL" in r.output and "1 of 2" in r.output


def test_junit_has_one_testcase_per_threshold(validated):
    d, _ = validated
    root = ET.parse(d / "j.xml").getroot()
    cases = root.findall(".//testcase")
    assert len(cases) == 2 and root.get("tests") == "2" and root.get("failures") == "1"
    failures = root.findall(".//testcase/failure")
    assert len(failures) == 1
    msg = failures[0].get("message")
    assert msg.startswith("ESR(v) = 0.0") and "> threshold 0.01 %" in msg


def test_markdown_and_result_files(validated):
    d, _ = validated
    md = (d / "s.md").read_text()
    assert "| validate | dp |" in md and "| FAIL |" in md and "**FAIL**: 1 of 2" in md
    with h5py.File(d / "runs" / "validate.h5") as h:
        assert {"P1", "P2", "x", "v", "dp"} <= set(h["measured"])     # dp derived from P1 − P2
        assert h["measured/dp"].attrs["display_unit"] == "bar"


def test_exit_0_when_thresholds_hold(tmp_path):
    f = tmp_path / "v.yaml"
    f.write_text("max_esr: {dp: 5, v: 1}\n")
    r = hydro("validate", MACHINE, "-e", VALIDATE_CSV, "--thresholds", f, "--junit", tmp_path / "j.xml")
    assert r.exit_code == 0, r.output
    root = ET.parse(tmp_path / "j.xml").getroot()
    assert len(root.findall(".//testcase")) == 2 and not root.findall(".//failure")


def test_results_mode_without_simulation(validated):
    d, _ = validated
    h5 = d / "runs" / "validate.h5"
    assert hydro("validate", "--results", h5, "--max-esr", "dp=5").exit_code == 0
    r = hydro("validate", "--results", h5, "--max-esr", "dp=0.1")
    assert r.exit_code == 1 and "dp" in r.output


def test_bad_inputs_exit_codes(tmp_path, validated):
    d, _ = validated
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5 at all")
    assert hydro("validate", "--results", junk).exit_code == 3
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as h:
        h["x"] = [1.0]
    r = hydro("validate", "--results", other)
    assert r.exit_code == 3 and "Traceback" not in r.output
    assert hydro("validate", "--results", d / "runs" / "validate.h5", "--max-esr", "dq=3").exit_code == 3
    assert hydro("validate", "--results", d / "runs" / "validate.h5", "--max-esr", "dp").exit_code == 2
    assert hydro("validate").exit_code == 2


def test_a_multi_experiment_file_validates_every_experiment(tmp_path):
    """Like identify and diagnose, validate takes all experiments of a file (two windows of one
    recording here); FILE#NAME still picks one."""
    exp = tmp_path / "two.yaml"
    exp.write_text(f"data: {VALIDATE_CSV}\ninputs: {{u: u, Ps: Ps, Fext: Fext}}\noutputs: {{P1: P1, P2: P2, v: v}}\n"
                   "experiments:\n  - {name: first, window: [0 s, 5 s]}\n"
                   "  - {name: second, window: [5 s, 10 s]}\n")
    r = hydro("validate", MACHINE, "-e", exp, "--max-esr", "dp=50", "--markdown", tmp_path / "all.md")
    assert r.exit_code == 0, r.output
    md = (tmp_path / "all.md").read_text()
    assert "| first | dp |" in md and "| second | dp |" in md
    r = hydro("validate", MACHINE, "-e", f"{exp}#second", "--max-esr", "dp=50", "--markdown", tmp_path / "one.md")
    md = (tmp_path / "one.md").read_text()
    assert r.exit_code == 0 and "| second |" in md and "| first |" not in md
