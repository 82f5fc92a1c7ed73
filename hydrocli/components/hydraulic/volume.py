"""Hydraulic capacitance: a fixed volume of compressible oil (hose, block, accumulator dead volume)."""
from __future__ import annotations

from ..base import Component, H, Param, Port
from ..registry import register
from .fluid import AIR_PARAMS, cavitation_floor, oil_bulk_modulus
from .. import roles as RL
from ..roles import role


@register
class Volume(Component):
    """C = V/β_e on its node, so that C·dp/dt = Σq (seed 004 eqs. 4–7 without the piston term)."""

    type = "volume"
    roles = (role(RL.VOLUME, {"node": "P"}, volume="V", air="air", bulk_modulus="beta"),)
    family = "hydraulic"
    description = "Lumped oil volume (capacitance V/β) on a node"
    source = "seed 004 eqs. 6–7; seed 002 §3 (fluid capacitance)"
    ports = (Port("P", H, "node"),)
    parameters = (
        Param("V", "m^3", 1e-4, "oil volume", positive=True, bounds=(1e-7, 1e-1)),
        Param("beta", "Pa", 1.5e9, "oil bulk modulus", fluid="beta", positive=True, bounds=(1e8, 2.5e9)),
        *AIR_PARAMS,
    )

    def equations(self, c):
        cap = c.p.V / oil_bulk_modulus(c, c.across("P"))
        c.capacitance("P", cap)
        cavitation_floor(c, "P", cap)
