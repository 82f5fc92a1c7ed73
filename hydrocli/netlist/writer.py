"""Edit a machine file's round-trip document and return the new text (comments kept).

Used by identification (write estimates back) and diagnosis (augment the machine). Every
function works on a copy of ``netlist.doc`` and returns YAML text; reload it with
:func:`hydrocli.netlist.loader.load_netlist_text` to continue editing. Values are written
in the unit the file used for them ("1.73 GPa" stays in GPa), with 6 significant digits.
Parameter names are the model's: ``valve.Kv``, ``outer.valve.Kv`` (written as the override
``valve.Kv:`` on the template instance ``outer``), ``fluid.beta``.
"""
from __future__ import annotations

import copy
import difflib

from ruamel.yaml.comments import CommentedMap, CommentedSeq
from ruamel.yaml.scalarstring import DoubleQuotedScalarString, SingleQuotedScalarString

from ..components import registry
from ..suggest import suggest
from ..errors import Location, NetlistError, Problem
from ..units import dimensionality, from_si
from . import yamldoc as Y
from .model import Netlist
from .params import unit_of

FLUID_UNITS = {"beta": "Pa", "rho": "kg/m^3", "nu": "m^2/s", "p_tank": "Pa", "p_vap": "Pa"}
DIGITS = 6


# -- public API ----------------------------------------------------------------------------
def set_parameters(net: Netlist, values: dict[str, float | list[float]]) -> str:
    """Write SI ``values`` ({"valve.Kv": 5.1e-7, …}) back into the file's text."""
    return Y.dump_text(with_parameters(net, values))


def with_parameters(net: Netlist, values: dict[str, float | list[float]]) -> CommentedMap:
    """:func:`set_parameters`' edited document (a copy), not yet written as text: edits that
    chain (the diagnosis's augmentations) reload it with ``loader.load_doc`` and skip a YAML
    dump and parse per edit."""
    doc = copy_doc(net)
    for name, value in values.items():
        _Slot(net, doc, name).set_value(value)
    return doc


def check_write_back(net: Netlist, names) -> None:
    """Raise the located NetlistError that :func:`set_parameters` would raise for ``names``,
    without writing anything: identification calls this BEFORE a long fit."""
    doc = copy_doc(net)
    for name in names:
        _Slot(net, doc, name)


def write_back(net: Netlist, values: dict, out) -> str:
    """Write the machine with ``values`` (SI) to ``out`` and return the new text.

    A parameter of a component defined in an included file is written by copying that
    component into the output file (an including file's entries replace the included ones,
    so the output loads the same machine; the included file itself is never changed).
    Include paths are rewritten relative to ``out``'s folder, and the original file's line
    ends (CRLF or LF) are kept.
    """
    import os
    from pathlib import Path

    from ..fileio import newline_of, write_text_atomic
    doc = copy_doc(net)
    for name, value in values.items():
        _Slot(net, doc, name).set_value(value)
    _rebase_includes(doc, Path(net.file).parent, Path(out).parent)
    text = Y.dump_text(doc)
    write_text_atomic(out, text, newline=newline_of(net.file) if os.path.exists(net.file) else None)
    return text


def identified_netlist(text: str, out) -> tuple[str, str]:
    """(sha256, normalised text) of the machine written to ``out``: a result simulated with the
    identified values records the netlist that reproduces it, not the original one."""
    from .loader import load_netlist_text
    from .normal import netlist_sha256, normalised_text
    net = load_netlist_text(text, str(out))
    return netlist_sha256(net), normalised_text(net)


def _rebase_includes(doc, src_dir, dst_dir) -> None:
    import os
    inc = doc.get("include")
    if inc is None or src_dir.resolve() == dst_dir.resolve():
        return
    items = list(inc) if Y.is_seq(inc) else [inc]
    new = [os.path.relpath((src_dir / str(rel)).resolve(), dst_dir.resolve()) if isinstance(rel, str) else rel
           for rel in items]
    if Y.is_seq(inc):
        for i, v in enumerate(new):
            inc[i] = v
    else:
        doc["include"] = new[0]


def set_free(net: Netlist, name: str, free: bool, bounds: tuple[float, float] | None = None) -> str:
    """Mark a parameter free (or fixed) for identification; ``bounds`` are SI."""
    return Y.dump_text(with_free(net, name, free, bounds))


def with_free(net: Netlist, name: str, free: bool, bounds: tuple[float, float] | None = None,
              log: bool | None = None) -> CommentedMap:
    """:func:`set_free`'s edited document (a copy); ``log``: also say whether the fit moves the
    parameter on a log scale."""
    doc = copy_doc(net)
    _Slot(net, doc, name).set_free(free, bounds, log)
    return doc


def add_component(net: Netlist, name: str, type: str, ports: dict[str, str],
                  params: dict | None = None) -> str:
    """Add a component; ``params`` values are SI numbers, unit strings or {value, free, bounds} maps."""
    return Y.dump_text(with_component(net, name, type, ports, params))


def with_component(net: Netlist, name: str, type: str, ports: dict[str, str],
                   params: dict | None = None) -> CommentedMap:
    """:func:`add_component`'s edited document (a copy)."""
    cls = registry.get(type)
    if cls is None:
        raise NetlistError(_problem(f"unknown component type '{type}'{suggest(type, registry.all_types())}",
                                    net, "'hydro components' lists the types"))
    for port in ports:
        if cls.port(port) is None:
            raise NetlistError(_problem(f"{type} has no port '{port}'", net,
                                        f"ports: {', '.join(p.name for p in cls.ports)}"))
    for pname in params or {}:
        if cls.param(pname) is None:
            raise NetlistError(_problem(f"{type} has no parameter '{pname}'", net,
                                        f"parameters: {', '.join(p.name for p in cls.parameters)}"))
    doc = copy_doc(net)
    comps = _components(doc, net)
    if name in comps or name in net.components:
        raise NetlistError(_problem(f"component '{name}' already exists", net, "choose another name"))
    cmap = CommentedMap()
    cmap["type"] = type
    cmap["ports"] = _flow_map(ports)
    for pname, v in (params or {}).items():
        cmap[pname] = (_flow_map(v) if isinstance(v, dict) else _number(v) if _is_num(v)
                       else DoubleQuotedScalarString(v) if isinstance(v, str) else _flow_seq(v))
    comps[name] = cmap
    return doc


def set_port(net: Netlist, comp: str, port: str, node: str) -> str:
    """Connect ``comp.port`` to ``node`` (the component must be written in the main file)."""
    return Y.dump_text(with_port(net, comp, port, node))


def with_port(net: Netlist, comp: str, port: str, node: str) -> CommentedMap:
    """:func:`set_port`'s edited document (a copy)."""
    doc = copy_doc(net)
    cmap = _top_component(net, doc, comp)
    cls = registry.get(str(cmap.get("type")))
    if cls is not None and cls.port(port) is None:
        raise NetlistError(_problem(f"{cls.type} has no port '{port}'", net,
                                    f"ports: {', '.join(p.name for p in cls.ports)}"))
    if not Y.is_map(cmap.get("ports")):
        cmap["ports"] = _flow_map({})
    cmap["ports"][port] = node
    return doc


def remove_component(net: Netlist, name: str) -> str:
    """Remove a component written in the main file (its nodes stay as written elsewhere)."""
    doc = copy_doc(net)
    _top_component(net, doc, name)
    del doc["components"][name]
    return Y.dump_text(doc)


def diff_text(old: str, new: str, name: str = "machine.yaml") -> str:
    """Unified diff of two versions of a machine file, for printing."""
    return "".join(difflib.unified_diff(old.splitlines(keepends=True), new.splitlines(keepends=True),
                                        f"a/{name}", f"b/{name}"))


# -- helpers -------------------------------------------------------------------------------
def copy_doc(net: Netlist) -> CommentedMap:
    """A deep copy of the machine's round-trip document, to edit (located error when it has none)."""
    if net.doc is None:
        raise NetlistError(_problem("this netlist has no source document to edit", net,
                                    "load it with load_netlist or load_netlist_text"))
    return copy.deepcopy(net.doc)


def _problem(msg: str, net: Netlist, hint: str | None = None) -> Problem:
    return Problem(msg, Location(net.file), hint)


def _components(doc, net: Netlist) -> CommentedMap:
    if doc.get("components") is None:
        doc["components"] = CommentedMap()
    return doc["components"]


def _top_component(net: Netlist, doc, name: str, copy_included: bool = False) -> CommentedMap:
    comps = _components(doc, net)
    if name not in comps and copy_included:
        included = _included_component(net, name)
        if included is not None:
            comps[name] = included
    if name not in comps:
        where = net.components[name].loc.file if name in net.components else None
        hint = (f"it is defined in {where}; edit that file" if where and where != net.file else
                f"components of the main file: {', '.join(map(str, comps))}")
        raise NetlistError(_problem(f"component '{name}' is not written in {net.file}"
                                    f"{suggest(name, list(map(str, comps)))}", net, hint))
    return comps[name]


def _included_component(net: Netlist, name: str):
    """A copy of component (or template instance) ``name`` as written in an included file
    (the nearest one, as the loader merges them), or None."""
    from pathlib import Path
    todo, seen = [(Path(net.file), net.doc)], set()
    while todo:
        file, doc = todo.pop(0)
        inc = doc.get("include") if Y.is_map(doc) else None
        for rel in (list(inc) if Y.is_seq(inc) else [inc] if inc else []):
            path = (file.parent / str(rel)).resolve()
            if path in seen or not path.is_file():
                continue
            seen.add(path)
            try:
                sub, _ = Y.load_file(path)
            except Exception:
                continue
            comps = sub.get("components")
            if Y.is_map(comps) and Y.is_map(comps.get(name)):
                return copy.deepcopy(comps[name])
            todo.append((path, sub))
    return None


def _is_num(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _number(x: float) -> float | int:
    r = float(f"{x:.{DIGITS}g}")
    return int(r) if r.is_integer() and abs(r) < 1e15 and "e" not in f"{x:.{DIGITS}g}" else r


def _flow_map(d: dict) -> CommentedMap:
    m = CommentedMap()
    for k, v in d.items():
        m[k] = _number(v) if _is_num(v) else _flow_seq(v) if isinstance(v, (list, tuple)) else v
    m.fa.set_flow_style()
    return m


def _flow_seq(items) -> CommentedSeq:
    s = CommentedSeq([_number(v) if _is_num(v) else v for v in items])
    s.fa.set_flow_style()
    return s


class _Slot:
    """Where a model parameter lives in the document, and how its value is written there."""

    def __init__(self, net: Netlist, doc, name: str):
        self.net, self.name = net, name
        comp, _, self.pname = name.rpartition(".")
        if comp == "fluid":
            if self.pname not in FLUID_UNITS:
                raise NetlistError(_problem(f"no fluid property '{self.pname}'", net,
                                            f"fluid properties: {', '.join(FLUID_UNITS)}"))
            if doc.get("fluid") is None:
                doc["fluid"] = CommentedMap()
            self.map, self.key, self.si_unit = doc["fluid"], self.pname, FLUID_UNITS[self.pname]
            self.pv = net.fluid.get(self.pname)
            return
        decl = net.components.get(comp)
        spec = registry.get(decl.type).param(self.pname) if decl else None
        if spec is None:
            known = [f"{c}.{p}" for c, d in net.components.items() for p in d.params]
            raise NetlistError(_problem(f"no parameter '{name}'{suggest(name, known)}", net,
                                        "parameter names are COMPONENT.PARAMETER, e.g. valve.Kv"))
        self.si_unit, self.pv = spec.unit, decl.params.get(self.pname)
        comps = _components(doc, net)
        if comp in comps or (decl.template is None and _top_component(net, doc, comp, copy_included=True)):
            self.map, self.key = comps[comp], self.pname
        else:  # a template instance: write the override on the instance
            inst, _, inner = comp.partition(".")
            self.map = _top_component(net, doc, inst, copy_included=True)
            self.key = f"{inner}.{self.pname}"

    # the unit a number is written in, and whether it is a "value unit" string
    def _style(self):
        raw = self.map.get(self.key)
        holder = raw if Y.is_map(raw) else None
        value = holder.get("value") if holder is not None else raw
        if holder is not None and holder.get("unit") is not None:
            return str(holder["unit"]), None
        if isinstance(value, str) and unit_of(value):
            return unit_of(value), type(value)
        if value is None and self.pv is not None and self.pv.unit:  # absent: fluid/default unit
            return self.pv.unit, DoubleQuotedScalarString
        return self.net.unit_defaults.get(dimensionality(self.si_unit)), None

    def _render(self, x):
        unit, string_type = self._style()
        if isinstance(x, (list, tuple)):
            return _flow_seq([from_si(v, unit) if unit else v for v in x])
        v = _number(from_si(x, unit) if unit else x)
        if string_type is not None:
            cls = string_type if string_type in (DoubleQuotedScalarString, SingleQuotedScalarString) else str
            return cls(f"{v:.{DIGITS}g} {unit}")
        return v

    def set_value(self, x) -> None:
        raw = self.map.get(self.key)
        new = self._render(x)
        if Y.is_map(raw):
            raw["value"] = new
        elif raw is None and self.pv is not None and self.pv.free and not self.pv.given:
            self._write_map(new, True, self.pv.bounds)
        else:
            self.map[self.key] = new

    def set_free(self, free: bool, bounds, log: bool | None = None) -> None:
        raw = self.map.get(self.key)
        if Y.is_map(raw):
            raw["free"] = free
            if bounds is not None:
                raw["bounds"] = _flow_seq([self._render(b) for b in bounds])
        else:
            value = raw if raw is not None else self._render(self.pv.value if self.pv else 0.0)
            if not free and bounds is None and log is None:
                self.map[self.key] = value
                return
            self._write_map(value, free, bounds)
        if log is not None:
            self.map[self.key]["log"] = bool(log)

    def _write_map(self, value, free, bounds) -> None:
        m = CommentedMap()
        m["value"] = value
        m["free"] = free
        if bounds is not None:
            m["bounds"] = _flow_seq([self._render(b) for b in bounds])
        m.fa.set_flow_style()
        self.map[self.key] = m
