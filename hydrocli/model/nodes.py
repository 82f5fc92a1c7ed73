"""Node equations from the normal tree (graph.topology): what the builder writes per node.

* imposed node: ``node.p`` (``.v``/``.w``, signal value) is the source's expression; its
  position/angle too when the source imposes one (else reading it is an error);
* state node: across (and position) are states, ``ΣC · d(across)/dt = −Σ through``
  (continuity on a hydraulic node, Newton on a mass, Euler on an inertia), d(position)/dt =
  across;
* ``node.through_except.COMP``: what the other components take from a node, for sources
  that need it (``Context.node_through``).
"""
from __future__ import annotations

from ..errors import Location, Problem
from ..graph.linear import Branch, Kind, LinearGraph
from ..graph.topology import NormalTree
from . import expr as E
from .context import Assembly, NodeInfo, across_name, position_name, rate_name


def node_equations(asm: Assembly, g: LinearGraph, tree: NormalTree,
                   comp_locs: dict[str, Location]) -> list[Problem]:
    """Write every node's variables/states into ``asm``; the problems in node order."""
    problems: list[Problem] = []
    for name, gnode in g.nodes.items():
        if name in tree.problems:
            problems.append(tree.problems[name])
            continue
        role = tree.roles.get(name)
        if role is None:          # the reference
            continue
        node = asm.nodes[name]
        if role.role == "imposed":
            loc = comp_locs.get(gnode.terminals[0][0], Location()) if gnode.terminals else Location()
            p = _imposed(asm, node, role.tree, loc)
            if p:
                problems.append(p)
        else:
            _capacitive_node(asm, node)
        _define_through_except(asm, node, [b.component for b in g.at(name, Kind.INPUT) + g.at(name, Kind.SOURCE)])
    return problems


def _imposed(asm: Assembly, node: NodeInfo, src, loc: Location) -> Problem | None:
    dom = node.domain
    if src.kind == Kind.INPUT:
        val, pos = E.input_(node.name), None
    else:
        _, val, pos = next(i for i in node.imposed if i[0] == src.component)
    asm.variables[across_name(node.name, dom)] = val
    asm.variable_units[across_name(node.name, dom)] = dom.across_unit
    if dom.position:
        if pos is not None:
            asm.variables[position_name(node.name, dom)] = pos
        elif node.name in asm.position_requests:
            return Problem(f"the position of node '{node.name}' is needed but its source "
                           f"'{src.component}' imposes only a {dom.across}", loc,
                           "give the node a mass, or a source that also imposes position")
    if node.name in asm.rate_requests:
        return Problem(f"the rate of change of {dom.across} at node '{node.name}' is needed but its source "
                       f"'{src.component}' imposes the {dom.across}", loc,
                       "give the node a mass or inertia of its own (a load between the source and the element)")
    return None


def _capacitive_node(asm: Assembly, node: NodeInfo) -> None:
    dom = node.domain
    aname = across_name(node.name, dom)
    total_cap = E.sum_exprs(c for _, c in node.capacitance)
    total_through = E.sum_exprs(q for _, q in node.through)
    asm.states[aname] = (dom.across_unit, 0.0, dom.nominal_across, f"{dom.across} of node {node.name}")
    asm.variables[aname] = E.state(aname)
    asm.variable_units[aname] = dom.across_unit
    cap_name = f"{node.name}.{dom.capacitance_name}"
    asm.variables[cap_name] = total_cap
    asm.derivatives[aname] = -total_through / E.var(cap_name)
    if node.name in asm.rate_requests:   # named once: the node's derivative and its readers share it
        rname = rate_name(node.name, dom)
        asm.variables[rname], asm.variable_units[rname] = asm.derivatives[aname], f"({dom.across_unit})/s"
        asm.derivatives[aname] = E.var(rname)
    if dom.position:
        pname = position_name(node.name, dom)
        asm.states[pname] = (dom.position_unit, 0.0, dom.nominal_position, f"{dom.position} of node {node.name}")
        asm.variables[pname] = E.state(pname)
        asm.variable_units[pname] = dom.position_unit
        asm.derivatives[pname] = E.state(aname)


def _define_through_except(asm: Assembly, node: NodeInfo, sources: list[str]) -> None:
    if node.name not in asm.node_through_requests:
        return
    for comp in sources:
        asm.variables[f"{node.name}.through_except.{comp}"] = E.sum_exprs(
            q for c, q in node.through if c != comp)


def stamped_branches(asm: Assembly):
    """The branches the components stamped (graph.linear.Branch), node by node."""
    for node in asm.nodes.values():
        yield from (Branch(c, node.name, Kind.SOURCE, pos is not None) for c, _, pos in node.imposed)
        yield from (Branch(c, node.name, Kind.CAPACITIVE) for c, _ in node.capacitance)
        yield from (Branch(c, node.name, Kind.THROUGH) for c, _ in node.through)
