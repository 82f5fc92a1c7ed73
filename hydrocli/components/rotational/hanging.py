"""A payload hanging on a rope from the tip of an arm that swings in a vertical plane (a
loader's or a luffing boom's joint), in the joint's coordinates: the exact two-link pendulum.

The tip at radius r is at r·(sin α, −cos α), α = θ + θ0 (θ0 as the arm's gravity load has it:
α = 0 hangs straight down); the bob of mass m_p = J_p/r² hangs on a rope of length L at the
angle φ from the vertical (Meirovitch, *Fundamentals of Vibrations* §6.2; the double pendulum's
Lagrangian). With ψ = α − φ and the arm's rate ω:

    T = ½ m_p (r² ω² + L² φ̇² + 2 r L ω φ̇ cos ψ),   V = −m_p g (r cos α + L cos φ),
    bob:  L φ̈ = r ω² sin ψ − g sin φ − r ω̇ cos ψ − c φ̇ /(m_p L)
    arm:  inertia J_p sin²ψ (what the bob does not take along), and the torque (in +θ)
          τ = −J_p ω² sin ψ cos ψ + m_p g r cos ψ sin φ + (r/L) c φ̇ cos ψ − m_p r L φ̇² sin ψ.

The bob's equation reads the arm's angular acceleration ω̇ (``Context.rate``: the joint's
torque balance, itself a function of the states once the bob's inertia is split as above).
The rope's tension follows the tip's acceleration, so on an arm that accelerates at r·ω̇ ~ g
the swing is parametric, not the tangential spring–mass (m_p r² on m_p g r²/L) that the
hanging pose and a slow arm reduce it to. The damping c acts on the rope's angle (the
payload's air drag). The bob's weight moment m_p·g·r·sin α is the arm's gravity load's (a free
weight moment takes it), so J_p, L and r set only the swing."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, Param, Port, R, StateSpec, VariableSpec
from ..registry import register
from .. import roles as RL
from ..roles import role

G = 9.81


@register
class HangingPayload(Component):
    """Payload on a rope from an arm's tip, the exact pendulum (module docstring)."""

    type = "hanging_payload"
    roles = (role(RL.PENDULUM, {"node": "r"}, inertia="J_p", length="L", radius="r", damping="c",
                  hanging="theta0"),)
    family = "rotational"
    description = "Payload on a rope from an arm's tip: the exact pendulum on a moving support"
    source = "Meirovitch, Fundamentals of Vibrations §6.2 (double pendulum)"
    ports = (Port("r", R, "the arm's joint"),)
    parameters = (
        Param("J_p", "kg*m^2", 0.01, "the payload's inertia about the joint, m_p·r²", positive=True, bounds=(1e-9, 1e6)),
        Param("L", "m", 1.0, "the rope's length (swing √(g/L))", positive=True, bounds=(1e-3, 1e3)),
        Param("r", "m", 0.5, "the arm's radius to the rope's pivot", positive=True, bounds=(1e-3, 1e3)),
        Param("c", "N*m*s/rad", 0.0, "damping of the rope's angle", min=0.0, bounds=(0.0, 1e6)),
        Param("theta0", "rad", 0.0, "angle from the hanging position at θ = 0 (as the arm's gravity_load)"),
    )
    states = (StateSpec("phi", "rad", "the rope's angle from the vertical", nominal=1e-3),
              StateSpec("phid", "rad/s", "the rope's angular speed", nominal=1e-3))
    variables = (VariableSpec("tau", "N*m", "torque of the rope on the arm (in +θ)"),)

    def equations(self, c):
        p = c.p
        a = c.position("r") + p.theta0
        phi, phid = c.state("phi"), c.state("phid")
        w = c.across("r")
        psi = a - phi
        s, co = E.sin(psi), E.cos(psi)
        m = p.J_p / (p.r * p.r)
        drag = p.c * phid if c.active("c") else 0.0
        c.der("phi", phid)
        c.der("phid", (p.r * w * w * s - G * E.sin(phi) - p.r * c.rate("r") * co) / p.L - drag / (m * p.L * p.L))
        c.capacitance("r", p.J_p * s * s)
        tau = c.let("tau", -p.J_p * w * w * s * co + m * G * p.r * co * E.sin(phi)
                    + (p.r / p.L) * drag * co - m * p.r * p.L * phid * phid * s)
        c.through("r", -tau)
