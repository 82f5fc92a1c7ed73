"""Small dynamic laws shared by several components (one definition each)."""
from __future__ import annotations

from ..model import expr as E


def rate_limited(u, xr, s_max, tau, s_min=None):
    """d(xr)/dt of a smooth rate limiter: s·tanh((u − xr)/(τ·s)), s = s_max when rising.

    Tracks u with lag τ for small errors and moves at most at s_max rising and s_min
    falling (seed 004 eq. 1: s_v,max and s_v,min = −s_min; continuous form so the stiff solver
    sees a smooth right-hand side). ``s_min`` None: symmetric, the same expression as before.
    Both branches have value 0, slope 1/τ and curvature 0 at u = xr, so the switch is C².
    """
    e = u - xr
    if s_min is None:
        return s_max * E.tanh(e / (tau * s_max))
    return E.where(e >= 0.0, s_max * E.tanh(e / (tau * s_max)), s_min * E.tanh(e / (tau * s_min)))


def second_order(x, xd, u, tau, zeta):
    """x'' of 1/(τ²s² + 2ζτs + 1); ζ = 1 gives seed 004 eq. 2, 1/(1 + τs)²."""
    return (u - x - 2.0 * zeta * tau * xd) / (tau * tau)


def first_order(x, u, tau):
    """x' of 1/(1 + τs)."""
    return (u - x) / tau


def dahl_rate(z, r, h, sigma, eps):
    """z' of Dahl's loop driven by an input moving at rate r: σ·r·(1 − (z/h)·tanh(r/ε))
    (Dahl 1968, TOR-158, eq. 5 with exponent 1; the direction sign(r) smoothed over ε).
    z tends to ±h while the input moves; dz/du = 2σ just after a reversal from ∓h."""
    return sigma * r * (1.0 - (z / h) * E.tanh(r / eps))


def play_rate(u, y, b, eps, tau):
    """y' of a smooth play (backlash) of half-width b: [s⁺(u − y − b) − s⁺(y − u − b)]/τ, s⁺ the
    positive part smoothed over ε (play operator, Tao & Kokotović ch. 2): y holds while
    |u − y| ≤ b and follows u with lag τ outside the band."""
    return (E.smooth_pos(u - y - b, eps) - E.smooth_pos(y - u - b, eps)) / tau


def tanh_sign(v, eps):
    """sign(v) smoothed as tanh(v/ε) (seed 004, text after eq. 11)."""
    return E.tanh(v / eps)
