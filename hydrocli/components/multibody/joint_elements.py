"""Sensing a joint port of a ``serial_chain`` as signals (springs, dampers and torque sources
on joints are the rotational library's ``shaft``, ``rotary_damper``, ``torque_source``)."""
from __future__ import annotations

from ..base import Component, Param, Port, R, S
from ..registry import register


@register
class AngleSensor(Component):
    """Joint angle (and optionally rate) as signals, e.g. for a joint PID (seed 002 Fig. 7)."""

    type = "angle_sensor"
    family = "multibody"
    description = "Joint angle / rate sensor"
    source = "seed 002 §4 (resolvers)"
    ports = (Port("j", R, "joint"), Port("angle", S, "angle [rad]", direction="out"),
             Port("rate", S, "rate [rad/s]", optional=True, direction="out"))
    parameters = (Param("offset", "rad", 0.0, "added to the measured angle"),)

    def equations(self, c):
        c.drive("angle", c.position("j") + c.p.offset)
        if c.connected("rate"):
            c.drive("rate", c.across("j"))
