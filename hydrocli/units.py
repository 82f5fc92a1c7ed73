"""Units: one pint registry; quantities become SI floats once, at load time.

Equations never see units. A parameter spec names its SI unit (e.g. ``"m^3/s/Pa^0.5"``);
a value in a machine or experiment file is a bare number (taken in the file's default
unit for that dimension, else SI) or a string with a unit (``"210 bar"``).
"""
from __future__ import annotations

import functools
import re

import pint

from .errors import Location, UnitError

_registry = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
_NUMBER = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$")


def registry() -> pint.UnitRegistry:
    return _registry


def _clean(text: str) -> str:
    return text.replace("%", " percent ").replace("^", "**").replace("²", "**2").replace("³", "**3")


@functools.lru_cache(maxsize=4096)
def parse_unit(unit: str) -> pint.Unit:
    """Parse a unit string such as ``"L/min/bar^0.5"`` (raises UnitError)."""
    if unit in ("", "1", "-"):
        return _registry.dimensionless
    try:
        q = _registry.parse_expression(_clean(unit))
    except Exception as exc:  # pint raises several types
        raise UnitError(f"unknown unit '{unit}' ({exc.__class__.__name__})",
                        hint="write units like 'bar', 'L/min', 'mm', 'kg/m^3', '%/s'") from None
    if isinstance(q, (int, float)):
        return _registry.dimensionless
    return q.units if q.magnitude == 1 else (q / q.magnitude).units if q.magnitude else q.units


@functools.lru_cache(maxsize=4096)
def _si_factor(unit: str) -> tuple[float, str]:
    """Factor to SI and the dimensionality string of a unit."""
    if unit in ("", "1", "-"):
        return 1.0, str(_registry.dimensionless.dimensionality)
    try:
        q = _registry.parse_expression(_clean(unit))
    except Exception as exc:
        raise UnitError(f"unknown unit '{unit}' ({exc.__class__.__name__})",
                        hint="write units like 'bar', 'L/min', 'mm', 'kg/m^3', '%/s'") from None
    if not isinstance(q, pint.Quantity):
        return float(q), str(_registry.dimensionless.dimensionality)
    base = q.to_base_units()
    return float(base.magnitude), str(base.dimensionality)


def dimensionality(unit: str) -> str:
    return _si_factor(unit)[1]


def same_dimension(a: str, b: str) -> bool:
    return _si_factor(a)[1] == _si_factor(b)[1]


def si_factor(unit: str) -> float:
    """Multiply a number in ``unit`` by this to get SI (temperatures are not supported)."""
    return _si_factor(unit)[0]


def to_si(value, expected_unit: str, *, default_unit: str | None = None,
          location: Location | None = None, what: str = "value") -> float:
    """Convert a YAML value (number or "number unit" string) to an SI float.

    ``expected_unit`` is the SI unit of the quantity (its dimension is checked);
    a bare number is taken in ``default_unit`` when given, else in SI.
    """
    loc = location or Location()
    if isinstance(value, bool):
        raise UnitError(f"{what}: expected a number with unit '{expected_unit}', got a boolean", location=loc)
    if isinstance(value, (int, float)):
        factor = si_factor(default_unit) if default_unit else 1.0
        return float(value) * factor
    if not isinstance(value, str):
        raise UnitError(f"{what}: expected a number or a string like '210 bar', got {type(value).__name__}",
                        location=loc)
    text = value.strip()
    if _NUMBER.match(text):
        factor = si_factor(default_unit) if default_unit else 1.0
        return float(text) * factor
    m = re.match(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.+)$", text)
    if not m:
        raise UnitError(f"{what}: cannot read '{value}' as a number with a unit",
                        location=loc, hint="write e.g. '210 bar' or '63 mm'")
    number, unit = float(m.group(1)), m.group(2).strip()
    try:
        factor, dim = _si_factor(unit)
    except UnitError as exc:
        raise UnitError(f"{what}: {exc.problems[0].message}", location=loc, hint=exc.problems[0].hint) from None
    want = dimensionality(expected_unit)
    if dim != want:
        raise UnitError(f"{what}: '{value}' has dimension {dim} but {expected_unit} ({want}) is expected",
                        location=loc, hint=f"give the value in a unit convertible to {expected_unit}")
    return number * factor


#: One canonical SI spelling per dimension, as the component specs write them (files and
#: reports never mix "Pa" and "kg/m/s**2" for one quantity); other dimensions use pint's
#: base-unit form.
CANONICAL_SI = ("Pa", "m", "m/s", "m/s^2", "m^2", "m^3", "m^3/s", "N", "N*m", "kg", "kg*m^2", "s", "1/s",
                "N/m", "N*s/m", "W", "m^3/s/Pa^0.5", "m^3/s/Pa", "Pa/s", "1")


@functools.lru_cache(maxsize=1)
def _canonical_by_dimension() -> dict[str, str]:
    return {dimensionality(u): u for u in reversed(CANONICAL_SI)}


@functools.lru_cache(maxsize=4096)
def si_unit(unit: str, fallback: str | None = None) -> str:
    """The canonical SI spelling of ``unit``'s dimension, e.g. "bar" → "Pa", "L/min" → "m^3/s",
    "%" → "1"; pint's base-unit form for dimensions without one; ``fallback`` (default:
    ``unit`` itself) when the unit cannot be parsed."""
    try:
        q = _registry.Quantity(1.0, parse_unit(unit)).to_base_units()
    except Exception:
        return unit if fallback is None else fallback
    known = _canonical_by_dimension().get(str(q.dimensionality))
    if known is not None:
        return known
    return f"{q.units:~}".replace(" ", "") or "1"


def from_si(value: float, unit: str) -> float:
    """Convert an SI float to ``unit`` (for display)."""
    return value / si_factor(unit)
