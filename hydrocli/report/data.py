"""What the report reads from result files: the RunResult (``runfiles.load_run``),
a few /meta attributes RunResult does not carry, display-unit conversion and decimation."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from ..errors import HydroError
from ..metrics import all_metrics
from ..results import RunResult
from ..runfiles import load_run
from ..units import si_factor


@dataclass
class Loaded:
    path: str
    res: RunResult
    meta: dict = field(default_factory=dict)
    _metrics: dict | None = None

    def metrics(self) -> dict[str, dict[str, float]]:
        """ESR, NRMSE, fit per measured output (computed once)."""
        if self._metrics is None:
            self._metrics = {n: all_metrics(self.res.measured[n], y) for n, y in self.res.outputs.items()
                             if n in self.res.measured}
        return self._metrics


def load(path: str | Path) -> Loaded:
    res = load_run(path)
    with h5py.File(path, "r") as h:
        meta = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in h["meta"].attrs.items()}
    return Loaded(str(path), res, meta)


def display(res: RunResult, group: str, name: str, values: np.ndarray) -> tuple[np.ndarray, str]:
    """Values in the dataset's display unit (falls back to SI when it cannot convert)."""
    key = f"{group}/{name}"
    unit = res.display_units.get(key) or res.units.get(key) or ""
    if not unit or unit == res.units.get(key):
        return values, _pretty(unit)
    try:
        return values / si_factor(unit), _pretty(unit)
    except HydroError:
        return values, _pretty(res.units.get(key, ""))


def _pretty(unit: str) -> str:
    return {"1": "-", "kg/m/s**2": "Pa", "kg*m/s**2": "N"}.get(unit, unit.replace("**", "^"))


def decimate(t: np.ndarray, y: np.ndarray, n: int = 3000) -> tuple[np.ndarray, np.ndarray]:
    """Min/max envelope decimation to about ``n`` points, so peaks survive in vector plots."""
    if t.size <= n:
        return t, y
    m = -(-t.size // (n // 2))                  # samples per bucket
    k = t.size // m
    Y = y[:k * m].reshape(k, m)
    base = np.arange(k) * m
    lo = base + np.argmin(np.where(np.isfinite(Y), Y, np.inf), axis=1)
    hi = base + np.argmax(np.where(np.isfinite(Y), Y, -np.inf), axis=1)
    idx = np.unique(np.concatenate([lo, hi, np.arange(k * m, t.size)]))
    return t[idx], y[idx]


def worst_windows(t: np.ndarray, residuals: list[np.ndarray], count: int = 2, frac: float = 0.06) -> list[tuple[float, float]]:
    """The ``count`` non-overlapping windows (``frac`` of the record each) with the largest
    rolling residual energy, residuals normalised per output by their variance."""
    if t.size < 10 or not residuals:
        return []
    energy = np.zeros(t.size)
    for r in residuals:
        r = np.nan_to_num(np.asarray(r, float) - np.nanmean(r))
        var = float(np.mean(r ** 2))
        if var > 0:
            energy += r ** 2 / var
    w = max(5, int(frac * t.size))
    if w >= t.size:
        return [(float(t[0]), float(t[-1]))]
    c = np.concatenate([[0.0], np.cumsum(energy)])
    rolling = c[w:] - c[:-w]                                     # rolling[i] = energy of [i, i+w)
    out = []
    for _ in range(count):
        if not np.isfinite(rolling).any() or np.nanmax(rolling) <= 0:
            break
        i = int(np.nanargmax(rolling))
        out.append((float(t[i]), float(t[min(i + w, t.size - 1)])))
        rolling[max(0, i - w + 1):i + w] = -np.inf
    return sorted(out)
