"""Residual statistics for the diagnosis (pure NumPy/SciPy functions of arrays).

* whiteness: sample autocorrelation and the Ljung–Box portmanteau statistic
  Q = n(n+2)·Σ_{k=1..h} ρ_k²/(n−k) ~ χ²_h under white residuals (Ljung & Box 1978);
* independence from the inputs: cross-correlation of the residual with each input
  (or regressor) at lags −h…h, against the ±1.96/√n_eff band (Ljung, *System
  Identification*, 2nd ed., §16.6);
* effective sample size of an autocorrelated series, n_eff = n·(1 − ρ₁)/(1 + ρ₁) (AR(1)
  variance inflation; Bayley & Hammersley 1946) — 30 000 samples of a smooth model error
  carry far less evidence than 30 000 independent ones;
* BIC difference ΔBIC = n·ln(SSR₁/SSR₀) + Δk·ln n (Schwarz 1978), with n = n_eff;
* noise floor from the high-frequency content: for white measurement noise the second
  difference has variance 6σ², while a smooth signal's second difference at the sampling
  rate is negligible;
* regression screening: explained fraction ΔR² of a residual by new regressors after
  projecting out the base model's own sensitivities (score/LM test), and t statistics.
"""
from __future__ import annotations

import numpy as np
from scipy import stats as _st

from ..metrics import effective_samples as effective_n  # noqa: F401  (one AR(1) estimate for identify and diagnose)


def acf(r: np.ndarray, maxlag: int) -> np.ndarray:
    r = np.asarray(r, float) - np.mean(r)
    n = r.size
    d = float(r @ r)
    if d == 0.0:
        return np.zeros(maxlag + 1)
    f = np.fft.rfft(r, 2 * n)
    c = np.fft.irfft(f * np.conj(f))[: maxlag + 1]
    return c / d


def ljung_box(r: np.ndarray, lags: int = 20) -> tuple[float, float]:
    """(Q, p-value); small p = residual is not white."""
    n = len(r)
    rho = acf(r, lags)[1:]
    q = float(n * (n + 2) * np.sum(rho ** 2 / (n - np.arange(1, lags + 1))))
    return q, float(_st.chi2.sf(q, lags))




def cross_correlation(r: np.ndarray, u: np.ndarray, maxlag: int) -> tuple[float, int]:
    """Largest |normalised cross-correlation| of residual r with signal u over lags
    −maxlag…maxlag, and its lag (samples; positive = r lags u)."""
    r = np.asarray(r, float) - np.mean(r)
    u = np.asarray(u, float) - np.mean(u)
    den = np.sqrt(float(r @ r) * float(u @ u))
    if den == 0.0:
        return 0.0, 0
    n = r.size
    full = np.fft.irfft(np.fft.rfft(r, 2 * n) * np.conj(np.fft.rfft(u, 2 * n)))
    lags = np.r_[np.arange(0, maxlag + 1), np.arange(-maxlag, 0)]
    vals = np.r_[full[: maxlag + 1], full[-maxlag:]] / den
    i = int(np.argmax(np.abs(vals)))
    return float(vals[i]), int(lags[i])


def delta_bic(ssr0: float, ssr1: float, n: float, dk: int) -> float:
    """BIC(new) − BIC(old); negative favours the new model."""
    return float(n * np.log(max(ssr1, 1e-300) / max(ssr0, 1e-300)) + dk * np.log(max(n, 2.0)))


NOISE_TRIM = 3.5   # robust σ beyond which a second difference is the motion's, not the noise's
# Variance of a unit normal truncated to ±c: 1 − 2cφ(c)/(2Φ(c) − 1) (Johnson, Kotz & Balakrishnan,
# *Continuous Univariate Distributions* 1, §13.10.1); the trimmed variance is divided by it.
_TRUNC_VAR = 1.0 - 2.0 * NOISE_TRIM * _st.norm.pdf(NOISE_TRIM) / (2.0 * _st.norm.cdf(NOISE_TRIM) - 1.0)


def noise_variance(y: np.ndarray) -> float:
    """White-noise variance σ² from the second differences d = Δ²y: Var(d) = 6σ² for white
    noise, while a smooth signal's d at the sampling rate is negligible.

    The variance is taken over the d within ``NOISE_TRIM`` robust σ (1.4826·MAD) of their
    median — a step, an end stop or a valve edge puts a few d far out, and they are dropped —
    and corrected for the truncation. The median absolute deviation alone is not used as the
    scale: on a quantised sensor (the lifts' speed, 0.1 mm/s steps against σ ≈ 1 mm/s) it
    locks onto the lattice and lands up to 7 % off (session 71, tests/benchmarks/
    bench_noise_floor.py), while the variance does not."""
    d = np.diff(np.asarray(y, float), 2)
    if d.size < 3:
        return 0.0
    c = float(np.median(d))
    s = 1.4826 * float(np.median(np.abs(d - c)))
    if s <= 0.0:     # over half the d equal (a lattice coarser than the noise): no scale to trim by
        return float(np.var(d)) / 6.0
    kept = d[np.abs(d - c) <= NOISE_TRIM * s]
    return float(np.var(kept)) / 6.0 / _TRUNC_VAR


def noise_esr(y: np.ndarray) -> float:
    """ESR (%) a perfect model would still show because of white measurement noise."""
    vy = float(np.var(y))
    return 100.0 * noise_variance(y) / vy if vy > 0 else 0.0


def project_out(B: np.ndarray | None, v: np.ndarray) -> np.ndarray:
    """v minus its least-squares projection on the columns of B."""
    if B is None or B.size == 0:
        return v
    coef, *_ = np.linalg.lstsq(B, v, rcond=None)
    return v - B @ coef


def screen(r: np.ndarray, S: np.ndarray, B: np.ndarray | None = None, n_eff: float | None = None) -> dict:
    """Score test of new regressors S (columns) for residual r, base sensitivities B
    projected out first. Returns the explained fraction ``dr2`` of the remaining residual,
    the coefficients, their t statistics (with n_eff degrees of freedom) and the F statistic."""
    S = np.atleast_2d(np.asarray(S, float).T).T if S.ndim == 1 else np.asarray(S, float)
    r_perp = project_out(B, r)
    S_perp = np.column_stack([project_out(B, S[:, j]) for j in range(S.shape[1])])
    coef, *_ = np.linalg.lstsq(S_perp, r_perp, rcond=None)
    fitted = S_perp @ coef
    ss = float(r_perp @ r_perp)
    dr2 = float(fitted @ fitted) / ss if ss > 0 else 0.0
    n = float(n_eff or r.size)
    k = S.shape[1]
    resid_var = max(ss - float(fitted @ fitted), 1e-300) / max(n - k, 1.0) * (r.size / n)
    try:
        cov = resid_var * np.linalg.pinv(S_perp.T @ S_perp)
        t = coef / np.sqrt(np.clip(np.diag(cov), 1e-300, None))
    except np.linalg.LinAlgError:
        t = np.full(k, np.nan)
    F = (dr2 / k) / max((1 - dr2) / max(n - k, 1.0), 1e-300)
    return {"dr2": dr2, "coef": coef, "t": t, "F": float(F), "p": float(_st.f.sf(F, k, max(n - k, 1.0)))}
