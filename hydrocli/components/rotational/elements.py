"""Rotational elements: inertia, torsion shaft, rotary damper, torque source, gravity load,
Coulomb friction (seed 001 eqs. 14–15)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, Param, Port, R, S, StateSpec, VariableSpec
from ..dynamics import spring_stiffness
from ..mechanical.friction import friction_force
from ..registry import register
from ..two_port import across_drop, branch, signal_or_param
from .. import roles as RL
from ..roles import role


@register
class Inertia(Component):
    """J·dω/dt = Στ on its node (J_v, J_l of seed 001 eqs. 14–15); optional constant torque."""

    type = "inertia"
    roles = (role(RL.LOAD, {"node": "r"}, inertia="J"),)
    family = "rotational"
    description = "Rotary inertia on a rotational node"
    source = "seed 001 eqs. 14–15 (J_v, J_l)"
    ports = (Port("r", R, "the node the inertia rotates with"),)
    parameters = (
        Param("J", "kg*m^2", 1.0, "moment of inertia", positive=True, bounds=(1e-6, 1e6)),
        Param("tau_const", "N*m", 0.0, "constant torque in +θ"),
    )
    variables = (VariableSpec("theta", "rad", "angle"), VariableSpec("w", "rad/s", "angular velocity"))

    def equations(self, c):
        c.capacitance("r", c.p.J)
        c.through("r", -c.p.tau_const)
        c.let("theta", c.position("r"))
        c.let("w", c.across("r"))


ROPE_MIN = 0.25   # a wound rope's shortest length, as a share of its length at θ = 0 (``Shaft.wind``)


@register
class Shaft(Component):
    """Torsion spring-damper between a and b: τ = k_s(θ_a − θ_b) + b_s(ω_a − ω_b), the spring
    torque a state, dτ_k/dt = k_s(ω_a − ω_b) (seed 001 eqs. 14–15; k_s = 8.9e4 lb·in/rad
    measured, §4.2.2). A hardening ``h`` > 0 (default 0: linear) stiffens it with the torque it
    carries, dτ_k/dt = k_s·(1 + h·τ_k²)(ω_a − ω_b) (a progressive coupling; see ``spring``);
    the cubic hardening ``hc`` makes it the Duffing spring τ_k = k_s·Δθ·(1 + hc·(k_s·Δθ)²/3).

    A wire rope that a drum at ``a`` pays out, in the drum's coordinates, is this element with
    the winding ``wind`` = r/L₀ (drum radius over the rope's length at θ_a = 0): a rope's
    stiffness is EA/L and winding shortens it, L = L₀·(1 − wind·θ_a), so
    k = k_s/(1 − wind·θ_a), the rope kept at least ``ROPE_MIN`` of L₀ (wind < 0: winding on
    lengthens it). 0 (default): a shaft."""

    type = "shaft"
    roles = (role(RL.SPRING, {"a": "a", "b": "b"}, stiffness="k", hardening="h", cubic="hc", winding="wind"),)
    family = "rotational"
    description = "Torsion spring-damper shaft (spring torque as state)"
    source = "seed 001 eqs. 14–15, eq. 19"
    ports = (Port("a", R, "driving end (vane)"), Port("b", R, "driven end (load)"))
    parameters = (
        Param("k", "N*m/rad", 1.0056e4, "torsional stiffness k_s (8.9e4 lb·in/rad)", source="seed 001 §4.2.2",
              positive=True, bounds=(1.0, 1e9)),
        Param("b", "N*m*s/rad", 0.0, "shaft damping b_s", min=0.0, bounds=(0.0, 1e5)),
        Param("h", "1/(N*m)^2", 0.0, "hardening: the stiffness is k_s·(1 + h·τ_k²) (0: linear)", min=0.0),
        Param("hc", "1/(N*m)^2", 0.0, "cubic hardening: τ_k = k_s·Δθ·(1 + hc·(k_s·Δθ)²/3) (0: linear)", min=0.0),
        Param("wind", "1/rad", 0.0, "a rope paid out by a drum at a: r/L₀, the stiffness k_s/(1 − wind·θ_a) "
                                    "(0: a shaft)", bounds=(-1.0, 1.0)),
    )
    states = (StateSpec("tau_k", "N*m", "spring torque k_s(θ_a − θ_b)", nominal=10.0),)
    variables = (VariableSpec("tau", "N*m", "transmitted torque"),)

    def equations(self, c):
        dw = across_drop(c)
        tk = c.state("tau_k")
        k = spring_stiffness(c.p.k, tk, c.p.h if c.active("h") else None, c.p.hc if c.active("hc") else None)
        if c.active("wind"):
            k = k / E.fmax(1.0 - c.p.wind * c.position("a"), ROPE_MIN)
        c.der("tau_k", k * dw)
        branch(c, "tau", tk + (c.p.b * dw if c.active("b") else 0.0))


@register
class RotaryDamper(Component):
    """Viscous rotary damper τ = b·(ω_a − ω_b) (b_vn, b_l of seed 001; B_sw of seed 002)."""

    type = "rotary_damper"
    roles = (role(RL.DAMPER, {"a": "a", "b": "b"}, damping="b"),)
    family = "rotational"
    description = "Linear viscous rotary damper"
    source = "seed 001 eqs. 14–15; seed 002 §3d"
    ports = (Port("a", R, "end a"), Port("b", R, "end b"))
    parameters = (Param("b", "N*m*s/rad", 1.0, "damping coefficient", min=0.0, bounds=(0.0, 1e6)),)
    variables = (VariableSpec("tau", "N*m", "damper torque"),)

    def equations(self, c):
        branch(c, "tau", c.p.b * across_drop(c))


@register
class TorqueSource(Component):
    """External torque on node a (τ_ext of seed 001 eq. 15), constant or from a signal."""

    type = "torque_source"
    family = "rotational"
    description = "Ideal torque source acting on a rotational node"
    source = "seed 001 eq. 15 (τ_ext)"
    ports = (Port("a", R, "node the torque acts on"),
             Port("tau", S, "torque signal [N m]", optional=True, direction="in"))
    parameters = (Param("tau0", "N*m", 0.0, "torque when the signal port is not connected"),)

    def equations(self, c):
        c.through("a", -signal_or_param(c, "tau", "tau0"))


@register
class GravityLoad(Component):
    """Gravity torque −W·sin(θ + θ0) on a pendulum load (seed 001 eq. 15, W_l = m·g·r)."""

    type = "gravity_load"
    roles = (role(RL.WEIGHT, {"node": "r"}, weight="W", hanging="theta0"),)
    family = "rotational"
    description = "Gravity torque of a pendulum load, −W·sin(θ + θ0)"
    source = "seed 001 eq. 15"
    ports = (Port("r", R, "load node"),)
    parameters = (
        Param("W", "N*m", 10.0, "weight moment W_l = m·g·r_cg", min=0.0, bounds=(0.0, 1e6)),
        Param("theta0", "rad", 0.0, "angle from the hanging position at θ = 0"),
    )
    variables = (VariableSpec("tau", "N*m", "gravity torque (in +θ)"),)

    def equations(self, c):
        tau = c.let("tau", -c.p.W * E.sin(c.position("r") + c.p.theta0))
        c.through("r", -tau)


@register
class RotaryFriction(Component):
    """Coulomb (+ viscous, + Stribeck) friction between rotational nodes a and b:
    τ = b·ω + (τ_c + τ_s·e^(−|ω|/ω_s))·tanh(ω/ε) (τ_coul of seed 001 eqs. 14–15; same law as
    the translational ``friction``, seed 004 eqs. 9–11)."""

    type = "rotary_friction"
    roles = (role(RL.FRICTION, {"a": "a", "b": "b"}, viscous="b", coulomb="tau_c", stribeck="tau_s", stribeck_speed="w_s", band="eps"),)
    family = "rotational"
    description = "Coulomb/viscous/Stribeck friction on a rotational node (vane seals, load bearing)"
    source = "seed 001 eqs. 14–15 (τ_coul); seed 004 eqs. 9–11"
    ports = (Port("a", R, "moving side"), Port("b", R, "fixed side (ground)"))
    parameters = (
        Param("tau_c", "N*m", 1.0, "Coulomb torque", min=0.0, bounds=(0.0, 1e5)),
        Param("b", "N*m*s/rad", 0.0, "viscous coefficient", min=0.0, bounds=(0.0, 1e5)),
        Param("tau_s", "N*m", 0.0, "Stribeck (breakaway excess) torque", min=0.0, bounds=(0.0, 1e5)),
        Param("w_s", "rad/s", 0.01, "Stribeck velocity", positive=True),
        Param("eps", "rad/s", 1e-3, "tanh smoothing velocity", positive=True),
    )
    variables = (VariableSpec("tau", "N*m", "friction torque opposing a relative to b"),)

    def equations(self, c):
        p = c.p
        tau = c.let("tau", friction_force(c.across("a") - c.across("b"), p.b, p.tau_c, p.tau_s, p.w_s, p.eps))
        c.through("a", tau)
        c.through("b", -tau)
