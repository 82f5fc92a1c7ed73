"""Netlist edits used by the diagnosis: free a parameter from a start value, add
components, re-route ports and rewrite output expressions — always on the machine's
round-trip YAML document (comments kept), through :mod:`hydrocli.netlist.writer`.

Edits chain on the document itself: each edits a copy and re-checks it with
``loader.load_doc``, without writing it as YAML text and parsing it back (that round trip
cost ~0.1 s per edit, 5–9 s per diagnosis round of twenty candidates); :func:`text_of`
writes the text once, at the end.

Every function takes a :class:`~hydrocli.netlist.model.Netlist` and returns a new one, so
edits chain: ``net = free(net, "valve.overlap_PA", 0.0, (-0.02, 0.1))``.
"""
from __future__ import annotations

import re

from ..components import registry
from ..netlist import writer
from ..netlist import yamldoc as Y
from ..netlist.loader import load_doc, load_netlist_text
from ..netlist.model import Netlist


def reload(net: Netlist, text: str) -> Netlist:
    return load_netlist_text(text, net.file)


def reload_doc(net: Netlist, doc) -> Netlist:
    """The machine of an edited copy of ``net``'s document, checked like a loaded file."""
    return load_doc(doc, net.file)


def param_slot(net: Netlist, name: str) -> str:
    """The writer's name for a model parameter: a component parameter that only inherits
    the machine's fluid property (``cylinder.beta`` from ``fluid.beta``) is written there."""
    comp, _, pname = name.rpartition(".")
    decl = net.components.get(comp)
    if decl is not None and pname in decl.params:
        spec = registry.get(decl.type).param(pname)
        if spec is not None and spec.fluid and not decl.params[pname].given and spec.fluid in net.fluid:
            return f"fluid.{spec.fluid}"
    return name


def set_values(net: Netlist, values: dict[str, float]) -> Netlist:
    """Write SI values (model parameter names) into the machine."""
    slots: dict[str, float] = {}
    for k, v in values.items():
        slots[param_slot(net, k)] = float(v)
    return reload_doc(net, writer.with_parameters(net, slots)) if slots else net


def free(net: Netlist, name: str, start: float, bounds: tuple[float, float], log: bool | None = None) -> Netlist:
    """Set ``name`` to ``start`` and mark it free within ``bounds`` (SI)."""
    net = set_values(net, {name: start})
    return reload_doc(net, writer.with_free(net, param_slot(net, name), True, bounds, log))


def free_new(net: Netlist, params) -> Netlist:
    """Each of a candidate's new parameters (``NewParam``) free from its start value within
    its bounds, on a log scale where it says so."""
    for prm in params:
        net = free(net, prm.name, prm.start, prm.bounds, prm.log)
    return net


def set_initial(net: Netlist, values: dict) -> Netlist:
    """The machine with these ``initial:`` entries set (SI numbers or values with units)."""
    if not values:
        return net
    doc = writer.copy_doc(net)
    if doc.get("initial") is None:
        doc["initial"] = {}
    for k, v in values.items():
        doc["initial"][k] = float(v) if isinstance(v, (int, float)) else v
    return reload_doc(net, doc)


def fix(net: Netlist, name: str) -> Netlist:
    return reload_doc(net, writer.with_free(net, param_slot(net, name), False))


def add(net: Netlist, name: str, type_: str, ports: dict[str, str], params: dict | None = None) -> Netlist:
    return reload_doc(net, writer.with_component(net, name, type_, ports, params or {}))


def set_type(net: Netlist, comp: str, type_: str) -> Netlist:
    """Replace a component's type by a compatible one (same ports and parameters, more of them)."""
    doc = writer.copy_doc(net)
    doc["components"][comp]["type"] = type_
    return reload_doc(net, doc)


def connect(net: Netlist, comp: str, port: str, node: str) -> Netlist:
    return reload_doc(net, writer.with_port(net, comp, port, node))


def unique_name(net: Netlist, base: str) -> str:
    """A component/node name not used in the machine yet."""
    used = set(net.components) | set(net.nodes()) | set(net.inputs)
    name, i = base, 2
    while name in used:
        name, i = f"{base}_{i}", i + 1
    return name


def rewrite_outputs(net: Netlist, mapping: dict[str, str], only: set[str] | None = None) -> Netlist:
    """Replace dotted symbols in output expressions (``chamber_1.p`` → ``s1.p``), whole
    names only; ``only`` limits the rewrite to some outputs."""
    doc = writer.copy_doc(net)
    outs = doc.get("outputs") or {}
    for key in list(outs):
        if only is not None and str(key) not in only:
            continue
        val = outs[key]
        text = val if isinstance(val, str) else val.get("expr")
        new = substitute_symbols(str(text), mapping)
        if isinstance(val, str):
            outs[key] = new
        else:
            val["expr"] = new
    return reload_doc(net, doc)


def substitute_symbols(text: str, mapping: dict[str, str]) -> str:
    for old, new in mapping.items():
        text = re.sub(rf"(?<![\w.]){re.escape(old)}(?![\w])", new, text)
    return text


def output_symbols(net: Netlist, output: str) -> set[str]:
    """Dotted names an output expression reads (``chamber_1.p``, ``piston.x`` …)."""
    return set(re.findall(r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+", net.outputs[output].expr))


def move_node(net: Netlist, node: str, new_node: str, keep: set[str]) -> Netlist:
    """Re-connect every port on ``node`` to ``new_node`` except those of components in ``keep``."""
    for comp, port in net.nodes().get(node, []):
        if comp not in keep:
            net = connect(net, comp, port, new_node)
    return net


def text_of(net: Netlist) -> str:
    return Y.dump_text(net.doc)


def output_symbols_expr(model, output: str) -> set[str]:
    """Nodes whose position or angle an output reads (``piston.x`` → ``piston``,
    ``arm.theta`` → ``arm``), from the model."""
    e = model.equations.output_exprs[output]
    out = set()

    def position(name):
        return name.endswith(".x") or name.endswith(".theta")
    for kind, name in e.symbols():
        if position(name):
            out.add(name.rsplit(".", 1)[0])
    # follow one variable alias (outputs often read a component variable)
    for kind, name in list(e.symbols()):
        if kind == "var" and name in model.equations.variables:
            for k2, n2 in model.equations.variables[name].symbols():
                if position(n2):
                    out.add(n2.rsplit(".", 1)[0])
    return out
