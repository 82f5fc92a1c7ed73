"""Designed signals against closed forms (scipy.signal.chirp as the independent reference),
zero-phase filtering, resampling, offsets, masks."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import signal as sps

from hydrocli.errors import DataError
from hydrocli.experiments import preprocess as pp
from hydrocli.experiments.signals import is_signal, signal

T = np.linspace(0, 10, 10001)


def test_step_ramp_sine_table_and_sums():
    assert np.array_equal(signal({"step": {"at": "2 s", "from": 1, "to": 3}})(T), np.where(T >= 2, 3.0, 1.0))
    assert np.allclose(signal({"ramp": {"start": 1, "stop": 3, "to": 4}})(T), np.clip((T - 1) * 2, 0, 4))
    s = signal({"sine": {"amplitude": 2, "frequency": "0.5 Hz", "phase": "90 deg", "offset": 1}})(T)
    assert np.allclose(s, 1 + 2 * np.cos(np.pi * T))
    tab = signal({"table": {"t": [0, 5, 10], "values": [0, 10, 0]}})(T)
    assert np.allclose(tab, np.where(T <= 5, 2 * T, 20 - 2 * T))
    total = signal([{"step": {"at": 1, "to": 1}}, 2.0, {"sum": [1.0, 1.0]}])(T)
    assert np.allclose(total, np.where(T >= 1, 5.0, 4.0))


def test_chirps_match_scipy():
    lin = signal({"chirp": {"amplitude": 1.5, "f0": 0.1, "f1": 5, "duration": 10}})(T)
    assert np.allclose(lin, 1.5 * sps.chirp(T, 0.1, 10, 5, method="linear", phi=-90), atol=1e-9)
    log = signal({"chirp": {"amplitude": 1, "f0": "0.2 Hz", "f1": "20 Hz", "duration": "10 s", "method": "logarithmic"}})(T)
    assert np.allclose(log, sps.chirp(T, 0.2, 10, 20, method="logarithmic", phi=-90), atol=1e-9)


def test_signal_units_follow_the_input_unit():
    assert signal("100 bar", "Pa")(np.zeros(1))[0] == pytest.approx(1e7)
    assert signal(50, "%")(np.zeros(1))[0] == pytest.approx(0.5)           # bare number: the input's unit
    assert signal({"step": {"at": "20 ms", "to": "2 kN"}}, "N")(np.array([0.01, 0.03])).tolist() == [0, 2000]
    assert is_signal("100 bar") and not is_signal("P1") and is_signal({"sine": {}})


def test_bad_signal_is_a_data_error():
    with pytest.raises(DataError, match="unknown signal kind"):
        signal({"square": {"at": 1}})
    with pytest.raises(DataError, match="needs 'to'"):
        signal({"step": {"at": 1}})


def test_zero_phase_lowpass_keeps_the_phase_of_a_delayed_sine():
    t = np.arange(0, 4, 1e-3)
    clean = np.sin(2 * np.pi * 2 * (t - 0.137))
    noisy = clean + 0.3 * np.sin(2 * np.pi * 180 * t)
    y = pp.lowpass(t, noisy, order=4, cutoff=20.0)
    core = slice(500, -500)
    assert np.max(np.abs(y[core] - clean[core])) < 0.01
    # a causal filter of the same design delays the sine (the test can tell)
    causal = sps.sosfilt(sps.butter(4, 20.0, fs=1000.0, output="sos"), noisy)
    assert np.max(np.abs(causal[core] - clean[core])) > 0.1
    lag = np.argmax(np.correlate(y[core], clean[core], "full")) - (y[core].size - 1)
    assert lag == 0


def test_lowpass_rejects_cutoff_above_nyquist():
    t = np.arange(0, 1, 1e-3)
    with pytest.raises(DataError, match="half the sample rate"):
        pp.lowpass(t, np.sin(t), 4, 600.0)


def test_resample_offset_window_and_masks():
    t = np.arange(0, 1.0001, 1e-4)
    u = (np.arange(t.size) // 1000).astype(float)           # a staircase: held, never interpolated
    tn, cols = pp.resample(t, {"y": 3 * t, "u": u}, 100.0, hold={"u"})
    assert tn.size == 101 and np.allclose(cols["y"], 3 * tn) and np.array_equal(cols["u"], np.arange(101) // 10)
    y = np.r_[np.full(10, 2.0), np.arange(5.0)]
    assert np.allclose(pp.remove_offset(y, samples=10)[:10], 0) and np.allclose(pp.remove_offset(y, value=1.0), y - 1)
    assert pp.window(t, 0.2, 0.3).sum() == 1001
    assert np.array_equal(pp.mask_condition(np.array([1, 5, 10.0]), above=9.0), [False, False, True])
    assert pp.mask_times(t, [(0.1, 0.2)]).sum() == 1001
