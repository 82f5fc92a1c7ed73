"""JSON Schema of machine files, generated from the component registry's specs.

Editors (VS Code's YAML extension, PyCharm) use it to complete and check machine files:
``# yaml-language-server: $schema=machine.schema.json``. Each component type contributes
its ports (with domain) and parameters (unit, default, description); a parameter may be a
number, a string with a unit, or a ``{value, free, bounds, unit, log}`` mapping.
"""
from __future__ import annotations

from .components import registry
from .components.base import Component
from .netlist.loader import FLUID_PROPS, UNIT_KEYS
from .netlist.sections import INITIAL_RULES

NUMBER_WITH_UNIT = r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?(\s*\S.*)?$"
_STR = {"type": "string"}


def machine_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a machine YAML file."""
    types = registry.all_types()
    defs = {"scalar": {"oneOf": [{"type": "number"}, {"type": "string", "pattern": NUMBER_WITH_UNIT}],
                       "description": "a number (SI or the file's default unit) or a string with a unit, e.g. '210 bar'"},
            "quantity": _quantity(), "component": _component(types), "instance": _instance(),
            "components": {"type": "object", "additionalProperties": {"$ref": "#/$defs/component"}}}
    for tname, cls in types.items():
        defs[f"type_{tname}"] = _component_type(cls)
    props = {
        "name": dict(_STR, description="machine name"),
        "description": _STR,
        "notes": {},
        "units": _closed({k: dict(_STR, description=f"default unit of bare {k} numbers") for k in UNIT_KEYS}),
        "fluid": _closed({k: {"$ref": "#/$defs/quantity", "description": f"[{u}]"} for k, u in FLUID_PROPS.items()}),
        "include": {"oneOf": [_STR, {"type": "array", "items": _STR}],
                    "description": "files merged under this one (paths relative to it)"},
        "templates": {"type": "object", "additionalProperties": _closed({
            "ports": {"type": "array", "items": _STR}, "components": {"$ref": "#/$defs/components"},
            "description": _STR}, required=["components"])},
        "inputs": {"type": "object", "additionalProperties": {"oneOf": [
            _STR, {"type": "null"},
            _closed({"unit": _STR, "hold": {"enum": ["linear", "zoh"]}, "description": _STR})]}},
        "outputs": {"type": "object", "additionalProperties": {"oneOf": [
            _STR, _closed({"expr": _STR, "unit": _STR, "description": _STR}, required=["expr"])]}},
        # a value, or a rule naming another state ({same_as: load.x}, {balance: chamber_a.p}, …)
        "initial": {"type": "object", "additionalProperties": {"oneOf": [
            {"$ref": "#/$defs/scalar"},
            *({"type": "object", "properties": {r: _STR}, "required": [r], "additionalProperties": False}
              for r in INITIAL_RULES)]}},
        "components": {"$ref": "#/$defs/components"},
    }
    return {"$schema": "https://json-schema.org/draft/2020-12/schema",
            "$id": "https://hydrocli.invalid/machine.schema.json",
            "title": "hydrocli machine file", "type": "object",
            "properties": props, "additionalProperties": False, "$defs": defs}


def _closed(props: dict, required: list[str] | None = None) -> dict:
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    return out


def _quantity() -> dict:
    scalar_or_list = {"oneOf": [{"$ref": "#/$defs/scalar"}, {"type": "array", "items": {"$ref": "#/$defs/scalar"}}]}
    mapping = _closed({
        "value": scalar_or_list, "free": {"type": "boolean", "description": "estimate it in 'hydro identify'"},
        "bounds": {"type": "array", "items": {"$ref": "#/$defs/scalar"}, "minItems": 2, "maxItems": 2,
                   "description": "[lower, upper] for identification"},
        "unit": dict(_STR, description="unit of bare numbers in value and bounds"),
        "log": {"type": "boolean", "description": "search on a log scale"}, "description": _STR,
    }, required=["value"])
    return {"oneOf": [{"$ref": "#/$defs/scalar"}, {"type": "array", "items": {"$ref": "#/$defs/scalar"}}, mapping]}


def _component(types: dict) -> dict:
    per_type = [{"if": {"properties": {"type": {"const": t}}, "required": ["type"]},
                 "then": {"$ref": f"#/$defs/type_{t}"}} for t in types]
    return {"if": {"type": "object", "required": ["template"]}, "then": {"$ref": "#/$defs/instance"},
            "else": {"type": "object", "required": ["type"],
                     "properties": {"type": {"enum": list(types), "description": "component type"}},
                     "allOf": per_type}}


def _instance() -> dict:
    return {"type": "object", "required": ["template"],
            "properties": {"template": dict(_STR, description="name of a template under 'templates:'"),
                           "ports": {"type": "object", "additionalProperties": _STR}, "description": _STR},
            "patternProperties": {r"^[^.]+\..+$": {"$ref": "#/$defs/quantity"}},
            "additionalProperties": False,
            "description": "an instance of a template; override inner parameters as component.parameter"}


def _component_type(cls: type[Component]) -> dict:
    ports = {p.name: dict(_STR, description=f"{p.domain.value}: {p.description}".rstrip(": "))
             for p in cls.ports}
    props = {"type": {"const": cls.type}, "description": _STR,
             "ports": {"type": "object", "properties": ports, "additionalProperties": False,
                       "required": [p.name for p in cls.ports if not p.optional]}}
    for p in cls.parameters:
        default = list(p.default) if isinstance(p.default, tuple) else p.default
        desc = f"{p.description} [{p.unit}]" + (f" ({p.source})" if p.source else "")
        props[p.name] = {"$ref": "#/$defs/quantity", "description": desc}
        if default is not None:
            props[p.name]["default"] = default
    required = ["type", "ports"] if any(not p.optional for p in cls.ports) else ["type"]
    return {"type": "object", "description": f"{cls.description} ({cls.family})", "properties": props,
            "required": required, "additionalProperties": False}
