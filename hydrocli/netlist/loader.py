"""Load a machine file: YAML → :class:`Netlist` with SI values, checked against the specs.

All problems of a file are collected and raised together, each with file, line, column,
what is wrong and how to fix it. Unknown keys are rejected with "did you mean".
"""
from __future__ import annotations

from pathlib import Path

from ..components import registry
from ..suggest import suggest
from ..errors import HydroError, Location, NetlistError
from ..units import dimensionality
from . import yamldoc as Y
from .model import ComponentDecl, Netlist, ParamValue
from .params import Errors, param_value
from .sections import entries
from .sections import load_initial as _load_initial
from .sections import load_inputs as _load_inputs
from .sections import load_outputs as _load_outputs
from .templates import CompSource, expand_templates

TOP_KEYS = ("name", "description", "units", "fluid", "include", "templates", "inputs", "outputs",
            "components", "initial", "notes")
MAP_SECTIONS = ("units", "fluid", "templates", "inputs", "outputs", "components", "initial")
COMPONENT_KEYS = ("type", "ports", "description")
FLUID_PROPS = {"beta": "Pa", "rho": "kg/m^3", "nu": "m^2/s", "p_tank": "Pa", "p_vap": "Pa"}
MAX_INCLUDES = 200       # included files read for one machine (a diamond of includes grows fast)
#: file-level default-unit categories and the SI unit whose dimension each must have
UNIT_CATEGORIES = {"pressure": "Pa", "length": "m", "area": "m^2", "volume": "m^3", "flow": "m^3/s", "mass": "kg",
                   "force": "N", "time": "s", "velocity": "m/s", "angle": "rad", "torque": "N*m",
                   "inertia": "kg*m^2", "stiffness": "N/m", "damping": "N*s/m", "flow_gain": "m^3/s/Pa^0.5",
                   "leakage": "m^3/s/Pa"}
UNIT_KEYS = tuple(UNIT_CATEGORIES)


def load_netlist(path: str | Path) -> Netlist:
    doc, text = Y.load_file(path)
    return load_doc(doc, str(path), text)


def load_netlist_text(text: str, file: str = "<machine>") -> Netlist:
    return load_doc(Y.load_text(text, file), file, text)


def load_doc(doc, file: str, text: str = "") -> Netlist:
    """Check and convert a parsed machine document; all problems are raised together."""
    errs = Errors()
    sections = _merge_includes(doc, file, errs, seen=(str(Path(file).resolve()),), budget=[MAX_INCLUDES])
    defaults = _unit_defaults(sections.get("units"), errs)
    fluid = _load_fluid(sections.get("fluid"), defaults, errs)
    components = {}
    for name, src in expand_templates(sections.get("components"), sections.get("templates"), errs).items():
        decl = _load_component(name, src, defaults, fluid, errs)
        if decl is not None:
            components[name] = decl
    inputs = _load_inputs(sections.get("inputs"), errs)
    outputs = _load_outputs(sections.get("outputs"), errs)
    initial = _load_initial(sections.get("initial"), defaults, errs)
    if not components and not errs:
        errs.add("the machine has no components", Location(file, 1, 1, "components"),
                 "add a 'components:' mapping ('hydro components' lists the types)")
    name = doc.get("name")
    if name is not None and not isinstance(name, str):
        errs.add("'name' must be a string", Y.value_loc(doc, "name", file, "name"), "e.g. name: eha_testbench")
    errs.raise_all(NetlistError)
    return Netlist(name=str(name or Path(file).stem), file=file, components=components, inputs=inputs,
                   outputs=outputs, initial=initial, fluid=fluid, description=str(doc.get("description") or ""),
                   text=text, doc=doc, unit_defaults=defaults)


def merged_sections(doc, file: str) -> dict:
    """The sections of a (valid) machine document merged over those of its includes, as the
    loader reads them: mapping sections as {key: (value, parent map, file)}."""
    return _merge_includes(doc, file, Errors(), seen=(str(Path(file).resolve()),), budget=[MAX_INCLUDES])


# -- sections ----------------------------------------------------------------------------
def _merge_includes(doc, file: str, errs: Errors, seen: tuple[str, ...], budget: list[int]) -> dict:
    """Sections of this file merged over those of its includes.

    Mapping sections become {key: (value, parent map, file)} so every entry keeps its own
    file for locations; an including file's entries replace included ones of the same name.
    """
    _check_keys(doc, TOP_KEYS, file, errs, what="top-level key")
    merged: dict = {}
    inc = doc.get("include")
    items = [] if inc is None else list(inc) if Y.is_seq(inc) else [inc]
    for i, rel in enumerate(items):
        loc = Y.item_loc(inc, i, file, "include") if Y.is_seq(inc) else Y.value_loc(doc, "include", file, "include")
        if not isinstance(rel, str):
            errs.add("include: expected a file path", loc, "e.g. include: [common.yaml]")
            continue
        path = Path(file).parent / rel
        key = str(path.resolve())
        if key in seen:
            chain = " -> ".join(Path(s).name for s in seen + (key,))
            errs.add(f"include cycle: {chain}", loc, f"remove the include of '{rel}'")
            continue
        if not path.is_file():
            errs.add(f"included file '{rel}' not found (looked for {path})", loc,
                     "include paths are relative to the including file")
            continue
        budget[0] -= 1
        if budget[0] < -1:
            return merged
        if budget[0] < 0:
            errs.add(f"more than {MAX_INCLUDES} included files are read for this machine (includes that "
                     "include each other many times?)", loc, "include each shared file once, from the top file")
            return merged
        try:
            sub, _ = Y.load_file(path)
        except HydroError as exc:
            errs.extend(exc)
            continue
        _merge_into(merged, _merge_includes(sub, str(path), errs, seen + (key,), budget))
    own = {}
    for k, v in doc.items():
        if k in ("include", "name", "description", "notes") or k not in TOP_KEYS:
            continue
        if k in MAP_SECTIONS and v is not None and not Y.is_map(v):
            errs.add(f"'{k}' must be a mapping (name: value lines), not a {Y.kind(v)}",
                     Y.value_loc(doc, k, file, k), f"write '{k}:' followed by indented 'name: ...' entries")
            continue
        own[k] = {kk: (vv, v, file) for kk, vv in v.items()} if Y.is_map(v) else v
    _merge_into(merged, own)
    return merged


def _merge_into(dst: dict, src: dict) -> None:
    for k, v in src.items():
        if isinstance(v, dict) and isinstance(dst.get(k), dict):
            dst[k].update(v)
        else:
            dst[k] = v


def _unit_defaults(section, errs: Errors) -> dict[str, str]:
    """Map dimensionality → default unit from the file-level ``units:`` mapping."""
    out: dict[str, str] = {}
    for key, unit, parent, f in entries(section):
        if key not in UNIT_KEYS:
            errs.add(f"unknown unit category '{key}'{suggest(str(key), UNIT_KEYS)}",
                     Y.key_loc(parent, key, f, f"units.{key}"), f"categories: {', '.join(UNIT_KEYS)}")
            continue
        loc = Y.value_loc(parent, key, f, f"units.{key}")
        want = UNIT_CATEGORIES[key]
        if not isinstance(unit, str) or not unit.strip():
            errs.add(f"units.{key}: expected a unit name such as '{want}', got {unit!r}", loc,
                     f"e.g. units: {{{key}: {want}}}")
            continue
        try:
            dim = dimensionality(unit)
            if dim != dimensionality(want):
                errs.add(f"units.{key}: '{unit}' is not a {key} unit (it has dimension {dim}, "
                         f"a {key} has {dimensionality(want)})", loc, f"give a unit convertible to {want}")
                continue
            out[dim] = unit
        except HydroError as exc:
            errs.extend(type(exc)([p.at(Y.value_loc(parent, key, f, f"units.{key}")) for p in exc.problems]))
    return out


class _MapWhere:
    """Locations inside one plain mapping (the CompSource interface for non-components)."""

    def __init__(self, m, file):
        self.m, self.file = m, file

    def key_loc(self, key, ypath=None):
        return Y.key_loc(self.m, key, self.file, ypath or "")

    def value_loc(self, key, ypath=None):
        return Y.value_loc(self.m, key, self.file, ypath or "")


def _load_fluid(section, defaults, errs) -> dict[str, ParamValue]:
    out = {}
    for key, val, parent, f in entries(section):
        if key not in FLUID_PROPS:
            errs.add(f"unknown fluid property '{key}'{suggest(str(key), FLUID_PROPS)}",
                     Y.key_loc(parent, key, f, f"fluid.{key}"), f"fluid properties: {', '.join(FLUID_PROPS)}")
            continue
        pv = param_value(val, FLUID_PROPS[key], _MapWhere(parent, f), key, f"fluid.{key}", defaults, errs)
        if pv is not None:
            out[key] = pv
    return out


def _load_component(name: str, src: CompSource, defaults, fluid, errs) -> ComponentDecl | None:
    cmap, loc = src.cmap, src.node_loc()
    if not Y.is_map(cmap):
        errs.add(f"component '{name}' must be a mapping with a 'type:'", loc, "e.g. 'tank: {type: tank, ports: {T: n}}'")
        return None
    if "type" not in cmap:
        near = next((k for k in cmap if suggest(str(k), ["type", "template"])), None)
        meant = "template" if near and suggest(str(near), ["template"]) else "type"
        errs.add(f"component '{name}' has no 'type:'" + (f" (is '{near}' a misspelt '{meant}'?)" if near else ""),
                 src.key_loc(near) if near else loc, "add e.g. 'type: orifice'; 'hydro components' lists the types")
        return None
    tname = cmap.get("type")
    cls = registry.get(str(tname))
    if cls is None:
        errs.add(f"unknown component type '{tname}'{suggest(str(tname), registry.all_types())}",
                 src.value_loc("type"), "'hydro components' lists the types")
        return None
    ports = _load_ports(name, cls, src, errs)
    params: dict[str, ParamValue] = {}
    known = [p.name for p in cls.parameters]
    for key, val in cmap.items():
        if key in COMPONENT_KEYS:
            continue
        if key not in known:
            errs.add(f"{cls.type} '{name}' has no parameter '{key}'{suggest(str(key), known + ['type', 'ports'])}",
                     src.key_loc(key), f"parameters of {cls.type}: {', '.join(known) or 'none'} "
                     f"('hydro components {cls.type}' describes them)")
            continue
        spec = cls.param(key)
        pv = param_value(val, spec.unit, src, key, f"{src.ypath}.{key}", defaults, errs, vector=spec.vector)
        if pv is not None and check_param(name, spec, pv, errs):
            params[str(key)] = pv
    ok = _defaults(name, cls, params, fluid, loc, errs)
    if ok:
        for problem in cls().check({k: v.value for k, v in params.items()}):
            errs.add(f"'{name}': {problem}", loc, "check the parameters of this component")
    return ComponentDecl(name, cls.type, ports, params, loc, template=src.instance)


def _load_ports(name, cls, src: CompSource, errs) -> dict[str, str]:
    ports: dict[str, str] = {}
    pmap = src.cmap.get("ports")
    names = [p.name for p in cls.ports]
    if pmap is not None and not Y.is_map(pmap):
        errs.add(f"'ports' of '{name}' must map port names to node names", src.value_loc("ports"),
                 f"e.g. ports: {{{', '.join(f'{p}: <node>' for p in names)}}}")
        return ports
    for port, node in (pmap or {}).items():
        ploc = Y.key_loc(pmap, port, src.file, f"{src.ypath}.ports.{port}")
        if cls.port(str(port)) is None:
            errs.add(f"{cls.type} has no port '{port}'{suggest(str(port), names)}", ploc,
                     f"ports of {cls.type}: {', '.join(names)}")
        elif not isinstance(node, str) or not node.strip():
            errs.add(f"port '{port}' of '{name}' must name a node", ploc, f"e.g. {port}: n_{name}_{port}")
        else:
            ports[str(port)] = node.strip()
    for spec in cls.ports:
        if spec.name not in ports and not spec.optional and (pmap is None or spec.name not in pmap):
            errs.add(f"port '{spec.name}' of '{name}' ({cls.type}, {spec.domain.value}) is not connected",
                     src.value_loc("ports") if pmap is not None else src.node_loc(),
                     f"add '{spec.name}: <node>' under ports (use 'ground' for the reference)")
    return ports


def _defaults(name, cls, params, fluid, loc, errs) -> bool:
    """Fill parameters the file does not give from the fluid section or the spec defaults."""
    ok = True
    for spec in cls.parameters:
        if spec.name in params:
            continue
        if spec.fluid and spec.fluid in fluid:
            fv = fluid[spec.fluid]
            if not check_param(name, spec, fv, errs):
                ok = False
                continue
            params[spec.name] = ParamValue(fv.value, fv.loc, fv.free, fv.bounds, fv.unit, fv.log, given=False)
        elif spec.default is not None:
            params[spec.name] = ParamValue(list(spec.default) if spec.vector else spec.default, loc, given=False)
        else:
            ok = False
            errs.add(f"'{name}' ({cls.type}) needs parameter '{spec.name}' [{spec.unit}]: {spec.description}", loc,
                     f"add '{spec.name}: <value>' to '{name}'")
    return ok


def check_param(name: str, spec, pv: ParamValue, errs: Errors) -> bool:
    """The one check of a parameter value against its spec's physical range (finite, sign,
    min/max, plausible magnitude), of its identification bounds against the same range, and
    of a free start value against its bounds. False (and a located problem) when it fails."""
    problem = spec.check(pv.value)
    if problem:
        errs.add(f"'{name}': {problem}", pv.loc, "give a physically valid value")
        return False
    if pv.bounds is not None:
        problem = spec.check(list(pv.bounds))
        if problem:
            errs.add(f"'{name}': bounds {list(pv.bounds)} leave the physical range: {problem}", pv.loc,
                     "give bounds inside the parameter's valid range ('hydro components TYPE' lists it)")
            return False
        if pv.free and not spec.vector and not pv.bounds[0] <= pv.value <= pv.bounds[1]:
            errs.add(f"'{name}': start value {pv.value:g} {spec.unit} is outside its bounds "
                     f"[{pv.bounds[0]:g}, {pv.bounds[1]:g}] {spec.unit}", pv.loc,
                     "move the value inside the bounds or widen them (it would be clipped silently)")
            return False
    return True


def _check_keys(m, allowed, file, errs, what="key", ypath="") -> None:
    for k in m:
        if k not in allowed:
            errs.add(f"unknown {what} '{k}'{suggest(str(k), allowed)}",
                     Y.key_loc(m, k, file, f"{ypath}{k}"), f"allowed: {', '.join(allowed)}")

