"""Jiles–Atherton hysteresis between input current and a virtual current (seed 001 eqs. 1–2)."""
from __future__ import annotations

from ...model import expr as E


def langevin(x):
    """L(x) = coth(x) − 1/x, with its series x/3 − x³/45 near 0 (seed 001 eq. 2)."""
    small = x / 3.0 - x * x * x / 45.0
    safe = E.where(E.fabs(x) < 1e-3, 1.0, x)
    return E.where(E.fabs(x) < 1e-3, small, 1.0 / E.tanh(safe) - 1.0 / safe)


def ja_slope(i, i_hys, delta, lam, mu0, alpha, k, i_s):
    """di_hys/di = Λ·μ0·(i_s·L − i_hys)/(k·δ − μ0·α·(i_s·L − i_hys)) (seed 001 eq. 1, the
    Jiles–Atherton law with H → i, M → i_hys, M_s → i_s, 1/a → μ0); δ = ±1 is the direction
    of the input. The slope is set to 0 when (i_s·L − i_hys)·δ < 0 (the usual correction
    that keeps the virtual current moving with the input)."""
    diff = i_s * langevin(mu0 * (i + alpha * i_hys)) - i_hys
    slope = lam * mu0 * diff / (k * delta - mu0 * alpha * diff)
    return E.where(diff * delta > 0.0, slope, 0.0)
