"""Builder: Netlist → Model (states, parameter vector, generated equations).

1. every component stamps its equations through a :class:`Context`;
2. the stamped elements become the branches of the linear graph (graph.linear); its
   normal tree (graph.topology) says which node across variables are imposed and which
   are states, and the node equations are written from it (model.nodes);
3. outputs are parsed; variables are ordered (an algebraic loop is refused);
4. the flat equations become C and NumPy source (codegen). Parameters stay symbols, so
   identification changes the parameter array without rebuilding.
"""
from __future__ import annotations

import hashlib

import numpy as np

from ..components import registry
from ..components.base import check_state_value
from ..suggest import suggest
from ..errors import HydroError, NetlistError, ProblemCollector, TopologyError, UnitError
from ..graph.linear import LinearGraph
from ..graph.topology import check_domains, input_branches, normal_tree
from ..netlist.model import Netlist
from ..netlist.normal import normalised_text
from ..units import dimensionality, to_si
from . import expr as E
from .equations import Equations, order_variables
from .context import Assembly, Context, NodeInfo
from .nodes import node_equations, stamped_branches
from .model import InitialRule, Model, ParamInfo, StateInfo
from .parse import ExprSyntaxError, parse_expression


def build_model(net: Netlist) -> Model:
    errs = ProblemCollector()
    comp_locs = {c.name: c.loc for c in net.components.values()}
    asm, graph = stamp(net)
    tree = normal_tree(graph, set(net.inputs), set(net.components), comp_locs)
    errs.problems.extend(node_equations(asm, graph, tree, comp_locs))
    errs.raise_if_any(TopologyError)
    for name in tree.unused_inputs:
        asm.warnings.append(f"machine input '{name}' drives no signal port")

    states = list(asm.states)
    params = sorted(asm.params)
    inputs = list(net.inputs)
    resolve = _Resolver(asm, params, inputs)
    output_exprs = {}
    for o in net.outputs.values():
        try:
            output_exprs[o.name] = parse_expression(o.expr, resolve)
        except (ExprSyntaxError, TypeError, ValueError, ArithmeticError, RecursionError) as exc:
            why = str(exc) if isinstance(exc, ExprSyntaxError) else _expr_failure(exc)
            errs.add(f"output '{o.name}': {why}", o.loc, "outputs use node quantities such as "
                     "'chamber_a.p', 'load.x', 'load.v' or component variables")
    errs.raise_if_any(TopologyError)
    missing = [s for s in states if s not in asm.derivatives]
    if missing:
        raise TopologyError(f"states without a derivative: {', '.join(missing)}")
    eqs = Equations(states=states, params=params, inputs=inputs, outputs=list(output_exprs),
                    variables=asm.variables, derivatives=asm.derivatives, output_exprs=output_exprs,
                    guards=asm.guards, rest=asm.rest)
    order_variables(eqs, [eqs.derivatives[s] for s in states] + list(output_exprs.values())
                    + [g for g, _ in asm.guards])  # refuses algebraic loops early

    state_infos = [StateInfo(s, *asm.states[s]) for s in states]
    x0 = np.array([si.initial for si in state_infos], dtype=float)
    p_tank = net.fluid["p_tank"].value if "p_tank" in net.fluid else 1e5
    for i, si in enumerate(state_infos):
        if si.unit == "Pa":
            x0[i] = p_tank
    rules = _apply_initial(net, state_infos, x0, errs, output_exprs)
    errs.raise_if_any(NetlistError)
    param_infos = [_param_info(net, name, *asm.params[name]) for name in params]
    out_units = {o.name: o.unit for o in net.outputs.values()}
    normal = normalised_text(net)
    model = Model(name=net.name, netlist_sha=hashlib.sha256(normal.encode()).hexdigest(),
                  equations=eqs, states=state_infos, x0=x0, params=param_infos,
                  input_units={k: v.unit for k, v in net.inputs.items()},
                  input_hold={k: v.hold for k, v in net.inputs.items()},
                  output_units=out_units, variable_units=dict(asm.variable_units),
                  warnings=list(asm.warnings), netlist_text=normal, file=net.file, initial_rules=rules)
    from .output_units import check_output_units
    ProblemCollector.raise_if_any(_collected(check_output_units(model, net.outputs)), UnitError)
    return model


def _collected(problems):
    c = ProblemCollector()
    c.problems.extend(problems)
    return c


def stamp(net: Netlist) -> tuple[Assembly, LinearGraph]:
    """Check the ports' domains, let every component stamp its equations, and return what
    they stamped with the machine's linear graph (its branches are the stamped elements)."""
    errs = ProblemCollector()
    comp_locs = {c.name: c.loc for c in net.components.values()}
    asm = Assembly()
    graph = graph_of(net)
    port_domains = {(c, p): dom for c, p, _, dom in terminals(net)}
    for p in check_domains(graph, port_domains, comp_locs):
        errs.problems.append(p)
    errs.raise_if_any(TopologyError)
    for node in graph.nodes.values():
        asm.nodes[node.name] = NodeInfo(node.name, node.domain, list(node.terminals))

    for decl in net.components.values():
        cls = registry.get(decl.type)
        structural = {p.name: decl.params[p.name].value for p in cls.parameters if p.structural}
        values = {k: v.value for k, v in decl.params.items()}
        free = {k for k, v in decl.params.items() if v.free}
        ctx = Context(asm, decl.name, cls, decl.ports, values, structural, free)
        try:
            cls().equations(ctx)
        except HydroError as exc:
            errs.extend(exc)
        except (KeyError, ValueError) as exc:
            errs.add(f"component '{decl.name}' ({decl.type}): {exc}", decl.loc)
    errs.raise_if_any(TopologyError)
    return asm, graph.with_branches([*input_branches(graph, set(net.inputs)), *stamped_branches(asm)])


def terminals(net: Netlist):
    """(component, port, node, domain) of every connected port, in netlist order."""
    for decl in net.components.values():
        cls = registry.get(decl.type)
        for port, node in decl.ports.items():
            yield decl.name, port, node, cls.port(port).domain


def graph_of(net: Netlist) -> LinearGraph:
    """The machine's linear graph before stamping: nodes and their terminals."""
    return LinearGraph.from_terminals(terminals(net))


def _apply_initial(net: Netlist, infos, x0, errs: ProblemCollector, outputs) -> list[InitialRule]:
    idx = {si.name: i for i, si in enumerate(infos)}
    rules = []
    for name, pv in net.initial.items():
        if name not in idx:
            errs.add(f"initial value for unknown state '{name}'{suggest(name, idx)}", pv.loc,
                     "'hydro check MACHINE' lists the states")
            continue
        if isinstance(pv.value, dict):
            (kind, ref), = pv.value.items()
            known = outputs if kind == "output" else idx
            if ref not in known or (kind != "output" and ref == name):
                what = "output" if kind == "output" else "state"
                errs.add(f"initial rule {{{kind}: {ref}}} of '{name}' names an unknown {what} '{ref}'"
                         f"{suggest(ref, known)}", pv.loc, f"'hydro check MACHINE' lists the {what}s")
            else:
                rules.append(InitialRule(name, kind, ref))
            continue
        try:
            unit = infos[idx[name]].unit
            default = net.unit_defaults.get(dimensionality(unit)) if unit not in ("", "1") else None
            x0[idx[name]] = to_si(pv.value, unit, default_unit=default, location=pv.loc, what=f"initial {name}")
            problem = check_state_value(name, unit, x0[idx[name]])
            if problem:
                errs.add(problem, pv.loc, "give a physically valid initial value")
        except HydroError as exc:
            errs.extend(exc)
    return rules


def _param_info(net: Netlist, name: str, value: float, unit: str) -> ParamInfo:
    base = name.split("[")[0]
    comp, _, pname = base.rpartition(".")
    decl = net.components[comp]
    spec = registry.get(decl.type).param(pname)
    pv = decl.params[pname]
    bounds = pv.bounds or spec.bounds
    return ParamInfo(name=name, value=value, unit=unit, bounds=bounds, free=pv.free, log=pv.log,
                     description=spec.description, display_unit=pv.unit,
                     min=spec.min, max=spec.max, positive=spec.positive)


class _Resolver:
    """Resolves dotted names in output expressions."""

    def __init__(self, asm: Assembly, params: list[str], inputs: list[str]):
        self.asm, self.params, self.inputs = asm, set(params), set(inputs)

    def __call__(self, name: str):
        if name in self.asm.variables:
            return E.var(name)
        if name in self.asm.states:
            return E.state(name)
        if name in self.params:
            return E.param(name)
        if name in self.inputs:
            return E.input_(name)
        return None

    def known(self):
        return list(self.asm.variables) + list(self.asm.states) + list(self.params) + list(self.inputs)


def _expr_failure(exc: Exception) -> str:
    """A readable reason for an output expression that parses but cannot be evaluated."""
    if isinstance(exc, RecursionError):
        return "the expression is nested too deeply"
    if isinstance(exc, ZeroDivisionError):
        return "division by zero"
    if isinstance(exc, (OverflowError, ValueError)):
        return f"a constant part cannot be evaluated ({exc})"
    return f"wrong number or kind of arguments ({exc})"
