"""Experiment files: CSV / HDF5 / MAT with units, scales and offsets; designed signals;
windows, masks, initial conditions; the real Festo .mat recordings; bad data exits 3."""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io as sio
from typer.testing import CliRunner

from hydrocli.errors import DataError
from hydrocli.experiments.experiment_file import load_experiment, load_experiment_files, recording_from_file
from hydrocli.experiments.initial import initial_state

ROOT = Path(__file__).resolve().parents[2]
EHA = ROOT / "machines" / "eha_testbench.yaml"
FESTO = ROOT.parent / "shared" / "real" / "festo_tp511"
T = np.arange(0, 1.0, 1e-3)
IO = "inputs: {u: {column: cmd, unit: V, scale: '10 %/V'}, Ps: {column: ps, unit: bar}, Fext: 0}\n"


def _signals():
    return {"cmd": 0.5 * np.sin(2 * np.pi * T), "ps": np.full_like(T, 100.0),   # V, bar
            "pos": 3.5 + 0.1 * T,                                              # V (0.02 m/V)
            "p1": 50.0 + T}                                                    # bar


def _check(exp):
    s = _signals()
    assert np.allclose(exp.inputs.U[:, 0], 0.1 * s["cmd"])              # 10 %/V → fraction
    assert np.allclose(exp.inputs.U[:, 1], 1e7) and np.allclose(exp.inputs.U[:, 2], 0.0)
    assert np.allclose(exp.measured["x"], 0.02 * s["pos"] - 0.001)
    assert np.allclose(exp.measured["P1"], 1e5 * s["p1"])


OUTS = "outputs: {x: {column: pos, unit: V, scale: '0.02 m/V', offset: '-1 mm'}, P1: {column: p1, unit: bar}}\n"


def test_csv_hdf5_and_mat_give_the_same_experiment(tmp_path, eha):
    _, model = eha
    s = _signals()
    np.savetxt(tmp_path / "r.csv", np.column_stack([T] + list(s.values())), delimiter=",", comments="",
               header="t[s]," + ",".join(s))
    with h5py.File(tmp_path / "r.h5", "w") as h:
        h["daq/t"] = T
        for k, v in s.items():
            h[f"daq/{k}"] = v
    sio.savemat(tmp_path / "r.mat", {"t": T[:, None], **{k: v[:, None] for k, v in s.items()}, "tout": T[:10, None]})
    for data, time_col in (("r.csv", "t"), ("r.h5", "daq/t"), ("r.mat", "t")):
        io = IO.replace("column: ", "column: daq/") if data.endswith(".h5") else IO
        outs = OUTS.replace("column: ", "column: daq/") if data.endswith(".h5") else OUTS
        (tmp_path / "e.yaml").write_text(f"data: {data}\ntime: {time_col}\n{io}{outs}")
        _check(load_experiment(tmp_path / "e.yaml", model))


def test_a_csv_whose_time_column_is_not_first_reads_its_clock_by_name(tmp_path):
    """Columns in another order (time last): the column named t is the clock, and the first
    column stays a signal with its unit converted."""
    p = 50.0 + T
    np.savetxt(tmp_path / "r.csv", np.column_stack([p, T * 1e3]), delimiter=",", comments="", header="P1[bar],t[ms]")
    rec = recording_from_file(tmp_path / "r.csv")
    assert np.allclose(rec.t, T) and np.allclose(rec.columns["P1"], 1e5 * p)
    np.savetxt(tmp_path / "n.csv", np.column_stack([T, p]), delimiter=",", comments="", header="clock[s],P1[bar]")
    assert np.allclose(recording_from_file(tmp_path / "n.csv").t, T)      # no t/time column: the first


def test_hdf5_unit_attribute_converts_to_si(tmp_path):
    with h5py.File(tmp_path / "r.h5", "w") as h:
        h["t"] = T
        h["p"] = np.full_like(T, 2.0)
        h["p"].attrs["unit"] = "bar"
    rec = recording_from_file(tmp_path / "r.h5")
    assert np.allclose(rec.columns["p"], 2e5)


def test_designed_signals_window_mask_initial_and_several_experiments(tmp_path, eha):
    _, model = eha
    (tmp_path / "d.yaml").write_text(
        "duration: 2 s\nrate: 500 Hz\n"
        "inputs: {u: {step: {at: 0.5 s, to: 10}}, Ps: 100 bar, Fext: {sine: {amplitude: 1 kN, frequency: 1 Hz}}}\n"
        "initial: {piston.x: 50 mm}\n"
        "experiments:\n  - {name: all}\n  - {name: late, window: [1 s, 2 s], initial: steady, settle: 0.5 s}\n")
    a, b = load_experiment_files(tmp_path / "d.yaml", model)
    assert a.t_out.size == 1001 and a.inputs.U[a.t_out >= 0.5, 0].min() == pytest.approx(0.1)
    assert a.initial == {"piston.x": pytest.approx(0.05)}
    assert b.t_out[0] == pytest.approx(1.0) and b.settle == pytest.approx(0.5)
    assert load_experiment(f"{tmp_path / 'd.yaml'}#late", model).name == "late"
    x0 = initial_state(model, b)        # settled with u frozen at 10 %: the piston moved on during the pre-roll
    assert x0[model.state_index("piston.x")] > 0.06


def test_mask_above_and_times(tmp_path, eha):
    _, model = eha
    x = np.linspace(0.19, 0.21, T.size)
    np.savetxt(tmp_path / "r.csv", np.column_stack([T, x, x]), delimiter=",", comments="", header="t[s],x[m],v[m/s]")
    (tmp_path / "e.yaml").write_text("data: r.csv\ninputs: {u: 0, Ps: 100 bar, Fext: 0}\noutputs: {x: x, v: v}\n"
                                     "mask: {x: {above: 199.9 mm}, v: {times: [[0 s, 0.1 s]]}}\n")
    e = load_experiment(tmp_path / "e.yaml", model)
    assert np.array_equal(e.mask["x"], x <= 0.1999)
    assert np.array_equal(e.mask["v"], T > 0.1 + 1e-12)


def test_festo_mat_recording_loads_with_scales(tmp_path, eha):
    if not FESTO.exists():
        pytest.skip("shared Festo recordings not present")
    _, model = eha
    mat = FESTO / "m_find_b_pA_2V_sample_1.mat"
    rec = recording_from_file(mat)
    assert rec.t.size == 160001 and "tout" in rec.other_lengths and "w_verdadero2" in rec.columns
    (tmp_path / "f.yaml").write_text(
        f"data: {mat}\ninputs: {{u: {{column: w_verdadero2, unit: V, scale: '10 %/V'}}, Ps: 44 bar, Fext: 0}}\n"
        "outputs: {x: {column: poloha_bez_filtr2, unit: V, scale: '0.02 m/V'}, "
        "P1: {column: pressure_bez_filtr1, unit: V, scale: '1e6 Pa/V'}}\n"
        "preprocess: {lowpass: {order: 2, cutoff: 50 Hz}, resample: 1 kHz}\nwindow: [0 s, 5 s]\n"
        "mask: {x: {above: 199.9 mm}}\n")
    e = load_experiment(tmp_path / "f.yaml", model)
    assert e.t_out.size == 5001 and 0.0 <= e.measured["x"].min() and e.measured["x"].max() <= 0.2
    assert 0 < np.median(e.measured["P1"]) < 60e5


BAD = [
    ("t[s],u[1]\n0,1\n0.001,nan\n", "IO", "r.csv:3"),                         # NaN in an input column
    ("t[s],u[1]\n0,1\n0.002,1\n0.001,1\n", "IO", "r.csv:4"),                # time goes back
    ("t[s],u[1]\n0,1\n0.001,1\n", "inputs: {u: uu, Ps: 1 bar, Fext: 0}\n", "unknown column 'uu'"),
    ("t[s],u[1]\n0,1\n0.001,1\n", "inputs: {u: u}\n", "no value for machine input(s) Ps, Fext"),
]


@pytest.mark.parametrize("csv,inputs,where", BAD)
def test_bad_data_exits_3_with_location(tmp_path, csv, inputs, where):
    from hydrocli.cli.main import app
    (tmp_path / "r.csv").write_text(csv)
    (tmp_path / "e.yaml").write_text("data: r.csv\n" + ("inputs: {u: u, Ps: 1 bar, Fext: 0}\n" if inputs == "IO" else inputs))
    r = CliRunner().invoke(app, ["simulate", str(EHA), "-e", str(tmp_path / "e.yaml"), "--out", str(tmp_path / "o.h5")])
    assert r.exit_code == 3, r.output
    assert where in r.output and "Traceback" not in r.output


def test_wrong_length_mat_column_and_missing_file(tmp_path, eha):
    _, model = eha
    sio.savemat(tmp_path / "r.mat", {"t": T[:, None], "u": T[:500, None]})
    (tmp_path / "e.yaml").write_text("data: r.mat\ninputs: {u: u, Ps: 1 bar, Fext: 0}\n")
    with pytest.raises(DataError, match="'u' has 500 samples but the time column has 1000"):
        load_experiment(tmp_path / "e.yaml", model)
    (tmp_path / "e.yaml").write_text("data: ../nowhere/r.mat\ninputs: {u: u, Ps: 1 bar, Fext: 0}\n")
    with pytest.raises(DataError, match="not found"):
        load_experiment(tmp_path / "e.yaml", model)
