"""runfiles.write_run picks the format from the suffix (HDF5 by default, CSV readable back
as a recording); load_run turns a bad file into a located DataError."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.errors import DataError
from hydrocli.experiments.recording import read_csv
from hydrocli.results import RunResult
from hydrocli.runfiles import load_run, write_run


def _result():
    t = np.linspace(0, 1, 11)
    return RunResult(machine="m", netlist_sha="abc", netlist_text="name: m\n", experiment="e", t=t,
                     inputs={"u": np.sin(t)}, outputs={"P1": 1e5 * t + 1.0 / 3.0}, states={"n.p": 2e5 * t},
                     units={"outputs/P1": "Pa", "inputs/u": "1", "states/n.p": "Pa"})


@pytest.mark.parametrize("suffix", [".h5", ".hdf5", ".result"])
def test_hdf5_for_h5_and_unknown_suffixes(tmp_path, suffix):
    path = tmp_path / f"r{suffix}"
    write_run(path, _result())
    back = load_run(path)
    assert back.machine == "m" and np.array_equal(back.outputs["P1"], _result().outputs["P1"])


def test_csv_reads_back_as_a_recording_bit_for_bit(tmp_path):
    path = tmp_path / "r.csv"
    write_run(path, _result())
    rec = read_csv(path)
    assert list(rec.columns) == ["u", "P1", "n.p"] and rec.units["P1"] == "Pa"
    res = _result()
    assert np.array_equal(rec.t, res.t)
    assert np.array_equal(rec.columns["P1"], res.outputs["P1"]) and np.array_equal(rec.columns["n.p"], res.states["n.p"])
    assert [p.name for p in tmp_path.iterdir()] == ["r.csv"]                  # no temporary left


def test_load_run_missing_and_malformed_files_are_located(tmp_path):
    with pytest.raises(DataError, match="result file not found"):
        load_run(tmp_path / "none.h5")
    bad = tmp_path / "bad.h5"
    bad.write_text("not hdf5")
    with pytest.raises(DataError, match="bad.h5"):
        load_run(bad)
