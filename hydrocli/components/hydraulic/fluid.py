"""Fluid properties used by several hydraulic components."""
from __future__ import annotations

from ...model import expr as E

P_ATM = 1.0e5
KAPPA = 1.4


def effective_bulk_modulus(beta, p, air):
    """Bulk modulus of oil with entrained air (volume fraction ``air`` at 1 bar).

    β_e = β·(1 + α(p₀/p)^(1/κ)) / (1 + α(p₀/p)^(1/κ)·β/(κ p)), the usual isentropic
    air-in-oil mixture (Merritt; Jelali & Kroll eq. 3.12); reduces to β when α = 0.
    The pressure is floored at 0.1 bar so the law stays finite.
    """
    if isinstance(air, (int, float)) and air == 0:
        return beta
    pp = E.fmax(p, 1e4)
    r = air * E.power(P_ATM / pp, 1.0 / KAPPA)
    return beta * (1.0 + r) / (1.0 + r * beta / (KAPPA * pp))
