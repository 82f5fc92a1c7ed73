"""A joint with clearance (backlash): a worn clevis pin or bushing between a rod and its load, a
spline or key with play between a shaft and what it turns. The two parts float freely across
the clearance and meet a stiff, damped contact at either side of it (the dead-zone model of
backlash: Nordin & Gutman, "Controlling mechanical systems with backlash — a survey",
Automatica 38 (2002), §2, eqs. 2–3; the damping acts in contact only):

    d' = v_a − v_b,   F = k·D(d) + c·D'(d)·(v_a − v_b)

D the dead zone of total width b (:func:`..dynamics.dead_zone`, its corners smoothed over
w·b + ε); b = 0 is the spring–damper k, c exactly. The relative displacement d is the state
(a force state cannot say where inside the clearance the parts float)."""
from __future__ import annotations

from ..base import Component, Param, Port, R, StateSpec, T, VariableSpec
from ..dynamics import dead_zone
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role

SMOOTHING = 0.02   # the dead zone's corners are rounded over this share of the clearance


class _Clearance(Component):
    """The equations of both domains (translational here, rotational below)."""

    family = "mechanical"
    source = "Nordin & Gutman, Automatica 38 (2002) §2, eqs. 2–3 (dead-zone backlash with contact damping)"

    def equations(self, c):
        v = across_drop(c)
        dz, slope = dead_zone(c.state("d"), c.p.b, SMOOTHING * c.p.b + c.p.eps)
        c.der("d", v)
        branch(c, self.through_name, c.p.k * dz + c.p.c * slope * v)


@register
class Clearance(_Clearance):
    type = "clearance"
    through_name = "F"
    roles = (role(RL.CLEARANCE, {"a": "a", "b": "b"}, stiffness="k", damping="c", gap="b"),)
    description = "Joint with clearance (backlash): stiff damped contact beyond a dead band"
    ports = (Port("a", T, "one part (a rod, a piston)"), Port("b", T, "the other (the load)"))
    parameters = (
        Param("k", "N/m", 1e8, "contact stiffness once the clearance is taken up", positive=True, bounds=(1.0, 1e12)),
        Param("c", "N*s/m", 1e3, "contact damping (in contact only)", min=0.0, bounds=(0.0, 1e8)),
        Param("b", "m", 0.0, "total clearance (the free play from one contact to the other; 0: none)",
              min=0.0, bounds=(0.0, 0.05)),
        Param("eps", "m", 1e-7, "floor of the corners' rounding (keeps b = 0 smooth)", positive=True),
    )
    states = (StateSpec("d", "m", "relative displacement x_a − x_b (0: centred in the clearance)", nominal=1e-3),)
    variables = (VariableSpec("F", "N", "force through the joint"),)


@register
class RotaryClearance(_Clearance):
    type = "rotary_clearance"
    family = "rotational"
    through_name = "tau"
    roles = (role(RL.CLEARANCE, {"a": "a", "b": "b"}, stiffness="k", damping="c", gap="b"),)
    description = "Rotary joint with clearance (spline or key play): stiff damped contact beyond a dead band"
    ports = (Port("a", R, "the driving part (a vane, a motor shaft)"), Port("b", R, "the driven part (the load)"))
    parameters = (
        Param("k", "N*m/rad", 1e6, "contact stiffness once the play is taken up", positive=True, bounds=(1.0, 1e10)),
        Param("c", "N*m*s/rad", 10.0, "contact damping (in contact only)", min=0.0, bounds=(0.0, 1e6)),
        Param("b", "rad", 0.0, "total play (from one flank to the other; 0: none)", min=0.0, bounds=(0.0, 0.5)),
        Param("eps", "rad", 1e-6, "floor of the corners' rounding (keeps b = 0 smooth)", positive=True),
    )
    states = (StateSpec("d", "rad", "relative angle θ_a − θ_b (0: centred in the play)", nominal=1e-2),)
    variables = (VariableSpec("tau", "N*m", "torque through the joint"),)
