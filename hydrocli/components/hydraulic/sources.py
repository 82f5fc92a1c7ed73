"""Hydraulic sources: tank, pressure source, flow source."""
from __future__ import annotations

from ..base import Component, H, Param, Port, S, VariableSpec
from ..registry import register
from ..two_port import signal_or_param
from .. import roles as RL
from ..roles import role


@register
class Tank(Component):
    """Reservoir: imposes the tank pressure on its node (absolute pressure)."""

    type = "tank"
    roles = (role(RL.TANK, {"node": "T"}),)
    family = "hydraulic"
    description = "Reservoir at constant (absolute) pressure"
    source = "seed 004 §III.A (P_d)"
    ports = (Port("T", H, "tank node"),)
    parameters = (Param("p", "Pa", 1e5, "tank pressure (absolute)", fluid="p_tank", min=0.0),)
    variables = (VariableSpec("q", "m^3/s", "flow into the tank"),)

    def equations(self, c):
        c.impose("T", c.p.p)
        c.let("q", c.node_through("T"))


@register
class PressureSource(Component):
    """Ideal pressure source: the constant ``p`` or, when ``ref`` is connected, that signal."""

    type = "pressure_source"
    roles = (role(RL.PRESSURE_SOURCE, {"out": "P", "reference": "ref"}, pressure="p"),)
    family = "hydraulic"
    description = "Ideal pressure source (constant, or following a signal such as a recorded supply pressure)"
    source = "seed 004 §III.A (P_s)"
    ports = (Port("P", H, "pressure node"), Port("ref", S, "pressure set-point [Pa]", optional=True, direction="in"))
    parameters = (Param("p", "Pa", 1e7, "pressure when 'ref' is not connected", min=0.0),)
    variables = (VariableSpec("q", "m^3/s", "flow delivered into the node"),)

    def equations(self, c):
        c.impose("P", signal_or_param(c, "ref", "p"))
        c.let("q", c.node_through("P"))


@register
class FlowSource(Component):
    """Ideal flow source (a fixed-displacement pump at constant speed, say)."""

    type = "flow_source"
    family = "hydraulic"
    description = "Ideal flow source into port P (constant, or following a signal)"
    source = "linear-graph through-variable source (seed 002 §3)"
    ports = (Port("P", H, "delivery node"), Port("ref", S, "flow set-point [m^3/s]", optional=True, direction="in"))
    parameters = (Param("Q", "m^3/s", 0.0, "flow when 'ref' is not connected"),)

    def equations(self, c):
        c.through("P", -signal_or_param(c, "ref", "Q"))
