"""Residual spectrum of several experiments of different lengths: Welch grids differ, the
densities are averaged on the coarsest one and the band shares still sum to 1."""
import numpy as np
from scipy import signal

from hydrocli.diagnose.locate import _bands


def test_bands_of_experiments_with_different_lengths():
    fs = 500.0
    items = []
    for n in (1200, 1550):
        t = np.arange(n) / fs
        r = np.sin(2 * np.pi * 25.0 * t)
        items.append(signal.welch(r, fs=fs, nperseg=min(4096, n)))
    out = _bands({"pA": items})["pA"]
    assert abs(sum(out["bands"].values()) - 1.0) < 1e-9
    assert out["bands"]["10-50 Hz"] > 0.9 and abs(out["peak_hz"] - 25.0) < 1.0
