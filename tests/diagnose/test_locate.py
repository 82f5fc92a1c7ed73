"""Localisation helpers: the residual spectrum of experiments of different lengths (Welch
grids differ; densities averaged on the coarsest), and which samples are direction reversals."""
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


def test_reversals_are_turns_of_real_motion_not_noise_at_rest():
    """A sine stroke turns at its crests; a standstill with noise does not reverse."""
    from hydrocli.diagnose.locate import _reversals
    t = np.arange(0, 4.0, 0.002)
    v = np.where(t < 2.0, np.cos(2 * np.pi * 0.5 * t), 0.0) + 1e-3 * np.sin(2 * np.pi * 40 * t)
    slow = np.abs(v) < 0.05
    idx = _reversals(v, slow, t)
    turns = t[idx]
    # the stroke turns where v = cos(πt) changes sign: 0.5 s and 1.5 s
    assert np.any(np.abs(turns - 0.5) < 0.02) and np.any(np.abs(turns - 1.5) < 0.02)
    assert not np.any(turns > 2.0)
