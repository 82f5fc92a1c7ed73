"""ESR, NRMSE and fit % against hand-computed values."""
import math

import numpy as np
import pytest

from hydrocli.metrics import all_metrics, esr, fit_percent, nrmse


def test_hand_computed_four_samples():
    y, yhat = [1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 3.0, 5.0]
    # residual [0,0,0,-1]: Var = 0.25 - 0.0625 = 0.1875; Var(y) = 1.25
    assert esr(y, yhat) == pytest.approx(15.0)
    assert nrmse(y, yhat) == pytest.approx(0.5 / 3.0)           # RMS 0.5 over range 3
    assert fit_percent(y, yhat) == pytest.approx(100 * (1 - 1 / math.sqrt(5)))


def test_scaled_sine_and_offset():
    t = np.linspace(0, 1, 1000, endpoint=False)
    y = np.sin(2 * np.pi * t)
    m = all_metrics(y, 0.9 * y)                      # residual 0.1·y
    assert m["esr"] == pytest.approx(1.0)
    assert m["fit"] == pytest.approx(90.0)
    assert m["nrmse"] == pytest.approx(0.1 * math.sqrt(0.5) / 2, rel=1e-3)
    off = all_metrics(y, y + 0.2)                    # a constant offset has no variance…
    assert off["esr"] == pytest.approx(0.0, abs=1e-12)
    assert off["fit"] == pytest.approx(100 * (1 - 0.2 / math.sqrt(0.5)))   # …but fit and NRMSE see it
    assert off["nrmse"] == pytest.approx(0.1, rel=1e-3)


def test_nan_and_mask_are_ignored():
    y = np.array([1.0, 2.0, 3.0, 4.0, np.nan, 100.0])
    yhat = np.array([1.0, 2.0, 3.0, 5.0, 7.0, -100.0])
    mask = np.array([True, True, True, True, True, False])
    assert esr(y, yhat, mask) == pytest.approx(15.0)


def test_constant_measurement_gives_nan():
    assert math.isnan(esr([2.0, 2.0, 2.0], [1.0, 2.0, 3.0]))
