"""Accumulators: a fixed capacitance (seed 001 eq. 8) and a gas-charged (bladder) accumulator."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, VariableSpec
from ..registry import register
from .. import roles as RL
from ..roles import role


@register
class Accumulator(Component):
    """Hydraulic capacitance C_A on a node: C_A·dp/dt = Σq (seed 001 eq. 8)."""

    type = "accumulator"
    family = "hydraulic"
    description = "Accumulator as a constant capacitance C_A"
    source = "seed 001 eq. 8"
    ports = (Port("P", H, "node"),)
    parameters = (Param("C", "m^5/N", 1e-11, "capacitance dV/dp", positive=True, bounds=(1e-14, 1e-7)),)

    def equations(self, c):
        c.capacitance("P", c.p.C)


@register
class GasAccumulator(Component):
    """Gas-charged accumulator: gas volume V_g = V0·(p0/p)^(1/n) above the precharge p0
    (polytropic, n = 1 isothermal … 1.4 adiabatic), so C = V_g/(n·p) + V_oil/β; below p0
    only the oil dead volume V_oil is compliant. The switch is smoothed over eps_p."""

    type = "gas_accumulator"
    roles = (role(RL.GAS_VOLUME, {"node": "P"}, gas_volume="V0", precharge="p0", exponent="n", oil_volume="V_oil"),)
    family = "hydraulic"
    description = "Gas-charged accumulator (polytropic gas spring over a precharge pressure)"
    source = "polytropic gas law p·V^n = p0·V0^n (Merritt §3); seed 001 eq. 8 (C_A)"
    ports = (Port("P", H, "node"),)
    parameters = (
        Param("V0", "m^3", 1e-3, "gas volume at precharge (nominal size)", positive=True, bounds=(1e-6, 1.0)),
        Param("p0", "Pa", 5e6, "gas precharge pressure (absolute)", positive=True, bounds=(1e5, 3e7)),
        Param("n", "1", 1.4, "polytropic exponent", min=1.0, max=1.67),
        Param("V_oil", "m^3", 1e-5, "oil dead volume (port, fittings)", positive=True),
        Param("beta", "Pa", 1.5e9, "oil bulk modulus", fluid="beta", positive=True),
        Param("eps_p", "Pa", 1e4, "smoothing of the precharge switch", positive=True),
    )
    variables = (VariableSpec("V_gas", "m^3", "gas volume"),)

    def equations(self, c):
        p = c.p
        pp = E.fmax(c.across("P"), 1e3)
        on = 0.5 * (1.0 + E.tanh((pp - p.p0) / p.eps_p))
        v_gas = c.let("V_gas", p.V0 * E.power(p.p0 / E.fmax(pp, p.p0), 1.0 / p.n))
        c.capacitance("P", on * v_gas / (p.n * pp) + p.V_oil / p.beta)
