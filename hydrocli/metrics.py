"""Fit metrics: ESR (seed 004 eq. 14), NRMSE, fit %; the effective sample size of a residual.

ESR = 100·Var(y − ŷ)/Var(y) per signal (seed 004 eq. 14 read as a per-signal ratio).
NRMSE = RMS(y − ŷ)/(max y − min y); fit % = 100·(1 − ‖y − ŷ‖/‖y − mean y‖).
Samples where either signal is NaN, or the mask is False, are ignored.
"""
from __future__ import annotations

import numpy as np


def _clean(y, yhat, mask=None):
    y, yhat = np.asarray(y, float), np.asarray(yhat, float)
    ok = np.isfinite(y) & np.isfinite(yhat)
    if mask is not None:
        ok &= np.asarray(mask, bool)
    return y[ok], yhat[ok]


def esr(y, yhat, mask=None) -> float:
    """100·Var(y − ŷ)/Var(y) in percent (seed 004 eq. 14)."""
    y, yhat = _clean(y, yhat, mask)
    vy = np.var(y)
    if y.size < 2 or vy == 0.0:
        return float("nan")
    return float(100.0 * np.var(y - yhat) / vy)


def nrmse(y, yhat, mask=None) -> float:
    y, yhat = _clean(y, yhat, mask)
    rng = np.ptp(y) if y.size else 0.0
    if rng == 0.0:
        return float("nan")
    return float(np.sqrt(np.mean((y - yhat) ** 2)) / rng)


def fit_percent(y, yhat, mask=None) -> float:
    y, yhat = _clean(y, yhat, mask)
    den = np.linalg.norm(y - y.mean())
    if den == 0.0:
        return float("nan")
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / den))


def all_metrics(y, yhat, mask=None) -> dict[str, float]:
    return {"esr": esr(y, yhat, mask), "nrmse": nrmse(y, yhat, mask), "fit": fit_percent(y, yhat, mask)}


def effective_samples(r: np.ndarray) -> float:
    """Independent samples in an autocorrelated residual, n·(1 − ρ₁)/(1 + ρ₁) for an AR(1)
    process with lag-1 autocorrelation ρ₁ (Bayley & Hammersley 1946; Box, Jenkins & Reinsel
    §2.1). Model error makes a dynamic fit's residuals strongly correlated, and Gauss–Newton
    standard errors, which assume white residuals, are then too small by √(n/n_eff)."""
    r = np.asarray(r, float)
    n = r.size
    if n < 3:
        return float(n)
    d = r - r.mean()
    den = float(d @ d)
    rho = float(np.clip((d[1:] @ d[:-1]) / den, -0.99, 0.9999)) if den > 0 else 0.0
    return float(np.clip(n * (1 - rho) / (1 + rho), 2.0, n))
