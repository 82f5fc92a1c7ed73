"""Gear train: ideal transformer with viscous loss (seed 002 Fig. 3, eq. 5)."""
from __future__ import annotations

from ..base import Component, Param, Port, R, VariableSpec
from ..registry import register


@register
class Gearbox(Component):
    """Gear ratio N between the input (motor) node and the output (load) node:
    ω_in = N·ω_out, τ_out = N·τ_in − B_sw·ω_out (seed 002 eq. 5 with B_sw, §3d).

    The gearbox is the source of the input node's velocity (an ideal transformer is a
    constraint), so the input node must carry no inertia of its own: give the motor-side
    inertia as ``J_in``; it is reflected to the output as N²·J_in. The output node needs an
    inertia (or a mechanism imposing its motion).
    """

    type = "gearbox"
    family = "rotational"
    description = "Gear train (transformer) with ratio N, viscous loss B_sw and reflected input inertia"
    source = "seed 002 Fig. 3, eq. 5, §3d (B_sw = 2.45e4 N·m·s/rad)"
    ports = (Port("in", R, "input shaft (motor side); driven by the gearbox"),
             Port("out", R, "output shaft (load side)"))
    parameters = (
        Param("N", "1", 10.0, "gear ratio ω_in/ω_out", positive=True, bounds=(0.01, 1e4)),
        Param("B_sw", "N*m*s/rad", 0.0, "viscous damping on the output shaft", min=0.0, bounds=(0.0, 1e6)),
        Param("J_in", "kg*m^2", 0.0, "inertia on the input side (motor rotor), reflected as N²·J_in", min=0.0),
    )
    variables = (VariableSpec("tau_in", "N*m", "torque delivered to the input shaft by what drives it"),
                 VariableSpec("tau_out", "N*m", "torque delivered to the output shaft"))

    def equations(self, c):
        p = c.p
        w_out = c.across("out")
        c.impose("in", p.N * w_out, position=p.N * c.position("out"))
        tau_in = c.let("tau_in", -c.node_through("in"))
        tau_out = c.let("tau_out", p.N * tau_in - p.B_sw * w_out)
        c.through("out", -tau_out)
        if c.active("J_in"):
            c.capacitance("out", p.N * p.N * p.J_in)
