"""The ``inputs:``, ``outputs:`` and ``initial:`` sections of a machine file."""
from __future__ import annotations

from ..suggest import suggest
from ..errors import HydroError
from ..units import dimensionality
from . import yamldoc as Y
from .model import InputDecl, OutputDecl, ParamValue
from .params import unit_of

INPUT_KEYS = ("unit", "hold", "description")
OUTPUT_KEYS = ("expr", "unit", "description")
# initial values given by a rule instead of a number, resolved per experiment
# (experiments.initial): start where another state starts, where an output's first measured
# sample puts this state, or such that another state's derivative is zero (a spring's force
# that holds a node at rest)
INITIAL_RULES = ("same_as", "output", "balance")


def entries(section):
    """(key, value, parent_map, file) over a merged mapping section (its items map key →
    (value, parent mapping, file) so every entry keeps its own location)."""
    if not isinstance(section, dict):
        return []
    return [(k, v, parent, f) for k, (v, parent, f) in section.items()]


def load_inputs(section, errs) -> dict[str, InputDecl]:
    out = {}
    for key, val, parent, f in entries(section):
        loc = Y.key_loc(parent, key, f, f"inputs.{key}")
        val = val if val is not None else {}
        if isinstance(val, str):
            val = {"unit": val}
        if not Y.is_map(val):
            errs.add(f"input '{key}' must be a mapping like {{unit: bar}}", loc, f"e.g. {key}: {{unit: bar}}")
            continue
        bad = [k for k in val if k not in INPUT_KEYS]
        for k in bad:
            errs.add(f"unknown key '{k}' in input '{key}'{suggest(str(k), INPUT_KEYS)}",
                     Y.key_loc(val, k, f), f"allowed: {', '.join(INPUT_KEYS)}")
        hold = str(val.get("hold", "linear"))
        if hold not in ("linear", "zoh"):
            errs.add(f"input '{key}': hold must be 'linear' or 'zoh', not '{hold}'", Y.value_loc(val, "hold", f, f"inputs.{key}.hold"),
                     "'zoh' holds each sample until the next one; 'linear' interpolates")
        unit = str(val.get("unit", "1"))
        try:
            dimensionality(unit)
        except HydroError as exc:
            errs.add(f"input '{key}': {exc.problems[0].message}", Y.value_loc(val, "unit", f, f"inputs.{key}.unit"),
                     exc.problems[0].hint)
        out[str(key)] = InputDecl(str(key), unit, hold, str(val.get("description", "")), loc)
    return out


def load_outputs(section, errs) -> dict[str, OutputDecl]:
    out = {}
    for key, val, parent, f in entries(section):
        ypath = f"outputs.{key}"
        loc = Y.key_loc(parent, key, f, ypath)
        if isinstance(val, str):
            expr_loc, val = Y.value_loc(parent, key, f, ypath), {"expr": val}
        elif Y.is_map(val):
            expr_loc = Y.value_loc(val, "expr", f, f"{ypath}.expr")
        else:
            val, expr_loc = None, loc
        bad = [k for k in (val or {}) if k not in OUTPUT_KEYS]
        for k in bad:
            errs.add(f"unknown key '{k}' in output '{key}'{suggest(str(k), OUTPUT_KEYS)}",
                     Y.key_loc(val, k, f, f"{ypath}.{k}"), f"allowed: {', '.join(OUTPUT_KEYS)}")
        if val is None or ("expr" not in val and not bad):
            errs.add(f"output '{key}' needs an expression, e.g. '{key}: chamber_a.p' or '{{expr: ..., unit: bar}}'",
                     loc, "outputs name node quantities (chamber_a.p, load.x) or component variables")
        if val is None or bad or "expr" not in val:
            continue
        unit = val.get("unit")
        if unit is not None:
            try:
                dimensionality(str(unit))
            except HydroError as exc:
                errs.add(f"output '{key}': {exc.problems[0].message}", Y.value_loc(val, "unit", f, f"{ypath}.unit"),
                         exc.problems[0].hint)
        out[str(key)] = OutputDecl(str(key), str(val["expr"]), None if unit is None else str(unit),
                                   str(val.get("description", "")), expr_loc)
    return out


def load_initial(section, defaults, errs) -> dict[str, ParamValue]:
    """Initial values keyed by state name; the unit is checked when the model is built."""
    out = {}
    for key, val, parent, f in entries(section):
        loc = Y.value_loc(parent, key, f, f"initial.{key}")
        if isinstance(val, (int, float)) and not isinstance(val, bool):
            out[str(key)] = ParamValue(float(val), loc, unit=None)
        elif isinstance(val, str):
            out[str(key)] = ParamValue(val, loc, unit=unit_of(val))  # converted by the builder
        elif Y.is_map(val) and len(val) == 1 and next(iter(val)) in INITIAL_RULES \
                and isinstance(next(iter(val.values())), str):
            kind, ref = next(iter(val.items()))
            out[str(key)] = ParamValue({str(kind): str(ref)}, loc)      # references checked by the builder
        else:
            errs.add(f"initial value of '{key}' must be a number, a string like '50 bar', or one rule "
                     f"({', '.join(f'{{{k}: NAME}}' for k in INITIAL_RULES)})", loc,
                     "e.g. chamber_a.p: \"50 bar\", piston.x: \"70 mm\", rod.x: {same_as: load.x}")
    return out
