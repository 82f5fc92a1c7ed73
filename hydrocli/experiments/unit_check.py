"""One unit check where a recorded quantity enters: the unit of a column (CSV header
``P1[bar]``, HDF5 ``unit`` attribute, or the experiment's ``{column, unit, scale}``) must have
the dimension of the machine signal it feeds.

    dimension(column unit) × dimension(scale unit) = dimension(machine input/output unit)

A column without a unit (``[1]`` or none) holds bare SI numbers and is not checked, and
neither is a signal whose machine unit is unknown or dimensionless ("1"). The time column
must be a time. Errors point at the header cell (CSV line 1, its column), the HDF5 dataset,
or the experiment file's line that gave the unit.
"""
from __future__ import annotations

from ..errors import DataError, Location, Problem
from ..units import registry


def _dimensionality(unit: str):
    from ..units import parse_unit
    try:
        return registry().Quantity(1.0, parse_unit(unit)).dimensionality
    except Exception:
        return None


def _file_loc(rec, col: str) -> Location:
    names = list(rec.units)
    if rec.file.lower().endswith(".csv") and col in names:
        return Location(rec.file, 1, names.index(col) + 1, col)
    return Location(rec.file, path=col)


def check_column(rec, col: str, target_unit: str | None, spec=None, loc: Location | None = None,
                 what: str = "") -> None:
    """Raise DataError when column ``col`` (with ``spec``'s unit and scale, if a mapping)
    cannot be a quantity in ``target_unit``."""
    if not target_unit or target_unit in ("1", ""):
        return
    from ..netlist import yamldoc as Y
    given = Y.is_map(spec) and spec.get("unit") is not None
    raw = str(spec["unit"]) if given else str(rec.units.get(col, "1") or "1")
    scale = spec.get("scale") if Y.is_map(spec) else None
    scale_unit = str(scale).strip().split(None, 1)[1] if isinstance(scale, str) and len(str(scale).split()) > 1 \
        else "1"
    if raw in ("1", "") and scale_unit == "1":
        return
    want = _dimensionality(target_unit)
    got_raw, got_scale = _dimensionality(raw), _dimensionality(scale_unit)
    if want is None or got_raw is None or got_scale is None:
        return                                            # unknown units are reported where they are read
    got = (registry().Quantity(1.0, raw) * registry().Quantity(1.0, scale_unit)).dimensionality \
        if scale_unit != "1" else got_raw
    if got == want:
        return
    where = (loc or Location(rec.file)) if given or scale_unit != "1" else _file_loc(rec, col)
    source = f"unit '{raw}'" + (f" × scale unit '{scale_unit}'" if scale_unit != "1" else "")
    raise DataError(Problem(f"{what or col}: column '{col}' has {source} ({got}) but it feeds a quantity in "
                            f"{target_unit} ({want})", where,
                            f"give the column a unit convertible to {target_unit}"
                            + (" (or a scale with units, e.g. '0.02 m/V')" if scale_unit == "1" else "")))


def check_time_unit(rec, tname: str) -> None:
    """The time column's unit (if any) must be a time."""
    unit = str(rec.units.get(tname, "1") or "1")
    if unit == "1":
        return
    got, want = _dimensionality(unit), _dimensionality("s")
    if got is not None and got != want:
        raise DataError(Problem(f"time column '{tname}' has unit '{unit}' ({got}), not a time", _file_loc(rec, tname),
                                "write the time column as t[s] or t[ms]"))


def check_recording_columns(rec, model) -> None:
    """A recording used directly: each column named like a machine input/output is checked."""
    for name in model.input_names:
        if name in rec.columns:
            check_column(rec, name, model.input_units.get(name))
    for name in model.output_names:
        if name in rec.columns:
            check_column(rec, name, model.output_unit_si(name))


#: Most samples an experiment grid may have (20 M samples × 8 B = 160 MB per signal): a
#: "1e6 s at 1 kHz" design or a "resample: 1 GHz" is refused instead of exhausting memory.
MAX_SAMPLES = 20_000_000


def checked_quantity(value: float, loc: Location, what: str, positive: bool = False) -> float:
    """``value`` (SI) if finite (and > 0 when ``positive``), else a located DataError."""
    import math
    if not math.isfinite(value):
        raise DataError(Problem(f"{what} must be a finite number (got {value})", loc, "give a finite value"))
    if positive and value <= 0:
        raise DataError(Problem(f"{what} must be greater than 0 (got {value:g})", loc, "give a positive value"))
    return value


def check_samples(duration: float, rate: float, loc: Location, what: str) -> None:
    """Refuse a time grid of more than :data:`MAX_SAMPLES` samples."""
    n = duration * rate
    if n > MAX_SAMPLES:
        raise DataError(Problem(f"{what}: {duration:g} s at {rate:g} Hz is {n:.3g} samples; at most "
                                f"{MAX_SAMPLES:.3g} are allowed", loc, "shorten the experiment or lower the rate"))
