"""Topology checks and the normal tree of the linear graph (graph.linear).

A normal tree holds every across source and as many capacitive branches as possible; the
across variables of its capacitive branches are the states. In the terminal graph every
branch joins a node to the reference, so the tree has one branch per free node and a node's
role is decided by what sits on it:

* one source (or the machine input of a signal node's name) → the node's across is imposed;
* capacitive branches and no source → the node's across (and position) is a state;
* anything else has no normal tree and is refused with a message that names the node, its
  ports and what to add (as lcapy does for singular networks): two sources (a source loop),
  a signal without a driver, a node without volume/mass/inertia (its across is undefined
  between the elements joined there), a mass or inertia on an imposed node (a dependent
  capacitor; a hydraulic volume on a tank node is simply absorbed).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..components.base import Domain
from ..errors import Location, Problem
from ..suggest import suggest
from .linear import REFERENCE_NODES, Branch, Kind, LinearGraph


@dataclass(frozen=True)
class NodeRole:
    """How a free node's across variable is defined."""

    node: str
    role: str                      # "imposed" | "state"
    tree: Branch                   # the node's normal-tree branch (its source, or a capacitor)


@dataclass
class NormalTree:
    roles: dict[str, NodeRole] = field(default_factory=dict)     # node → role (nodes without problems)
    problems: dict[str, Problem] = field(default_factory=dict)   # node → why it has no tree branch
    unused_inputs: list[str] = field(default_factory=list)       # machine inputs that drive no node

    @property
    def tree(self) -> list[Branch]:
        return [r.tree for r in self.roles.values()]


def check_domains(g: LinearGraph, port_domains: dict[tuple[str, str], Domain],
                  comp_locs: dict[str, Location]) -> list[Problem]:
    problems = []
    for node in g.nodes.values():
        domains = {port_domains[p] for p in node.terminals}
        if len(domains) > 1 and not node.is_reference:   # ground is the reference of every domain
            listing = ", ".join(f"{c}.{p} ({port_domains[(c, p)].value})" for c, p in node.terminals)
            problems.append(Problem(
                f"node '{node.name}' joins ports of different domains: {listing}",
                comp_locs.get(node.terminals[0][0], Location()),
                "a node joins ports of one domain only; use a cylinder/motor to couple hydraulics and mechanics"))
    return problems


def input_branches(g: LinearGraph, input_names: set[str]) -> list[Branch]:
    """A machine input drives the signal node of the same name (a source branch)."""
    return [Branch("<input>", n.name, Kind.INPUT) for n in g.nodes.values()
            if n.domain == Domain.SIGNAL and n.name in input_names and not n.is_reference]


def normal_tree(g: LinearGraph, input_names: set[str], comp_names: set[str],
                comp_locs: dict[str, Location]) -> NormalTree:
    """Every node's role, or the located problem that prevents one (nodes in graph order)."""
    out = NormalTree()
    used: set[str] = set()
    for node in g.nodes.values():
        loc = comp_locs.get(node.terminals[0][0], Location()) if node.terminals else Location()
        listing = ", ".join(f"{c}.{p}" for c, p in node.terminals)
        if node.name in comp_names:
            out.problems[node.name] = Problem(f"node '{node.name}' has the same name as a component", loc,
                                              "rename the node (e.g. 'n_" + node.name + "') so names stay unambiguous")
            continue
        if node.is_reference:  # the reference absorbs everything stamped on it
            continue
        dom = node.domain
        sources = g.at(node.name, Kind.INPUT) + g.at(node.name, Kind.SOURCE)
        caps = g.at(node.name, Kind.CAPACITIVE)
        used.update(node.name for b in sources if b.kind == Kind.INPUT)
        if len(sources) > 1:
            who = ", ".join(b.component if b.kind != Kind.INPUT else f"machine input '{node.name}'" for b in sources)
            out.problems[node.name] = Problem(f"node '{node.name}' is driven by more than one source ({who})", loc,
                                              "a loop of sources: remove one, or put a resistance between them")
            continue
        if sources:
            if caps and dom != Domain.HYDRAULIC:
                out.problems[node.name] = Problem(
                    f"node '{node.name}' has its {dom.across} imposed by '{sources[0].component}' and also carries "
                    f"{dom.capacitance_name} from {', '.join(b.component for b in caps)}",
                    loc, f"move the {dom.capacitance_name} into the imposing component")
                continue
            out.roles[node.name] = NodeRole(node.name, "imposed", sources[0])
            continue
        if dom == Domain.SIGNAL:
            hint = (f"connect it to a block output or name it after a machine input"
                    f"{suggest(node.name, input_names)}")
            out.problems[node.name] = Problem(f"signal node '{node.name}' has no driver (ports: {listing})", loc, hint)
            continue
        if not caps:
            near = suggest(node.name, [n for n in g.nodes if n != node.name and n not in REFERENCE_NODES])
            what = {"hydraulic": "a 'volume' component (hose or chamber volume)",
                    "translational": "a 'mass'", "rotational": "an 'inertia'"}[dom.value]
            single = " Only one port is connected: a dangling connection?" if len(node.terminals) == 1 else ""
            out.problems[node.name] = Problem(
                f"node '{node.name}' ({dom.value}; ports: {listing}) has no {dom.capacitance_name}: its "
                f"{dom.across} is undefined between the elements joined there.{single}{near}", loc,
                f"add {what} on node '{node.name}', or join it to a node that has one")
            continue
        out.roles[node.name] = NodeRole(node.name, "state", caps[0])
    out.unused_inputs = sorted(input_names - used)
    return out
