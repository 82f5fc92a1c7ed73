"""The shape of an experiment mapping, checked once before it is used: every key of the
wrong type, every name that matches no machine input/output, every negative weight or
threshold becomes a located DataError (exit 3) instead of an internal error later or a
silently ignored setting."""
from __future__ import annotations

import math

from ..suggest import suggest
from ..netlist import yamldoc as Y
from .signals import KINDS, is_signal

COLUMN_KEYS = ("column", "unit", "scale", "offset")
PREPROCESS_KEYS = ("remove_offset", "lowpass", "resample")


def check_spec(b) -> None:
    """``b`` is the experiment builder (``b.spec``, ``b.model``, ``b.loc(*keys)``, ``b.fail``)."""
    s, model = b.spec, b.model
    _mapping(b, "inputs")
    for name, spec in (s.get("inputs") or {}).items():
        if name not in model.input_names:
            b.fail(f"inputs: '{name}' is not an input of machine {model.name}{suggest(str(name), model.input_names)}",
                   b.loc("inputs", name), f"machine inputs: {', '.join(model.input_names) or 'none'}")
        _channel(b, "inputs", name, spec)
    for section in ("outputs", "measured"):
        _mapping(b, section)
        for name, spec in (s.get(section) or {}).items():
            _channel(b, section, name, spec)
    for section in ("weights", "thresholds", "max_esr"):
        _mapping(b, section)
        for name, value in (s.get(section) or {}).items():
            if name not in model.output_names:
                b.fail(f"{section}: '{name}' is not an output of machine {model.name}"
                       f"{suggest(str(name), model.output_names)}", b.loc(section, name),
                       f"outputs: {', '.join(model.output_names)}")
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                b.fail(f"{section}.{name}: expected a finite number ≥ 0, got {value!r}", b.loc(section, name),
                       f"e.g. {section}: {{{name}: 1}}")
    for section in ("mask", "preprocess"):
        _mapping(b, section)
    fit = s.get("fit")
    if fit is not None:
        names = [x.strip() for x in fit.split(",")] if isinstance(fit, str) else fit
        if not Y.is_seq(names) and not isinstance(names, list) or not names \
                or not all(isinstance(n, str) and n for n in names):
            b.fail(f"fit: expected a non-empty list of output names, got {fit!r}", b.loc("fit"), "e.g. fit: [P1, P2, v]")
    remove = (s.get("preprocess") or {}).get("remove_offset")
    if remove is not None and not Y.is_map(remove):
        b.fail("preprocess.remove_offset must map signal names to {samples: N} or a value",
               b.loc("preprocess", "remove_offset"), "e.g. remove_offset: {P1: {samples: 100}}")
    for name, how in (remove or {}).items():
        if Y.is_map(how):
            n = how.get("samples", 1)
            if isinstance(n, bool) or not isinstance(n, int) or n < 1:
                b.fail(f"remove_offset.{name}.samples must be a whole number ≥ 1, got {n!r}",
                       b.loc("preprocess", "remove_offset"))
    lowpass = (s.get("preprocess") or {}).get("lowpass")
    if lowpass is not None:
        if not Y.is_map(lowpass):
            b.fail("preprocess.lowpass must be a mapping {order, cutoff, signals}", b.loc("preprocess", "lowpass"))
        order = lowpass.get("order", 4)
        if isinstance(order, bool) or not isinstance(order, int) or not 1 <= order <= 10:
            b.fail(f"lowpass order must be a whole number from 1 to 10, got {order!r}", b.loc("preprocess", "lowpass"))
    if s.get("settle") is not None and b.time(s["settle"], "settle") < 0:
        b.fail("settle must be ≥ 0 s", b.loc("settle"))
    name = s.get("name")
    if name is not None and not isinstance(name, str):
        b.fail(f"name must be a string, got {name!r}", b.loc("name"))
    tspec = s.get("time")
    if tspec is not None and not isinstance(tspec, str) and not Y.is_map(tspec):
        b.fail("time: expected a column name or {column: t, unit: ms}", b.loc("time"))
    if Y.is_map(tspec) and tspec.get("unit") is not None:
        from ..errors import HydroError
        from ..units import same_dimension
        try:
            ok = same_dimension(str(tspec["unit"]), "s")
        except HydroError:
            ok = False
        if not ok:
            b.fail(f"time.unit '{tspec['unit']}' is not a unit of time", b.loc("time"), "e.g. time: {column: t, unit: ms}")
    _initial(b)


def _mapping(b, section: str) -> None:
    v = b.spec.get(section)
    if v is not None and not Y.is_map(v):
        b.fail(f"'{section}' must be a mapping (name: value), not a {Y.kind(v)}", b.loc(section),
               f"write '{section}:' followed by 'name: …' entries")


def _channel(b, section: str, name, spec) -> None:
    if is_signal(spec) or isinstance(spec, str):
        return
    if not Y.is_map(spec):
        b.fail(f"{section}.{name}: expected a column name, a mapping {{column, unit, scale, offset}} or a signal, "
               f"got a {Y.kind(spec)}", b.loc(section, name))
    for k in spec:
        if k not in COLUMN_KEYS:
            kinds = list(COLUMN_KEYS) + (list(KINDS) if section == "inputs" else [])
            b.fail(f"{section}.{name}: unknown key '{k}'{suggest(str(k), kinds)}", b.loc(section, name),
                   f"a column mapping has {', '.join(COLUMN_KEYS)}"
                   + (f"; a designed signal is one of {', '.join(KINDS)}" if section == "inputs" else ""))
    for k in ("scale", "offset"):
        v = spec.get(k)
        if isinstance(v, float) and not math.isfinite(v):
            b.fail(f"{section}.{name}.{k} must be finite, got {v}", b.loc(section, name))


def _initial(b) -> None:
    from ..components.base import check_state_value
    from ..units import to_si
    init = b.spec.get("initial")
    if not Y.is_map(init):
        return
    for k, v in init.items():
        if k in b.model.state_names:
            unit = b.model.states[b.model.state_index(k)].unit
            value = to_si(v, unit, location=b.loc("initial", k), what=f"initial.{k}")
            problem = check_state_value(k, unit, value)
            if problem:
                b.fail(problem, b.loc("initial", k), "give a physically valid initial value")
