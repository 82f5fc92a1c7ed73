"""Load a machine file: YAML → :class:`Netlist` with SI values, checked against the specs.

All problems of a file are collected and raised together, each with file, line, column,
what is wrong and how to fix it. Unknown keys are rejected with "did you mean".
"""
from __future__ import annotations

from pathlib import Path

from ..components import registry
from ..errors import HydroError, Location, NetlistError, ProblemCollector
from ..units import dimensionality, same_dimension, to_si
from . import yamldoc as Y
from .model import ComponentDecl, InputDecl, Netlist, OutputDecl, ParamValue
from .templates import expand_templates

TOP_KEYS = ("name", "description", "units", "fluid", "include", "templates", "inputs", "outputs",
            "components", "initial", "notes")
PARAM_KEYS = ("value", "free", "bounds", "unit", "log", "description")
INPUT_KEYS = ("unit", "hold", "description")
OUTPUT_KEYS = ("expr", "unit", "description")
FLUID_PROPS = {"beta": "Pa", "rho": "kg/m^3", "nu": "m^2/s", "p_tank": "Pa"}
UNIT_KEYS = ("pressure", "length", "area", "volume", "flow", "mass", "force", "time", "velocity",
             "angle", "torque", "inertia", "stiffness", "damping", "flow_gain", "leakage")


def load_netlist(path: str | Path) -> Netlist:
    doc, text = Y.load_file(path)
    return load_doc(doc, str(path), text)


def load_netlist_text(text: str, file: str = "<machine>") -> Netlist:
    return load_doc(Y.load_text(text, file), file, text)


def load_doc(doc, file: str, text: str = "") -> Netlist:
    errs = ProblemCollector()
    sections = _merge_includes(doc, file, errs, seen={str(Path(file).resolve())})
    _check_keys(doc, TOP_KEYS, file, "", errs, what="top-level key")
    defaults = _unit_defaults(sections.get("units"), errs)
    fluid = _load_fluid(sections.get("fluid"), defaults, errs)
    comps_src = expand_templates(sections.get("components"), sections.get("templates"), errs)
    components = {}
    for name, (cmap, cfile, ypath) in comps_src.items():
        decl = _load_component(name, cmap, cfile, ypath, defaults, fluid, errs)
        if decl is not None:
            components[name] = decl
    inputs = _load_inputs(sections.get("inputs"), errs)
    outputs = _load_outputs(sections.get("outputs"), errs)
    initial = _load_initial(sections.get("initial"), defaults, errs)
    errs.raise_if_any(NetlistError)
    name = str(doc.get("name") or Path(file).stem)
    return Netlist(name=name, file=file, components=components, inputs=inputs, outputs=outputs,
                   initial=initial, fluid=fluid, description=str(doc.get("description") or ""),
                   text=text, doc=doc)


# -- sections ----------------------------------------------------------------------------
def _merge_includes(doc, file: str, errs: ProblemCollector, seen: set[str]) -> dict:
    """Sections of this file merged over those of its includes: {section: (map, file)}.

    Returns {section: value} where mapping sections are merged key by key; every entry
    remembers its own file through the ``_files`` side table used for locations.
    """
    merged: dict = {}
    inc = doc.get("include")
    if inc is not None:
        items = inc if Y.is_seq(inc) else [inc]
        for i, rel in enumerate(items):
            loc = Y.item_loc(inc, i, file, "include") if Y.is_seq(inc) else Y.value_loc(doc, "include", file)
            if not isinstance(rel, str):
                errs.add("include: expected a file path", loc)
                continue
            path = (Path(file).parent / rel)
            key = str(path.resolve())
            if key in seen:
                errs.add(f"include cycle: {rel} includes itself", loc, "remove one of the include lines")
                continue
            try:
                sub, _ = Y.load_file(path)
            except HydroError as exc:
                errs.add(f"cannot include '{rel}': {exc.problems[0].message}", loc,
                         "paths are relative to the including file")
                continue
            sub_sections = _merge_includes(sub, str(path), errs, seen | {key})
            _merge_into(merged, sub_sections)
    own = {}
    for k, v in doc.items():
        if k in ("include", "name", "description", "notes"):
            continue
        if Y.is_map(v):
            own[k] = {kk: (vv, v, file) for kk, vv in v.items()}
        else:
            own[k] = v
    _merge_into(merged, own)
    return merged


def _merge_into(dst: dict, src: dict) -> None:
    for k, v in src.items():
        if isinstance(v, dict) and isinstance(dst.get(k), dict):
            dst[k].update(v)
        else:
            dst[k] = v


def _entries(section):
    """Iterate (key, value, parent_map, file) over a merged mapping section."""
    if not isinstance(section, dict):
        return []
    return [(k, v, parent, f) for k, (v, parent, f) in section.items()]


def _unit_defaults(section, errs: ProblemCollector) -> dict[str, str]:
    """Map dimensionality → default unit from the file-level ``units:`` mapping."""
    out: dict[str, str] = {}
    for key, unit, parent, f in _entries(section):
        loc = Y.key_loc(parent, key, f, f"units.{key}")
        if key not in UNIT_KEYS:
            errs.add(f"unknown unit category '{key}'{registry.suggest(str(key), UNIT_KEYS)}", loc,
                     f"categories: {', '.join(UNIT_KEYS)}")
            continue
        try:
            out[dimensionality(str(unit))] = str(unit)
        except HydroError as exc:
            errs.add(exc.problems[0].message, Y.value_loc(parent, key, f), exc.problems[0].hint)
    return out


def _load_fluid(section, defaults, errs) -> dict[str, ParamValue]:
    out = {}
    for key, val, parent, f in _entries(section):
        if key not in FLUID_PROPS:
            errs.add(f"unknown fluid property '{key}'{registry.suggest(str(key), FLUID_PROPS)}",
                     Y.key_loc(parent, key, f, f"fluid.{key}"), f"fluid properties: {', '.join(FLUID_PROPS)}")
            continue
        pv = _param_value(val, FLUID_PROPS[key], parent, key, f, f"fluid.{key}", defaults, errs)
        if pv is not None:
            out[key] = pv
    return out


def _load_component(name, cmap, file, ypath, defaults, fluid, errs) -> ComponentDecl | None:
    loc = Y.node_loc(cmap, file, ypath) if Y.is_map(cmap) else Location(file, None, None, ypath)
    if not Y.is_map(cmap):
        errs.add(f"component '{name}' must be a mapping with a 'type:'", loc)
        return None
    tname = cmap.get("type")
    if tname is None:
        errs.add(f"component '{name}' has no 'type:'", Y.key_loc(cmap, next(iter(cmap), None), file, ypath)
                 if cmap else loc, "add e.g. 'type: orifice'; 'hydro components' lists the types")
        return None
    cls = registry.get(str(tname))
    if cls is None:
        errs.add(f"unknown component type '{tname}'{registry.suggest(str(tname), registry.all_types())}",
                 Y.value_loc(cmap, "type", file, f"{ypath}.type"), "'hydro components' lists the types")
        return None
    ports: dict[str, str] = {}
    pmap = cmap.get("ports")
    if pmap is not None and not Y.is_map(pmap):
        errs.add(f"'ports' of '{name}' must map port names to node names",
                 Y.value_loc(cmap, "ports", file, f"{ypath}.ports"), "e.g. ports: {A: chamber_a, B: tank}")
    elif pmap is not None:
        for port, node in pmap.items():
            ploc = Y.key_loc(pmap, port, file, f"{ypath}.ports.{port}")
            if cls.port(str(port)) is None:
                errs.add(f"{cls.type} has no port '{port}'{registry.suggest(str(port), [p.name for p in cls.ports])}",
                         ploc, f"ports of {cls.type}: {', '.join(p.name for p in cls.ports)}")
                continue
            if not isinstance(node, str) or not node.strip():
                errs.add(f"port '{port}' of '{name}' must name a node", ploc)
                continue
            ports[str(port)] = node.strip()
    for spec in cls.ports:
        if spec.name not in ports and not spec.optional:
            errs.add(f"port '{spec.name}' of '{name}' ({cls.type}, {spec.domain.value}) is not connected", loc,
                     f"add '{spec.name}: <node>' under ports (use 'ground' for the reference)")
    params: dict[str, ParamValue] = {}
    known = {p.name for p in cls.parameters}
    for key, val in cmap.items():
        if key in ("type", "ports", "description"):
            continue
        kloc = Y.key_loc(cmap, key, file, f"{ypath}.{key}")
        if key not in known:
            errs.add(f"{cls.type} has no parameter '{key}'{registry.suggest(str(key), known | {'type', 'ports'})}",
                     kloc, f"'hydro components {cls.type}' lists its parameters")
            continue
        spec = cls.param(key)
        pv = _param_value(val, spec.unit, cmap, key, file, f"{ypath}.{key}", defaults, errs, vector=spec.vector)
        if pv is None:
            continue
        problem = spec.check(pv.value)
        if problem:
            errs.add(f"'{name}': {problem}", Y.value_loc(cmap, key, file, f"{ypath}.{key}"),
                     "give a physically valid value")
            continue
        if pv.bounds and not (pv.bounds[0] < pv.bounds[1]):
            errs.add(f"'{name}.{key}': bounds must be [lower, upper] with lower < upper (got {pv.bounds})",
                     Y.value_loc(cmap, key, file, f"{ypath}.{key}"), "swap the two bounds")
            continue
        params[str(key)] = pv
    for spec in cls.parameters:
        if spec.name in params:
            continue
        if spec.fluid and spec.fluid in fluid:
            fv = fluid[spec.fluid]
            params[spec.name] = ParamValue(fv.value, fv.loc, fv.free, fv.bounds, fv.unit, fv.log, given=False)
        elif spec.default is not None:
            params[spec.name] = ParamValue(list(spec.default) if spec.vector else spec.default, loc, given=False)
        else:
            errs.add(f"'{name}' ({cls.type}) needs parameter '{spec.name}' [{spec.unit}]: {spec.description}", loc,
                     f"add '{spec.name}: <value>' to '{name}'")
    decl = ComponentDecl(name, cls.type, ports, params, loc)
    for problem in cls().check({k: v.value for k, v in params.items()}):
        errs.add(f"'{name}': {problem}", loc)
    return decl


def _param_value(val, si_unit, parent, key, file, ypath, defaults, errs, vector=False) -> ParamValue | None:
    """A parameter given as a number, a unit string, a list, or a {value, free, bounds, …} map."""
    loc = Y.value_loc(parent, key, file, ypath)
    free, bounds, unit, log = False, None, None, None
    if Y.is_map(val):
        for k in val:
            if k not in PARAM_KEYS:
                errs.add(f"unknown key '{k}' in parameter '{key}'{registry.suggest(str(k), PARAM_KEYS)}",
                         Y.key_loc(val, k, file, f"{ypath}.{k}"), f"allowed: {', '.join(PARAM_KEYS)}")
                return None
        if "value" not in val:
            errs.add(f"parameter '{key}' given as a mapping needs 'value:'", loc)
            return None
        unit = val.get("unit")
        free = bool(val.get("free", False))
        log = val.get("log")
        raw_bounds = val.get("bounds")
        raw = val["value"]
        loc = Y.value_loc(val, "value", file, ypath)
        if raw_bounds is not None:
            if not Y.is_seq(raw_bounds) or len(raw_bounds) != 2:
                errs.add(f"bounds of '{key}' must be a list [lower, upper]", Y.value_loc(val, "bounds", file, ypath))
                return None
            try:
                bounds = tuple(_convert(b, si_unit, unit, defaults, Y.value_loc(val, "bounds", file, ypath), key)
                               for b in raw_bounds)
            except HydroError as exc:
                errs.extend(exc)
                return None
    else:
        raw = val
    try:
        if vector:
            if not Y.is_seq(raw):
                raw = [raw]
            value = [_convert(v, si_unit, unit, defaults, loc, key) for v in raw]
        else:
            if Y.is_seq(raw):
                errs.add(f"parameter '{key}' takes one value, not a list", loc)
                return None
            value = _convert(raw, si_unit, unit, defaults, loc, key)
    except HydroError as exc:
        errs.extend(exc)
        return None
    written_unit = unit or (_unit_of(raw) if isinstance(raw, str) else None)
    return ParamValue(value, loc, free, bounds, written_unit, log)


def _unit_of(text: str) -> str | None:
    parts = text.strip().split(None, 1)
    return parts[1] if len(parts) == 2 else None


def _convert(raw, si_unit, unit, defaults, loc, key) -> float:
    default_unit = unit or defaults.get(dimensionality(si_unit))
    if unit and not same_dimension(unit, si_unit):
        from ..errors import UnitError
        raise UnitError(f"{key}: unit '{unit}' is not convertible to {si_unit}", location=loc)
    return to_si(raw, si_unit, default_unit=default_unit, location=loc, what=str(key))


def _load_inputs(section, errs) -> dict[str, InputDecl]:
    out = {}
    for key, val, parent, f in _entries(section):
        loc = Y.key_loc(parent, key, f, f"inputs.{key}")
        val = val if val is not None else {}
        if isinstance(val, str):
            val = {"unit": val}
        if not Y.is_map(val):
            errs.add(f"input '{key}' must be a mapping like {{unit: bar}}", loc)
            continue
        bad = [k for k in val if k not in INPUT_KEYS]
        for k in bad:
            errs.add(f"unknown key '{k}' in input '{key}'{registry.suggest(str(k), INPUT_KEYS)}",
                     Y.key_loc(val, k, f), f"allowed: {', '.join(INPUT_KEYS)}")
        hold = str(val.get("hold", "linear"))
        if hold not in ("linear", "zoh"):
            errs.add(f"input '{key}': hold must be 'linear' or 'zoh'", Y.value_loc(val, "hold", f))
        unit = str(val.get("unit", "1"))
        try:
            dimensionality(unit)
        except HydroError as exc:
            errs.add(f"input '{key}': {exc.problems[0].message}", Y.value_loc(val, "unit", f))
        out[str(key)] = InputDecl(str(key), unit, hold, str(val.get("description", "")), loc)
    return out


def _load_outputs(section, errs) -> dict[str, OutputDecl]:
    out = {}
    for key, val, parent, f in _entries(section):
        loc = Y.key_loc(parent, key, f, f"outputs.{key}")
        if isinstance(val, str):
            val = {"expr": val}
        if not Y.is_map(val) or "expr" not in val:
            errs.add(f"output '{key}' needs an expression, e.g. '{key}: chamber_a.p' or '{{expr: ..., unit: bar}}'",
                     loc)
            continue
        for k in val:
            if k not in OUTPUT_KEYS:
                errs.add(f"unknown key '{k}' in output '{key}'{registry.suggest(str(k), OUTPUT_KEYS)}",
                         Y.key_loc(val, k, f), f"allowed: {', '.join(OUTPUT_KEYS)}")
        unit = val.get("unit")
        if unit is not None:
            try:
                dimensionality(str(unit))
            except HydroError as exc:
                errs.add(f"output '{key}': {exc.problems[0].message}", Y.value_loc(val, "unit", f))
        out[str(key)] = OutputDecl(str(key), str(val["expr"]), None if unit is None else str(unit),
                                   str(val.get("description", "")), Y.value_loc(val, "expr", f, f"outputs.{key}"))
    return out


def _load_initial(section, defaults, errs) -> dict[str, ParamValue]:
    """Initial values keyed by state name; the unit is checked when the model is built."""
    out = {}
    for key, val, parent, f in _entries(section):
        loc = Y.value_loc(parent, key, f, f"initial.{key}")
        if isinstance(val, (int, float)) and not isinstance(val, bool):
            out[str(key)] = ParamValue(float(val), loc, unit=None)
        elif isinstance(val, str):
            out[str(key)] = ParamValue(val, loc, unit=_unit_of(val))  # converted by the builder
        else:
            errs.add(f"initial value of '{key}' must be a number or a string like '50 bar'", loc)
    return out


def _check_keys(m, allowed, file, ypath, errs, what="key") -> None:
    for k in m:
        if k not in allowed:
            errs.add(f"unknown {what} '{k}'{registry.suggest(str(k), allowed)}",
                     Y.key_loc(m, k, file, f"{ypath}{k}"), f"allowed: {', '.join(allowed)}")
