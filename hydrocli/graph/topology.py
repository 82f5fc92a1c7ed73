"""Linear-graph topology: node checks and node equations.

Each node is a linear-graph vertex. Its across variable is

* imposed by exactly one source component (tank, pressure source, signal driver,
  a mechanism imposing a joint-driven velocity), or
* a state when capacitive elements sit on it (volumes → pressure; masses → velocity and
  position; inertias → angular velocity and angle), with the balance
  ``Σ capacitance · d(across)/dt = −Σ through`` (continuity / Newton).

Anything else cannot be turned into an ODE and is refused here with a message that
names the node, its ports, and what to add (as lcapy does for singular networks).
"""
from __future__ import annotations

from ..components.base import Domain
from ..errors import Location, Problem
from ..model import expr as E
from ..model.context import REFERENCE_NODES, Assembly, NodeInfo, across_name, position_name
from ..suggest import suggest


def check_domains(asm: Assembly, port_domains: dict[tuple[str, str], Domain],
                  comp_locs: dict[str, Location]) -> list[Problem]:
    problems = []
    for node in asm.nodes.values():
        domains = {port_domains[p] for p in node.ports}
        if len(domains) > 1 and not node.is_reference:   # ground is the reference of every domain
            listing = ", ".join(f"{c}.{p} ({port_domains[(c, p)].value})" for c, p in node.ports)
            problems.append(Problem(
                f"node '{node.name}' joins ports of different domains: {listing}",
                comp_locs.get(node.ports[0][0], Location()),
                "a node joins ports of one domain only; use a cylinder/motor to couple hydraulics and mechanics"))
    return problems


def node_equations(asm: Assembly, input_names: set[str], comp_names: set[str],
                   comp_locs: dict[str, Location]) -> tuple[list[Problem], list[str]]:
    """Turn every node into states/derivatives or imposed variables; return problems and
    the list of machine inputs that drive no node."""
    problems: list[Problem] = []
    used_inputs: set[str] = set()
    all_nodes = list(asm.nodes)
    for node in asm.nodes.values():
        loc = comp_locs.get(node.ports[0][0], Location()) if node.ports else Location()
        listing = ", ".join(f"{c}.{p}" for c, p in node.ports)
        if node.name in comp_names:
            problems.append(Problem(f"node '{node.name}' has the same name as a component",
                                    loc, "rename the node (e.g. 'n_" + node.name + "') so names stay unambiguous"))
            continue
        if node.is_reference:  # the reference absorbs everything stamped on it
            continue
        dom = node.domain
        if dom == Domain.SIGNAL and node.name in input_names:
            node.imposed.insert(0, ("<input>", E.input_(node.name), None))
            used_inputs.add(node.name)
        if len(node.imposed) > 1:
            who = ", ".join(c if c != "<input>" else f"machine input '{node.name}'" for c, _, _ in node.imposed)
            problems.append(Problem(f"node '{node.name}' is driven by more than one source ({who})", loc,
                                    "a loop of sources: remove one, or put a resistance between them"))
            continue
        if node.imposed:
            comp, val, pos = node.imposed[0]
            if node.capacitance and dom != Domain.HYDRAULIC:
                problems.append(Problem(
                    f"node '{node.name}' has its {dom.across} imposed by '{comp}' and also carries "
                    f"{dom.capacitance_name} from {', '.join(c for c, _ in node.capacitance)}",
                    loc, f"move the {dom.capacitance_name} into the imposing component"))
                continue
            asm.variables[across_name(node.name, dom)] = val
            asm.variable_units[across_name(node.name, dom)] = dom.across_unit
            if dom.position:
                if pos is not None:
                    asm.variables[position_name(node.name, dom)] = pos
                elif node.name in asm.position_requests:
                    problems.append(Problem(f"the position of node '{node.name}' is needed but its source "
                                            f"'{comp}' imposes only a {dom.across}", loc,
                                            "give the node a mass, or a source that also imposes position"))
            _define_through_except(asm, node)
            continue
        if dom == Domain.SIGNAL:
            hint = (f"connect it to a block output or name it after a machine input"
                    f"{suggest(node.name, input_names)}")
            problems.append(Problem(f"signal node '{node.name}' has no driver (ports: {listing})", loc, hint))
            continue
        if not node.capacitance:
            near = suggest(node.name, [n for n in all_nodes if n != node.name and n not in REFERENCE_NODES])
            what = {"hydraulic": "a 'volume' component (hose or chamber volume)",
                    "translational": "a 'mass'", "rotational": "an 'inertia'"}[dom.value]
            single = " Only one port is connected: a dangling connection?" if len(node.ports) == 1 else ""
            problems.append(Problem(
                f"node '{node.name}' ({dom.value}; ports: {listing}) has no {dom.capacitance_name}: its "
                f"{dom.across} is undefined between the elements joined there.{single}{near}", loc,
                f"add {what} on node '{node.name}', or join it to a node that has one"))
            continue
        _capacitive_node(asm, node)
        _define_through_except(asm, node)
    unused = sorted(input_names - used_inputs)
    return problems, unused


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
    if dom.position:
        pname = position_name(node.name, dom)
        asm.states[pname] = (dom.position_unit, 0.0, dom.nominal_position, f"{dom.position} of node {node.name}")
        asm.variables[pname] = E.state(pname)
        asm.variable_units[pname] = dom.position_unit
        asm.derivatives[pname] = E.state(aname)


def _define_through_except(asm: Assembly, node: NodeInfo) -> None:
    if node.name not in asm.node_through_requests:
        return
    for comp, _, _ in node.imposed:
        asm.variables[f"{node.name}.through_except.{comp}"] = E.sum_exprs(
            q for c, q in node.through if c != comp)
