"""FMI UnitDefinitions: each SI unit with its base-unit exponents, and its display units.

FMI (2.0 §2.2.2, 3.0 §2.4.3) defines a unit by integer exponents of kg, m, s, A, K, mol,
cd and rad plus a factor and offset to them; a display unit converts as
``display = factor · value + offset``. Units with the same dimension share one
definition (named by the shortest spelling seen, e.g. "Pa" rather than "kg/m/s**2").
A unit with a fractional exponent (the valve's m³/s/Pa^0.5) gets no BaseUnit element
(the standard allows none), since FMI exponents are integers.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..units import registry, parse_unit, from_si

_BASE = {"[mass]": "kg", "[length]": "m", "[time]": "s", "[current]": "A",
         "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}


@dataclass
class UnitDef:
    name: str
    exponents: dict[str, int] | None            # None: not expressible with integer exponents
    display: dict[str, tuple[float, float]] = field(default_factory=dict)  # name → (factor, offset)


def _dimension_key(unit: str):
    dims = registry().Quantity(1.0, parse_unit(unit)).to_base_units().dimensionality
    return tuple(sorted((k, float(v)) for k, v in dims.items() if v))


def _exponents(key) -> dict[str, int] | None:
    out = {}
    for dim, v in key:
        if dim not in _BASE or abs(v - round(v)) > 1e-12:
            return None
        out[_BASE[dim]] = int(round(v))
    return out


def _display_conversion(display: str) -> tuple[float, float]:
    offset = from_si(0.0, display)
    return from_si(1.0, display) - offset, offset


class UnitTable:
    """Collects the units of all variables; names are final once every unit was added."""

    def __init__(self) -> None:
        self.by_key: dict[tuple, UnitDef] = {}

    def add(self, unit: str, display: str | None = None):
        """Register ``unit`` (SI) and an optional ``display`` unit; return the key that
        :meth:`resolve` turns into the unit's final name ("" for an unknown or empty unit:
        the variable then carries no unit)."""
        if not unit:
            return ""
        try:
            key = _dimension_key(unit)
        except Exception:
            return ""
        d = self.by_key.get(key)
        label = "1" if not key else unit
        if d is None:
            d = self.by_key[key] = UnitDef(label, _exponents(key))
        elif len(label) < len(d.name):
            d.name = label
        if display and display != unit:
            try:
                if _dimension_key(display) == key:
                    d.display.setdefault(display, _display_conversion(display))
            except Exception:
                pass
        return key

    def resolve(self, key) -> str:
        return self.by_key[key].name if key in self.by_key else ""

    def has_display(self, key, display: str | None) -> bool:
        return bool(display) and key in self.by_key and display in self.by_key[key].display
