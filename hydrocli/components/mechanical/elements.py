"""Translational elements: mass, spring, damper, force source."""
from __future__ import annotations

from ..base import Component, Param, Port, S, StateSpec, T, VariableSpec
from ..dynamics import spring_stiffness
from ..registry import register
from ..two_port import across_drop, branch, signal_or_param
from .. import roles as RL
from ..roles import role


@register
class Mass(Component):
    """m·dv/dt = ΣF on its node (seed 004 eq. 8); an optional constant force (e.g. weight
    on an inclined or vertical axis) acts in +x."""

    type = "mass"
    roles = (role(RL.LOAD, {"node": "m"}, inertia="m"),)
    family = "mechanical"
    description = "Point mass on a translational node (with an optional constant force such as weight)"
    source = "seed 004 eq. 8"
    ports = (Port("m", T, "the node the mass moves with"),)
    parameters = (
        Param("m", "kg", 1.0, "moved mass", positive=True, bounds=(1e-3, 1e5)),
        Param("F_const", "N", 0.0, "constant force in +x (e.g. −m·g on a vertical axis)"),
    )
    variables = (VariableSpec("x", "m", "position"), VariableSpec("v", "m/s", "velocity"),
                 VariableSpec("a", "m/s^2", "acceleration"))

    def equations(self, c):
        c.capacitance("m", c.p.m)
        c.through("m", -c.p.F_const)
        c.let("x", c.position("m"))
        c.let("v", c.across("m"))


@register
class Spring(Component):
    """Spring between a and b; its force is a state: dF/dt = k·(1 + h·F²)·(v_a − v_b)
    (the through variable of an inductive element, linear-graph convention). Linear with the
    hardening ``h`` = 0 (default); h > 0 stiffens it with the force it carries — a rubber
    bushing or a clevis that firms up under load, whose tangent stiffness k + 3k₃d² of
    F = k·d + k₃·d³ is, to first order in k₃, k·(1 + h·F²) with h = 3k₃/k³. The cubic
    hardening ``hc`` (default 0) is that Duffing spring exactly, F = k·d·(1 + hc·(k·d)²/3)
    (``components.dynamics.spring_stiffness``); use one of h and hc."""

    type = "spring"
    roles = (role(RL.SPRING, {"a": "a", "b": "b"}, stiffness="k", hardening="h", cubic="hc"),)
    family = "mechanical"
    description = "Linear spring (force as state)"
    source = "linear-graph inductive element (seed 002 §3); seed 000 eq. 2"
    ports = (Port("a", T, "end a"), Port("b", T, "end b"))
    parameters = (
        Param("k", "N/m", 1e5, "stiffness", positive=True, bounds=(1.0, 1e10)),
        Param("F0", "N", 0.0, "initial tension force (+ pulls a toward b)"),
        Param("h", "1/N^2", 0.0, "hardening: the stiffness is k·(1 + h·F²) (0: linear)", min=0.0),
        Param("hc", "1/N^2", 0.0, "cubic hardening: F = k·d·(1 + hc·(k·d)²/3), i.e. k₃ = hc·k³/3 "
                                  "(0: linear)", min=0.0),
    )
    states = (StateSpec("dF", "N", "tension change since t0, ∫k(F)·(v_a − v_b)dt", nominal=100.0),)
    variables = (VariableSpec("F", "N", "spring tension F0 + dF"),)

    def equations(self, c):
        f = c.p.F0 + c.state("dF")
        k = spring_stiffness(c.p.k, f, c.p.h if c.active("h") else None, c.p.hc if c.active("hc") else None)
        c.der("dF", k * across_drop(c))
        branch(c, "F", f)


@register
class Damper(Component):
    """Viscous damper F = c·(v_a − v_b) (seed 002: B_bm, B_sk)."""

    type = "damper"
    roles = (role(RL.DAMPER, {"a": "a", "b": "b"}, damping="c"),)
    family = "mechanical"
    description = "Linear viscous damper"
    source = "seed 004 eq. 9; seed 002 §4 (B)"
    ports = (Port("a", T, "end a"), Port("b", T, "end b"))
    parameters = (Param("c", "N*s/m", 1e3, "damping coefficient", min=0.0, bounds=(0.0, 1e7)),)
    variables = (VariableSpec("F", "N", "damper force"),)

    def equations(self, c):
        branch(c, "F", c.p.c * across_drop(c))


@register
class ForceSource(Component):
    """External force on node a (positive in +x), constant or from a signal (F_ext, seed 004 eq. 8)."""

    type = "force_source"
    family = "mechanical"
    description = "Ideal force source acting on a node (e.g. the recorded external load)"
    source = "seed 004 eq. 8 (F_ext)"
    ports = (Port("a", T, "node the force acts on"),
             Port("F", S, "force signal [N]", optional=True, direction="in"))
    parameters = (Param("F0", "N", 0.0, "force when the signal port is not connected"),)

    def equations(self, c):
        c.through("a", -signal_or_param(c, "F", "F0"))
