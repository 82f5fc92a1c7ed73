"""Parameter values as a machine file writes them: a number, a unit string, a list, or a
``{value, free, bounds, unit, log, description}`` mapping; converted to SI once, here."""
from __future__ import annotations

from ..suggest import suggest
from ..errors import HydroError, Location, Problem, ProblemCollector, UnitError
from ..units import dimensionality, same_dimension, to_si
from . import yamldoc as Y
from .model import ParamValue

PARAM_KEYS = ("value", "free", "bounds", "unit", "log", "description")


class Errors(ProblemCollector):
    """A collector that remembers whether every problem is a unit problem (→ UnitError)."""

    def __init__(self) -> None:
        super().__init__()
        self._unit_ids: set[int] = set()

    def extend(self, err: HydroError) -> None:
        super().extend(err)
        if isinstance(err, UnitError):
            self._unit_ids.update(id(p) for p in err.problems)

    def raise_all(self, default_cls) -> None:
        if not self.problems:
            return
        only_units = all(id(p) in self._unit_ids for p in self.problems)
        raise (UnitError if only_units else default_cls)(self.problems)


def param_value(val, si_unit: str, where, key, ypath: str, defaults: dict, errs: Errors,
                vector: bool = False) -> ParamValue | None:
    """Parse one parameter value; ``where`` gives locations (``key_loc``/``value_loc``)."""
    loc = where.value_loc(key, ypath)
    free, bounds, unit, log = False, None, None, None
    file = loc.file
    if Y.is_map(val):
        bad = [k for k in val if k not in PARAM_KEYS]
        for k in bad:
            errs.add(f"unknown key '{k}' in parameter '{key}'{suggest(str(k), PARAM_KEYS)}",
                     Y.key_loc(val, k, file, f"{ypath}.{k}"), f"allowed: {', '.join(PARAM_KEYS)}")
        if bad:
            return None
        if "value" not in val:
            errs.add(f"parameter '{key}' given as a mapping needs 'value:'", loc, "e.g. {value: 1e-6, free: true}")
            return None
        ok = _check_flag(val, "free", file, ypath, errs) & _check_flag(val, "log", file, ypath, errs)
        unit = val.get("unit")
        if unit is not None:
            try:
                if not same_dimension(str(unit), si_unit):
                    errs.extend(UnitError(f"{key}: unit '{unit}' is not convertible to {si_unit}",
                                          location=Y.value_loc(val, "unit", file, f"{ypath}.unit"),
                                          hint=f"give a unit of the same dimension as {si_unit}"))
                    return None
            except HydroError as exc:
                errs.extend(UnitError([p.at(Y.value_loc(val, "unit", file, f"{ypath}.unit"))
                                       for p in exc.problems]))
                return None
            unit = str(unit)
        free, log = bool(val.get("free", False)), val.get("log")
        raw = val["value"]
        loc = Y.value_loc(val, "value", file, f"{ypath}.value")
        if not ok:
            return None
        if val.get("bounds") is not None:
            bounds = _bounds(val, key, si_unit, unit, defaults, file, ypath, errs)
            if bounds is None:
                return None
    else:
        raw = val
    try:
        if vector:
            raw_list = raw if Y.is_seq(raw) else [raw]
            value = [convert(v, si_unit, unit, defaults, loc, key) for v in raw_list]
        else:
            if Y.is_seq(raw) or Y.is_map(raw):
                errs.add(f"parameter '{key}' takes one value, not a {'list' if Y.is_seq(raw) else 'mapping'}", loc,
                         "write e.g. 'Kv: 4.7e-7' or 'V: \"0.2 L\"'")
                return None
            value = convert(raw, si_unit, unit, defaults, loc, key)
    except HydroError as exc:
        errs.extend(exc)
        return None
    written_unit = unit or (unit_of(raw) if isinstance(raw, str) else None)
    return ParamValue(value, loc, free, bounds, written_unit, log)


def _check_flag(val, name, file, ypath, errs) -> bool:
    if name in val and val[name] is not None and not isinstance(val[name], bool):
        errs.add(f"'{name}' must be true or false, got '{val[name]}'", Y.value_loc(val, name, file, f"{ypath}.{name}"),
                 f"write '{name}: true' or '{name}: false'")
        return False
    return True


def _bounds(val, key, si_unit, unit, defaults, file, ypath, errs):
    raw = val["bounds"]
    bloc = Y.value_loc(val, "bounds", file, f"{ypath}.bounds")
    if not Y.is_seq(raw) or len(raw) != 2:
        errs.add(f"bounds of '{key}' must be a list [lower, upper]", bloc, "e.g. bounds: [1e-7, 2e-6]")
        return None
    try:
        lo, hi = (convert(b, si_unit, unit, defaults, Y.item_loc(raw, i, file, f"{ypath}.bounds"), key)
                  for i, b in enumerate(raw))
    except HydroError as exc:
        errs.extend(exc)
        return None
    if not lo < hi:
        errs.add(f"bounds of '{key}' must be [lower, upper] with lower < upper (got [{raw[0]}, {raw[1]}])", bloc,
                 "swap the two bounds" if lo > hi else "give a non-empty interval")
        return None
    return (lo, hi)


def unit_of(text: str) -> str | None:
    """The unit part of ``"210 bar"`` (None for a bare number)."""
    parts = text.strip().split(None, 1)
    return parts[1] if len(parts) == 2 else None


def convert(raw, si_unit: str, unit: str | None, defaults: dict, loc: Location, key) -> float:
    """SI value of ``raw``; a bare number is in ``unit``, else the file default, else SI."""
    default_unit = unit or defaults.get(dimensionality(si_unit))
    try:
        return to_si(raw, si_unit, default_unit=default_unit, location=loc, what=str(key))
    except UnitError as exc:
        if all(p.hint for p in exc.problems):
            raise
        hint = f"write a number (in {default_unit or si_unit}) or a string with a unit, e.g. '{key}: \"1.5 {si_unit}\"'"
        raise UnitError([Problem(p.message, p.location, p.hint or hint) for p in exc.problems]) from None
