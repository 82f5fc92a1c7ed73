"""Preprocessing of recorded signals (seed 004 §II) and sample masks.

* ``lowpass(t, y, order, cutoff)``: zero-phase Butterworth low-pass (``scipy.signal.butter``
  as second-order sections + ``sosfiltfilt``): the forward-backward pass cancels the phase,
  so a filtered signal is not delayed (seed 004's pre-processing);
* ``resample(t, columns, rate)``: linear interpolation onto a uniform grid from t[0]
  (low-pass first when decimating, to avoid aliasing);
* ``remove_offset(y, samples=N | value=v)``: subtract the mean of the first N samples, or v;
* ``window(t, t0, t1)``: the samples with t0 ≤ t ≤ t1;
* masks: ``mask_condition(y, above=…, below=…)`` and ``mask_times(t, [[t0, t1], …])`` give
  True where a sample must be IGNORED (e.g. a position sensor clipping at full stroke).
"""
from __future__ import annotations

import numpy as np
from scipy import signal as sps

from ..errors import DataError, Location, Problem


def sample_rate(t: np.ndarray) -> float:
    return float((t.size - 1) / (t[-1] - t[0]))


def lowpass(t: np.ndarray, y: np.ndarray, order: int, cutoff: float, loc: Location | None = None) -> np.ndarray:
    fs = sample_rate(t)
    if not 0 < cutoff < fs / 2:
        raise DataError(Problem(f"low-pass cutoff {cutoff:g} Hz must lie between 0 and half the sample rate "
                                f"({fs / 2:g} Hz)", loc or Location(), "lower the cutoff or resample later"))
    if not 1 <= int(order) <= 12:
        raise DataError(Problem(f"filter order {order} must be between 1 and 12", loc or Location()))
    sos = sps.butter(int(order), cutoff, btype="low", fs=fs, output="sos")
    if y.size <= 3 * (2 * len(sos) + 1):
        raise DataError(Problem(f"too few samples ({y.size}) for an order-{order} zero-phase filter", loc or Location()))
    return sps.sosfiltfilt(sos, y)


def resample(t: np.ndarray, columns: dict[str, np.ndarray], rate: float,
             hold: set[str] | None = None) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Uniform grid at ``rate`` Hz; columns named in ``hold`` use the previous sample (no interpolation)."""
    n = int(np.floor((t[-1] - t[0]) * rate + 1e-9)) + 1
    tn = t[0] + np.arange(n) / rate
    out = {}
    for k, y in columns.items():
        if hold and k in hold:
            idx = np.clip(np.searchsorted(t, tn + 1e-9 / rate, side="right") - 1, 0, t.size - 1)  # round-off
            out[k] = y[idx]
        else:
            out[k] = np.interp(tn, t, y)
    return tn, out


def remove_offset(y: np.ndarray, samples: int | None = None, value: float | None = None) -> np.ndarray:
    if value is not None:
        return y - value
    n = max(int(samples or 1), 1)
    return y - float(np.mean(y[:n]))


def window(t: np.ndarray, t0: float | None, t1: float | None) -> np.ndarray:
    """Boolean index of the samples inside [t0, t1]."""
    keep = np.ones(t.size, dtype=bool)
    if t0 is not None:
        keep &= t >= t0 - 1e-12
    if t1 is not None:
        keep &= t <= t1 + 1e-12
    return keep


def mask_condition(y: np.ndarray, above: float | None = None, below: float | None = None) -> np.ndarray:
    bad = np.zeros(y.size, dtype=bool)
    if above is not None:
        bad |= y > above
    if below is not None:
        bad |= y < below
    return bad


def mask_times(t: np.ndarray, intervals) -> np.ndarray:
    bad = np.zeros(t.size, dtype=bool)
    for t0, t1 in intervals:
        bad |= (t >= t0) & (t <= t1)
    return bad
