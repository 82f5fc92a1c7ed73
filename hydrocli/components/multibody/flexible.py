"""``flexible_member``: the rotational springs and dampers of a finite-segment flexible member.

Finite segment method (seed 000 §3.2, Huston 1981): a flexible member is split into rigid
segments (bodies of a ``serial_chain``) joined by revolute joints; each segment's bending
flexibility is two rotational springs of stiffness

    k_S = 2·E·I / L                                   (seed 000 eq. 3)

so the connection between segments 1 and 2 has the series stiffness

    k_C = 1 / (1/k_S,1 + 1/k_S,2)                     (eq. 2)

and a rigid neighbour (k_S = 0 here means rigid) leaves k_C = k_S of the flexible one (the
rule behind Table 2). Stiffness-proportional damping c = β_k·k (eq. 4), with
β_k = 2ζ_S/ω_S (eq. 5). ``stiffness_scale`` multiplies every spring of the member, so
identification tunes them together (seed 000 §5.3 ended at 0.55).

Ports ``c1…c8`` are the connections in order, each joined to a joint port of the chain: the
first connection is between segment 1 and segment 2, and so on. A member clamped to a rigid
part (a cantilever root) lists that part as a rigid first segment (k_S = 0).
"""
from __future__ import annotations

from ..base import Component, Param, Port, R
from ..registry import register

MAX_CONNECTIONS = 8


def segment_stiffness(EI, length):
    """k_S = 2·E·I/L (seed 000 eq. 3)."""
    return 2.0 * EI / length


def connection_stiffness(k1, k2):
    """Series connection of two segment springs (seed 000 eq. 2); None means rigid."""
    if k1 is None and k2 is None:
        raise ValueError("two adjoining rigid segments have no connection spring")
    if k1 is None:
        return k2
    if k2 is None:
        return k1
    return k1 * k2 / (k1 + k2)


def damping_multiplier(zeta, omega):
    """β_k = 2·ζ_S/ω_S (seed 000 eq. 5)."""
    return 2.0 * zeta / omega


@register
class FlexibleMember(Component):
    type = "flexible_member"
    family = "multibody"
    description = "Finite-segment flexibility: connection springs from segment stiffnesses, stiffness damping"
    source = "seed 000 eqs. 2–5, Tables 2–3"
    ports = tuple(Port(f"c{i}", R, f"connection {i} (between segments {i} and {i + 1})", optional=True)
                  for i in range(1, MAX_CONNECTIONS + 1))
    parameters = (
        Param("k_S", "N*m/rad", [], "segment stiffnesses (0 = rigid segment); or give EI and L", vector=True,
              min=0.0),
        Param("EI", "N*m^2", [], "segment bending stiffness E·I (0 = rigid), used with L", vector=True, min=0.0),
        Param("L", "m", [], "segment lengths, used with EI", vector=True, min=0.0),
        Param("stiffness_scale", "1", 1.0, "factor on every spring of the member (seed 000 §5.3: 0.55)",
              positive=True, bounds=(0.1, 2.0)),
        Param("beta_k", "s", 0.0, "stiffness multiplier of the damping c = β_k·k (seed 000 eqs. 4–5, Table 3)",
              min=0.0, bounds=(0.0, 0.02)),
    )

    def check(self, values):
        ks, ei, ln = values["k_S"], values["EI"], values["L"]
        if bool(ks) == bool(ei):
            return ["give either k_S or EI (with L) for every segment"]
        if ei and len(ln) != len(ei):
            return ["L needs one length per EI entry"]
        if ei and any(v <= 0 for v in ln):
            return ["segment lengths L must be > 0"]
        n = len(ks or ei)
        if not 2 <= n <= MAX_CONNECTIONS + 1:
            return [f"a member needs 2…{MAX_CONNECTIONS + 1} segments"]
        flags = [v > 0 for v in (ks or ei)]
        if any(not a and not b for a, b in zip(flags, flags[1:])):
            return ["two adjoining rigid segments: merge them into one"]
        return []

    def equations(self, c):
        for i, k in enumerate(member_connections(c), start=1):
            port = f"c{i}"
            if not c.connected(port):
                raise ValueError(f"connection {i} has no joint: connect port {port}")
            k = c.let(f"k_C{i}", c.p.stiffness_scale * k, "N*m/rad")
            c.through(port, c.let(f"T{i}", k * c.position(port) + c.p.beta_k * k * c.across(port), "N*m"))


def member_connections(c) -> list:
    """Unscaled connection stiffness expressions, one per connection (eqs. 2–3)."""
    if c.value("k_S"):
        vals, syms = c.value("k_S"), c.p.k_S
        seg = [s if v > 0 else None for v, s in zip(vals, syms)]
    else:
        vals, ei, ln = c.value("EI"), c.p.EI, c.p.L
        seg = [segment_stiffness(e, le) if v > 0 else None for v, e, le in zip(vals, ei, ln)]
    return [connection_stiffness(a, b) for a, b in zip(seg, seg[1:])]
