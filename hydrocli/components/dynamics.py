"""Small dynamic laws shared by several components (one definition each)."""
from __future__ import annotations

from ..model import expr as E


def rate_limited(u, xr, s_max, tau):
    """d(xr)/dt of a smooth rate limiter: s_max·tanh((u − xr)/(τ·s_max)).

    Tracks u with lag τ for small errors and moves at most at s_max (seed 004 eq. 1,
    continuous form so the stiff solver sees a smooth right-hand side).
    """
    return s_max * E.tanh((u - xr) / (tau * s_max))


def second_order(x, xd, u, tau, zeta):
    """x'' of 1/(τ²s² + 2ζτs + 1); ζ = 1 gives seed 004 eq. 2, 1/(1 + τs)²."""
    return (u - x - 2.0 * zeta * tau * xd) / (tau * tau)


def first_order(x, u, tau):
    """x' of 1/(1 + τs)."""
    return (u - x) / tau


def tanh_sign(v, eps):
    """sign(v) smoothed as tanh(v/ε) (seed 004, text after eq. 11)."""
    return E.tanh(v / eps)
