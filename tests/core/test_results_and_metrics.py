"""HDF5 layout of DESIGN.md, atomic writes, and the fit metrics."""
import h5py
import numpy as np
import pytest

from hydrocli.metrics import esr, fit_percent, nrmse
from hydrocli.results import RunResult, read_result, write_result


def _result():
    t = np.linspace(0, 1, 11)
    return RunResult(machine="m", netlist_sha="abc", netlist_text="name: m\n", experiment="e", t=t,
                     inputs={"u": np.sin(t)}, outputs={"P1": 1e5 * t}, states={"n.p": 1e5 * t},
                     measured={"P1": 1e5 * t + 1.0}, parameters=[("valve.Kv", 4.68e-7, "m^3/s/Pa^0.5")],
                     units={"outputs/P1": "Pa", "measured/P1": "Pa", "inputs/u": "1", "states/n.p": "Pa"},
                     display_units={"outputs/P1": "bar"}, solver_stats={"steps_accepted": 12},
                     identify={"names": np.array(["valve.Kv"], dtype=object), "estimates": np.array([5e-7]),
                               "cost": 0.1})


def test_layout_matches_design(tmp_path):
    path = tmp_path / "r.h5"
    write_result(path, _result())
    with h5py.File(path) as h:
        assert {"meta", "time", "inputs", "outputs", "states", "measured", "parameters", "identify"} <= set(h)
        meta = h["meta"].attrs
        for key in ("tool_version", "machine", "netlist_sha256", "command", "timestamp"):
            assert key in meta
        assert h["meta/netlist"][()].decode() == "name: m\n"
        assert h["outputs/P1"].attrs["unit"] == "Pa" and h["outputs/P1"].attrs["display_unit"] == "bar"
        assert h["time"].attrs["unit"] == "s"
        assert h["parameters"][0]["value"] == pytest.approx(4.68e-7)


def test_round_trip(tmp_path):
    path = tmp_path / "r.h5"
    write_result(path, _result())
    back = read_result(path)
    assert back.machine == "m" and back.parameters[0][0] == "valve.Kv"
    np.testing.assert_allclose(back.measured["P1"], 1e5 * back.t + 1.0)
    assert list(back.identify["names"]) == ["valve.Kv"]


def test_failed_write_leaves_no_file(tmp_path):
    bad = _result()
    bad.inputs = {"u": object()}  # cannot be written
    with pytest.raises(Exception):
        write_result(tmp_path / "r.h5", bad)
    assert list(tmp_path.iterdir()) == []


def test_esr_definition():
    y = np.array([0.0, 1.0, 2.0, 3.0])
    yhat = y + np.array([0.1, -0.1, 0.1, -0.1])
    assert esr(y, yhat) == pytest.approx(100 * np.var([0.1, -0.1, 0.1, -0.1]) / np.var(y))
    assert esr(y, y) == 0.0


def test_nrmse_and_fit():
    y = np.array([0.0, 2.0, 4.0])
    assert nrmse(y, y + 1.0) == pytest.approx(1.0 / 4.0)
    assert fit_percent(y, y) == pytest.approx(100.0)
    assert fit_percent(y, np.full(3, y.mean())) == pytest.approx(0.0)
