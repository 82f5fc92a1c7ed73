"""Nothing is lost: the output guard, the atomic writer (temporary file removed on failure,
on SIGTERM, and after a SIGKILL by the next write), write-back into included files checked
before a fit, CRLF kept, the identified netlist's hash in identify.h5, one SI spelling per
dimension in HDF5, strict JSON, help without Python type names, --debug anywhere."""
from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest
from typer.testing import CliRunner

import bad_corpus
from hydrocli.cli.main import COMMANDS, app
from hydrocli.errors import DataError, UsageError
from hydrocli.fileio import atomic_path, command_scope, guard_output, json_text, note_input, write_text_atomic

runner = CliRunner()
ROOT = Path(__file__).parents[2]


def _rig(tmp_path: Path, machine: str = bad_corpus.MACHINE) -> Path:
    (tmp_path / "m.yaml").write_text(machine)
    (tmp_path / "e.yaml").write_text(bad_corpus.EXPERIMENT)
    (tmp_path / "r.csv").write_text(bad_corpus.CSV)
    return tmp_path


# -- the atomic writer -----------------------------------------------------------------------
def test_failed_write_keeps_the_old_file_and_removes_the_temporary(tmp_path):
    target = tmp_path / "report.pdf"
    target.write_text("old report")
    with pytest.raises(RuntimeError):
        with atomic_path(target, suffix=".pdf") as tmp:
            Path(tmp).write_text("half a rep")
            raise RuntimeError("killed half way")
    assert target.read_text() == "old report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.pdf"]


def test_sigterm_during_a_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "result.h5"
    target.write_text("previous result")
    code = ("import sys, time, pathlib\nsys.path.insert(0, %r)\nfrom hydrocli.fileio import atomic_path\n"
            "with atomic_path(%r) as tmp:\n    pathlib.Path(tmp).write_text('partial')\n"
            "    print('writing', flush=True)\n    time.sleep(30)\n") % (str(ROOT), str(target))
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing"
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=20) != 0
    assert target.read_text() == "previous result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.h5"]


def test_temporary_of_a_killed_writer_is_removed_by_the_next_write(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = tmp_path / f".out.yaml.{int(dead.stdout)}.abcd.tmp"      # what SIGKILL leaves behind
    stale.write_text("junk")
    write_text_atomic(tmp_path / "out.yaml", "a: 1\n")
    assert not stale.exists() and (tmp_path / "out.yaml").read_text() == "a: 1\n"


def test_crlf_is_written_when_asked(tmp_path):
    write_text_atomic(tmp_path / "x.yaml", "a: 1\nb: 2\n", newline="\r\n")
    assert (tmp_path / "x.yaml").read_bytes() == b"a: 1\r\nb: 2\r\n"


def test_unwritable_target_is_a_located_data_error(tmp_path):
    (tmp_path / "ro").mkdir()
    with pytest.raises((DataError, UsageError)):
        with atomic_path(tmp_path / "ro" / "x" / "\0bad"):
            pass


# -- the guard -------------------------------------------------------------------------------
def test_guard_refuses_inputs_hard_links_directories_and_devices(tmp_path):
    src = tmp_path / "m.yaml"
    src.write_text("x")
    os.link(src, tmp_path / "alias.yaml")
    with pytest.raises(UsageError, match="input"):
        guard_output(tmp_path / "alias.yaml", [src])
    with command_scope():
        note_input(src)
        with pytest.raises(UsageError, match="input"):
            guard_output(src)
    guard_output(src)                                   # outside a command: nothing is an input
    with pytest.raises(UsageError, match="directory"):
        guard_output(tmp_path)
    with pytest.raises(UsageError, match="regular file"):
        guard_output("/dev/null")
    with pytest.raises(UsageError, match="not a folder"):
        guard_output(src / "out.h5")


def test_simulate_refuses_to_overwrite_the_recording_an_experiment_names(tmp_path):
    d = _rig(tmp_path)
    before = (d / "r.csv").read_bytes()
    r = runner.invoke(app, ["simulate", str(d / "m.yaml"), "-e", str(d / "e.yaml"), "-o", str(d / "r.csv")])
    assert r.exit_code == 2 and "input" in r.stderr
    assert (d / "r.csv").read_bytes() == before


def test_diagnose_refuses_an_existing_file_as_output_folder_before_working(tmp_path, monkeypatch):
    import hydrocli.diagnose as D
    d = _rig(tmp_path)
    (d / "diag").write_text("keep")

    def no_work(*a, **k):                                   # refused before any diagnosis
        raise AssertionError("the diagnosis ran before the output folder was checked")
    monkeypatch.setattr(D, "diagnose", no_work)
    r = runner.invoke(app, ["diagnose", str(d / "m.yaml"), "--train", str(d / "e.yaml"), "--validate",
                            str(d / "e.yaml"), "-o", str(d / "diag")])
    assert r.exit_code == 2 and "not a directory" in r.stderr
    assert (d / "diag").read_text() == "keep"


# -- identify: write-back into an included file, checked before the fit; the result's hash --
def test_identify_writes_back_a_parameter_defined_in_an_included_file(tmp_path):
    d = _rig(tmp_path)
    text = bad_corpus.MACHINE
    load_block = "  load:\n    type: mass\n    ports: {m: piston}\n    m: {value: 50, free: true, bounds: [20, 300]}\n"
    (d / "parts").mkdir()
    (d / "parts" / "load.yaml").write_bytes(("components:\n" + load_block).replace("\n", "\r\n").encode())
    main = text.replace(load_block, "").replace("name: rig\n", "name: rig\ninclude: [parts/load.yaml]\n")
    main = main.replace("Kv: {value: 4.68e-7, free: true,", "Kv: {value: 4.68e-7, free: false,")
    (d / "m.yaml").write_bytes(main.replace("\n", "\r\n").encode())
    included_before = (d / "parts" / "load.yaml").read_bytes()
    (d / "out").mkdir()
    r = runner.invoke(app, ["identify", str(d / "m.yaml"), "-e", str(d / "e.yaml"), "--max-evals", "3",
                            "-o", str(d / "out" / "id.yaml"), "--results", str(d / "out" / "id.h5")])
    assert r.exit_code == 0, r.output
    from hydrocli.netlist.loader import load_netlist
    from hydrocli.netlist.normal import netlist_sha256
    from hydrocli.results import read_result
    out = d / "out" / "id.yaml"
    assert b"\r\n" in out.read_bytes() and b"\n" not in out.read_bytes().replace(b"\r\n", b"")   # CRLF kept
    assert (d / "parts" / "load.yaml").read_bytes() == included_before                        # input untouched
    ident = load_netlist(out)                          # include path rebased to the output folder
    assert "load" in ident.components and ident.components["load"].params["m"].free
    # identify.h5 records the netlist that reproduces it: the identified machine's
    assert read_result(d / "out" / "id.h5").netlist_sha == netlist_sha256(ident)


def test_identify_refuses_an_impossible_write_back_before_fitting(tmp_path, monkeypatch):
    d = _rig(tmp_path)
    import hydrocli.identify.fit as fit_module
    from hydrocli.errors import NetlistError, Problem
    import hydrocli.netlist.writer as writer

    def refuse(net, names):
        raise NetlistError(Problem("cannot write valve.Kv back"))
    monkeypatch.setattr(writer, "check_write_back", refuse)
    monkeypatch.setattr(fit_module, "fit", lambda *a, **k: pytest.fail("the fit started"))
    r = runner.invoke(app, ["identify", str(d / "m.yaml"), "-e", str(d / "e.yaml"), "-o", str(d / "id.yaml")])
    assert r.exit_code == 3 and "cannot write" in r.stderr and not (d / "id.yaml").exists()


# -- HDF5 units, JSON, help, --debug -------------------------------------------------------
def test_hdf5_unit_attributes_use_one_si_spelling(tmp_path):
    d = _rig(tmp_path)
    r = runner.invoke(app, ["simulate", str(d / "m.yaml"), "-e", str(d / "e.yaml"), "-o", str(d / "r.h5")])
    assert r.exit_code == 0, r.output
    units = {}
    with h5py.File(d / "r.h5") as h:
        h.visititems(lambda name, obj: units.__setitem__(name, obj.attrs.get("unit")) if "unit" in obj.attrs else None)
    assert units["outputs/P1"] == units["states/a.p"] == units["inputs/Ps"] == "Pa"
    assert not [u for u in units.values() if "**" in str(u)]


def test_json_text_is_strict_json():
    import numpy as np
    text = json_text({"esr": float("nan"), "x": [1.0, float("inf")], "a": np.float64(2.5), "v": np.array([np.nan, 1])})
    assert json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in JSON")) == \
        {"esr": None, "x": [1.0, None], "a": 2.5, "v": [None, 1.0]}
    assert not math.isnan(json.loads(text)["a"])


@pytest.mark.parametrize("command", [c for c in COMMANDS])
def test_help_has_no_python_type_names(command):
    r = runner.invoke(app, [command, "--help"])
    assert r.exit_code == 0
    for bad in ("<list[", "<path>", "<str>", "<int>", "<float>", "<bool>", "{machine}", "{results}"):
        assert bad not in r.output, (command, bad)


def test_debug_works_after_the_command(tmp_path):
    r = runner.invoke(app, ["check", str(tmp_path / "missing.yaml"), "--debug"])
    assert r.exception is not None and type(r.exception).__name__ == "NetlistError"   # the traceback is shown
    r = runner.invoke(app, ["check", str(tmp_path / "missing.yaml")])
    assert r.exit_code == 3 and "Traceback" not in r.output


def test_diagnose_only_names_an_effect_of_the_vocabulary(tmp_path, monkeypatch):
    import hydrocli.diagnose as D
    d = _rig(tmp_path)
    monkeypatch.setattr(D, "diagnose", lambda *a, **k: (_ for _ in ()).throw(AssertionError("ran")))
    r = runner.invoke(app, ["diagnose", str(d / "m.yaml"), "--train", str(d / "e.yaml"), "--validate",
                            str(d / "e.yaml"), "-o", str(d / "diag"), "--only", "entrained_ai"])
    assert r.exit_code == 2 and "did you mean 'entrained_air'" in r.stderr and "Traceback" not in r.stderr
