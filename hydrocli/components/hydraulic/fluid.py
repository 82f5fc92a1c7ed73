"""Fluid properties used by several hydraulic components."""
from __future__ import annotations

from ...model import expr as E
from ..base import Param

P_ATM = 1.0e5
KAPPA = 1.4


def effective_bulk_modulus(beta, p, air, n=KAPPA, p_dissolve=None):
    """Bulk modulus of oil with entrained air (``air``: free-air volume at 1 bar per volume of
    oil, r₀; the volume fraction at 1 bar is r₀/(1 + r₀)).

    β_e = β·(1 + r) / (1 + r·β/(n·p)), r = α·(p₀/p)^(1/n)·d(p): the air-in-oil mixture of
    Merritt and Jelali & Kroll eq. 3.12 with a polytropic exponent n (1.4 isentropic: fast
    compression; 1 isothermal: small bubbles that exchange heat) and, when ``p_dissolve`` is
    given, Henry's-law dissolution of the free air, d = 1 − (p − p₀)/(p_dissolve − p₀) down to
    0 at p_dissolve (Gholizadeh, Burton & Schoenau 2011, Int. J. Fluid Power 12(3), §4). With
    α' = r/(1 + r): 1/β_e = (1 − α')/β + α'/(n·p). Reduces to β when α = 0; p floored at 0.1 bar.
    """
    if isinstance(air, (int, float)) and air == 0:
        return beta
    pp = E.fmax(p, 1e4)
    r = air * E.power(P_ATM / pp, 1.0 / n)
    if p_dissolve is not None:
        r = r * E.smooth_pos(1.0 - (pp - P_ATM) / (p_dissolve - P_ATM), 1e-3)
    return beta * (1.0 + r) / (1.0 + r * beta / (n * pp))


#: the oil-and-air parameters of every component that holds oil in a volume (spec as data)
AIR_PARAMS = (
    Param("air", "1", 0.0, "entrained (free) air at 1 bar per volume of oil, r (the volume fraction is r/(1 + r))",
          min=0.0, max=1.0, bounds=(0.0, 0.1)),
    Param("air_n", "1", KAPPA, "polytropic exponent of the air: 1.4 isentropic, 1 isothermal", min=1.0, max=1.4,
          bounds=(1.0, 1.4)),
    Param("p_dissolve", "Pa", 0.0, "pressure at which the free air has dissolved (Henry's law); 0 = never",
          min=0.0, bounds=(2e5, 5e7)),
    Param("p_vap", "Pa", 0.0, "vapour / gas-release pressure (absolute): below it released gas and vapour fill "
          "the chamber and hold its pressure there (cavitation floor; typically 2 kPa); 0 = no floor. "
          "'fluid: {p_vap: 2 kPa}' sets it for every volume and chamber", min=0.0, max=1e6, fluid="p_vap",
          source="Merritt, Hydraulic Control Systems §2.5 (cavitation); Jelali & Kroll §3.2"),
    Param("tau_cav", "s", 1e-3, "time constant with which released gas/vapour fills a chamber below p_vap",
          positive=True),
)


def cavitation_floor(c, port, capacitance) -> None:
    """Below the vapour / gas-release pressure p_vap, gas and vapour come out of the oil and
    fill the chamber: a flow into the node q_cav = C·max(p_vap − p, 0)/τ_cav, so that
    C·dp/dt = Σq + q_cav relaxes p towards p_vap (a constant outflow q settles at
    p_vap − q·τ_cav/C instead of falling to absolute zero and below). Above p_vap the term is
    exactly zero: the equations are numerically unchanged there."""
    if not c.active("p_vap"):
        return
    c.through(port, -capacitance * E.fmax(c.p.p_vap - c.across(port), 0.0) / c.p.tau_cav)


def oil_bulk_modulus(c, p):
    """β_e at pressure p of a component declaring ``beta`` and :data:`AIR_PARAMS`."""
    if not c.active("air"):
        return c.p.beta
    return effective_bulk_modulus(c.p.beta, p, c.p.air, c.p.air_n,
                                  c.p.p_dissolve if c.active("p_dissolve") else None)
