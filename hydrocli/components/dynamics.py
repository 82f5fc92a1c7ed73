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


def softplus(x, width):
    """max(x, 0) smoothed over ``width`` with an exponential tail: max(x, 0) + w·ln(1 + e^(−|x|/w))
    (overflow-free form of w·ln(1 + e^(x/w))). Unlike :func:`E.smooth_pos`, whose tail falls
    only as w²/(4|x|), it is zero to within w·e^(−|x|/w) away from the corner."""
    return E.fmax(x, 0.0) + width * E.log(1.0 + E.exp(-E.fabs(x) / width))


def logistic(x, width):
    """The slope of :func:`softplus`: 1/(1 + e^(−x/w)) = ½(1 + tanh(x/2w))."""
    return 0.5 * (1.0 + E.tanh(0.5 * x / width))


def dead_zone(d, gap, width):
    """A clearance's dead zone and its slope, ``(D, D')``: D(d) = s⁺(d − g/2) − s⁺(−d − g/2),
    s⁺ the positive part smoothed over ``width`` (:func:`softplus`), so D is 0 while the two
    parts float inside the clearance of total width g and d ∓ g/2 once it is taken up; D' is
    the contact indicator (0 inside the band, 1 in contact). g = 0 gives D = d, D' = 1
    exactly, a plain spring. The dead-zone model of backlash, with damping acting in contact
    only (Nordin & Gutman, Automatica 38 (2002), §2, eqs. 2–3)."""
    h = 0.5 * gap
    up, down = d - h, -d - h
    return softplus(up, width) - softplus(down, width), logistic(up, width) + logistic(down, width)


def tanh_sign(v, eps):
    """sign(v) smoothed as tanh(v/ε) (seed 004, text after eq. 11)."""
    return E.tanh(v / eps)


CUBIC_SERIES_BELOW = 1e-3   # hc·F² below which the inversion uses its series (error < (hc·F²)⁴)


def cubic_linear_force(f, hc):
    """u = k·d of a cubic (Duffing) spring F = k·d·(1 + hc·(k·d)²/3) from its force F.

    The real root of u³ + (3/hc)·u − 3F/hc = 0 (positive coefficient: one real root), in the
    hyperbolic form of Cardano's solution, u = (2/s)·sinh(asinh(1.5·F·s)/3) with s = √hc;
    for hc·F² < 10⁻³ the Lagrange inversion series u = F·(1 − z/3 + z²/3 − 4z³/9), z = hc·F²,
    which stays exact at hc = 0 (no 0/0 in the value or its derivatives). With
    hc = 3k₃/k³ this is F = k·d + k₃·d³, whose tangent stiffness is k·(1 + hc·u²)."""
    z = hc * f * f
    s = E.sqrt(E.fmax(hc, 1e-300))
    exact = 2.0 * E.sinh(E.asinh(1.5 * f * s) / 3.0) / s
    series = f * (1.0 - z / 3.0 + z * z / 3.0 - 4.0 / 9.0 * z * z * z)
    return E.where(z < CUBIC_SERIES_BELOW, series, exact)


def spring_stiffness(k, f, h=None, hc=None):
    """Tangent stiffness of a spring carrying force (or torque) f: k·(1 + h·f² + hc·u²).

    ``h``: hardening with the force carried, dF/dd = k·(1 + h·F²) (a stiffness that grows
    with load without limit: F = tan(√h·k·d)/√h); ``hc``: cubic hardening with the
    deflection, F = k·d + k₃·d³ with hc = 3k₃/k³ (:func:`cubic_linear_force`), the Duffing
    spring of a rubber bushing or a clevis that firms up. To first order in F² the two agree;
    at large load the force law stiffens far faster. Either None (or both): linear."""
    if h is None and hc is None:
        return k
    extra = 0.0
    if h is not None:
        extra = extra + h * f * f
    if hc is not None:
        u = cubic_linear_force(f, hc)
        extra = extra + hc * u * u
    return k * (1.0 + extra)
