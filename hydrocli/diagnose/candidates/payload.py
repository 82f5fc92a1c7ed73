"""A swinging payload on a ROTARY drive (a load hanging on a rope from an arm: a harvester's
head, a crane's hook seen from the slewing or luffing joint).

A payload of mass m_p on a rope of length L hanging at radius r from the joint, for small
swing angles, is a tangential spring–mass on the arm: the rope's restoring force
m_p·g·s/L on the tangential offset s = r·(φ − θ) gives, in the joint's coordinates, an inertia
J_p = m_p·r² coupled to the arm by a torsion spring k = m_p·g·r²/L = J_p·g/L (Meirovitch,
*Fundamentals of Vibrations* §6.2; seed 002 §4 treats the harvester head this way). Both J_p
(how much swings) and k (its frequency √(k/J_p) = √(g/L)) are identified, so neither r nor L
needs to be known; elements are the rotational load and spring found by role.
"""
from __future__ import annotations

from ...components import roles as R
from ...components.base import Domain
from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Part, Skipped

G = 9.81
L_START = 1.0        # m: rope length of the start and probe values (frequency 0.5 Hz)


class RotaryPayloadFamily(Family):
    effects = ("payload_swing",)

    def candidates(self, ctx: Context):
        out = []
        for act in ctx.parts(R.ACTUATOR):
            node = act.node("motion")
            if ctx.domain(node) != Domain.ROTATIONAL:
                continue
            loads = ctx.parts_on(node, R.LOAD)
            if not loads:
                out.append(Skipped("payload_swing", f"no inertia on the rotary node '{node}' of '{act.name}'"))
                continue
            out.append(_payload(ctx, act, node, loads[0]))
        return out


def _payload(ctx: Context, act: Part, node: str, load: Part) -> Candidate:
    try:
        J = abs(float(ctx.value(load.param("inertia"))))
    except (KeyError, TypeError, ValueError):
        J = 1.0
    ltype, lrole = ctx.element(R.LOAD, Domain.ROTATIONAL)
    stype, srole = ctx.element(R.SPRING, Domain.ROTATIONAL)
    swing = A.unique_name(ctx.net, f"{node}_payload")
    pj, rope = A.unique_name(ctx.net, "payload_inertia"), A.unique_name(ctx.net, "payload_rope")
    jp, kp = f"{pj}.{lrole.param('inertia')}", f"{rope}.{srole.param('stiffness')}"
    j0 = 1e-3 * J
    params = [NewParam(jp, j0, (1e-4 * J, 2.0 * J), (0.02 * J, 2.0 * J), 0.3 * J, True),
              # k/J_p = g/L: rope lengths 5 cm … 50 m (log scale); a companion (shapes the swing)
              NewParam(kp, j0 * G / L_START, (1e-4 * J * G / 50.0, 2.0 * J * G / 0.05),
                       (1e-4 * J * G / 50.0, 2.0 * J * G / 0.05), 0.3 * J * G / L_START, True, primary=False)]

    def build(net):
        net = A.add(net, pj, ltype, {lrole.port("node"): swing}, {lrole.param("inertia"): j0})
        net = A.add(net, rope, stype, {srole.port("a"): node, srole.port("b"): swing},
                    {srole.param("stiffness"): j0 * G / L_START})
        return A.free_new(net, params)
    return Candidate("payload_swing", act.name, params, build, "force",
                     f"a payload swinging on a rope from the arm of '{act.name}' (tangential spring–mass)",
                     variant="rotary")
