"""The machine's linear graph: nodes (vertices), branches and the incidence matrix.

A node joins component ports of one domain; its across variable is a pressure [Pa], a
velocity [m/s] (and position), an angular velocity [rad/s] (and angle) or a signal value.
``ground`` is the reference node of every domain (across 0).

Components are multi-terminal, so the graph is a terminal graph: every element a component
stamps on a port is one branch from the port's node to the reference, oriented so that its
through variable is what the component takes from the node (a two-port orifice is two
branches carrying q and −q). The kind of a branch is what the component stamped there:

* ``source``     — imposes the node's across value (tank, pressure source, signal driver,
                   a mechanism imposing a joint-driven velocity);
* ``input``      — a machine input driving the signal node of the same name;
* ``capacitive`` — V/β, a mass or an inertia: ``Σ C · d(across)/dt = −Σ through``;
* ``through``    — a through variable only (resistances, inertances, gyrator ports).

Rows of the reduced incidence matrix are the non-reference nodes, columns the branches:
A[i, b] = +1 when branch b leaves node i, so node i's balance is ``(A q)_i`` (KCL /
Newton). References: Rowell & Wormley, *System Dynamics: An Introduction* (1997), ch. 5;
the harvester seed papers' graph-based formulation.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from enum import Enum

import numpy as np

from ..components.base import Domain

REFERENCE_NODES = ("ground",)


class Kind(str, Enum):
    SOURCE = "source"
    INPUT = "input"
    CAPACITIVE = "capacitive"
    THROUGH = "through"


@dataclass(frozen=True)
class Branch:
    """One element stamped by ``component`` on ``node`` (oriented node → reference)."""

    component: str
    node: str
    kind: Kind = Kind.THROUGH
    has_position: bool = False     # a source that also imposes the node's position / angle


@dataclass(frozen=True)
class Node:
    name: str
    domain: Domain                              # the domain of its first port
    terminals: tuple[tuple[str, str], ...] = ()  # (component, port) in netlist order

    @property
    def is_reference(self) -> bool:
        return self.name in REFERENCE_NODES


@dataclass(frozen=True)
class LinearGraph:
    nodes: dict[str, Node] = field(default_factory=dict)      # in order of first appearance
    branches: tuple[Branch, ...] = ()

    @classmethod
    def from_terminals(cls, terminals) -> "LinearGraph":
        """``terminals``: (component, port, node, domain) in netlist order."""
        nodes: dict[str, Node] = {}
        for comp, port, node, dom in terminals:
            n = nodes.get(node) or Node(node, dom)
            nodes[node] = replace(n, terminals=n.terminals + ((comp, port),))
        return cls(nodes)

    def with_branches(self, branches) -> "LinearGraph":
        return LinearGraph(self.nodes, tuple(branches))

    def at(self, node: str, kind: Kind | None = None) -> list[Branch]:
        """Branches on ``node`` (of one kind), in stamping order."""
        return [b for b in self.branches if b.node == node and (kind is None or b.kind == kind)]

    @property
    def free_nodes(self) -> list[str]:
        """Non-reference nodes: the rows of the reduced incidence matrix."""
        return [n for n, v in self.nodes.items() if not v.is_reference]

    def incidence(self) -> np.ndarray:
        """Reduced incidence matrix (free nodes × branches)."""
        row = {n: i for i, n in enumerate(self.free_nodes)}
        A = np.zeros((len(row), len(self.branches)), dtype=int)
        for j, b in enumerate(self.branches):
            if b.node in row:
                A[row[b.node], j] = 1
        return A
