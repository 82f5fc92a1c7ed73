"""A base fit that hides an effect in a physically implausible value, and the same fit
restrained to what the physics allows.

The base fit is free to move the oil's bulk modulus in the actuator chambers. Far below what
oil can have it stands in for a compliance the machine file lacks (DESIGN.md, diagnosis step
1): free air, a hose, a compliant mount or rod–load link. A softer oil explains such data
only roughly — air softens with falling pressure, a hose sits between the valve and the
chamber, a mount behind the body — but well enough that, from that base, none of those
effects screens above the noise. An engineer who sees β = 0.6 GPa says "that is not oil" and
asks which compliance it is: the effects are then tested on a base whose bulk modulus is
RESTRAINED to what oil with dissolved air, seal and wall elasticity can have (≥ 1.0 GPa;
mineral oil 1.4–1.8 GPa, Merritt 1967 §2.5; seed 004 identifies 1.73 GPa), and each must
beat the free base — low β included — on BIC and on held-out data (``engine.round_step``'s
``floor``).

Only the actuators' own bulk modulus (role slot ``bulk_modulus``) is restrained: a hose or a
volume element may legitimately carry a low effective modulus (wall elasticity).
"""
from __future__ import annotations

from ..components import roles as R
from ..netlist.model import Netlist
from . import augment
from .candidates import Context

OIL_MIN = 1.0e9   # Pa: the softest effective bulk modulus of oil in a rigid chamber


def limits(ctx: Context, estimates: dict[str, float], bounds: dict[str, tuple[float, float]]) \
        -> dict[str, tuple[float, float]]:
    """Free actuator bulk moduli the base fit left below :data:`OIL_MIN`: name → restrained
    bounds (``OIL_MIN``, the file's upper bound)."""
    out = {}
    for act in ctx.parts(R.ACTUATOR):
        name = act.param("bulk_modulus")
        if name in estimates and estimates[name] < OIL_MIN and name in bounds:
            out[name] = (OIL_MIN, max(bounds[name][1], 1.5 * OIL_MIN))
    return out


def apply(net: Netlist, lim: dict[str, tuple[float, float]]) -> Netlist:
    """The machine with each restrained parameter free within its restrained bounds, starting
    at the lower one (the closest plausible value to what the base fit wanted)."""
    for name, (lo, hi) in lim.items():
        net = augment.free(net, name, lo, (lo, hi))
    return net
