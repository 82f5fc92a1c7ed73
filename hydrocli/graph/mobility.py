"""Degrees of freedom of a machine's mechanism, from its netlist structure (seed 000 eq. 1).

    n_DOF = 6·n_bodies − 6·n_fixtures − 5·n_PJ − 5·n_RJ − 4·n_UJ − 3·n_SJ   (Nikravesh 1988)

counted for the rigid-body mechanism as seed 000 §3.1 does: each ``serial_chain`` body is a
body; a fixed joint (axis 0) and a flexible-member connection (rigid in this count) are
fixtures; other joints are revolute; each chain actuator port joined to a ``cylinder`` adds a
barrel and a piston (2 bodies) on a spherical joint, a universal joint and a prismatic joint.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..netlist.model import Netlist


@dataclass
class MobilityCount:
    bodies: int = 0
    fixtures: int = 0
    prismatic: int = 0
    revolute: int = 0
    universal: int = 0
    spherical: int = 0

    @property
    def dof(self) -> int:
        """Seed 000 eq. 1."""
        return (6 * self.bodies - 6 * self.fixtures - 5 * self.prismatic - 5 * self.revolute
                - 4 * self.universal - 3 * self.spherical)


def mechanism_mobility(net: Netlist) -> MobilityCount:
    nodes = net.nodes()
    flex_nodes = {node for c in net.components.values() if c.type == "flexible_member"
                  for node in c.ports.values()}
    count = MobilityCount()
    for chain in (c for c in net.components.values() if c.type == "serial_chain"):
        n = len(chain.params["m"].value)
        axis = [int(a) for a in chain.params["axis"].value] or [-2] * n
        count.bodies += n
        for i, a in enumerate(axis, start=1):
            if a == 0 or chain.ports.get(f"j{i}") in flex_nodes:
                count.fixtures += 1
            else:
                count.revolute += 1
        for port, node in chain.ports.items():
            if port.startswith("a") and any(net.components[c].type == "cylinder" for c, _ in nodes[node]
                                            if c != chain.name):
                count.bodies += 2
                count.spherical += 1
                count.universal += 1
                count.prismatic += 1
    return count
