"""Recording columns → machine signals in SI: ``{column, unit, scale, offset}`` or a designed
signal (used by the experiment-file builder, see experiment_file.py).

SI value = scale · (raw value in ``unit``) + offset. ``unit`` is the unit of the column as
written (it overrides a CSV header or HDF5 ``unit`` attribute; .mat columns have none); a
``scale`` string carries its own unit (``"0.02 m/V"``, ``"10 %/V"``) and is checked against
the signal's dimension; a bare scale is a plain SI multiplier; ``offset`` is a value with
the signal's unit (``"-1 mm"``) or an SI number.
"""
from __future__ import annotations

import numpy as np

from ..errors import Location
from ..netlist import yamldoc as Y
from ..units import parse_unit, registry, si_factor, to_si
from .signals import is_signal, signal
from .unit_check import check_column


class ChannelsMixin:
    """Needs ``self.loc(*keys)``, ``self.fail(msg, loc, hint)``."""

    def channel(self, rec, t, section, name, spec, unit, nan_ok) -> np.ndarray:
        """One signal in SI on the recording's time grid."""
        if is_signal(spec):
            return signal(spec, unit, self.loc(section, name))(t)
        col = spec.get("column", name) if Y.is_map(spec) else spec
        if not isinstance(col, str):
            self.fail(f"{section}.{name}: expected a column name, a mapping {{column, unit, scale, offset}} or a signal",
                      self.loc(section, name))
        loc = self.loc(section, name)
        if rec is None:
            self.fail(f"{section}.{name}: column '{col}' but the experiment has no 'data:' recording", loc,
                      "add 'data: FILE' or use a designed signal")
        if col not in rec.columns:
            if col in rec.other_lengths:
                self.fail(f"column '{col}' has {rec.other_lengths[col]} samples but the time column has {rec.t.size}",
                          loc, "every signal must have one sample per time sample")
            from ..suggest import suggest
            self.fail(f"unknown column '{col}' in {rec.file}{suggest(col, list(rec.columns))}", loc,
                      f"columns: {', '.join(rec.columns)}")
        check_column(rec, col, unit, spec, loc, f"{section}.{name}")
        y = rec.columns[col]
        bad = np.flatnonzero(~np.isfinite(y))
        if bad.size and not nan_ok:
            row = int(bad[0]) + rec.first_row
            self.fail(f"column '{col}' has a non-finite value (NaN/inf) at row {row} of {rec.file}",
                      Location(rec.file, row, path=col),
                      f"remove or interpolate it, or add 'mask: {{{name}: {{nan: ignore}}}}'" if section != "inputs"
                      else "inputs must be finite everywhere: repair the recording")
        if Y.is_map(spec):
            y = self.convert(y, spec, rec.units.get(col, "1"), unit, section, name)
        return y.astype(float)

    def convert(self, y, spec, file_unit, target_unit, section, name):
        loc = self.loc(section, name)
        raw_unit = str(spec.get("unit") or file_unit or "1")
        if spec.get("unit") is not None:
            y = y * si_factor(raw_unit) / si_factor(file_unit or "1")
        scale = spec.get("scale", 1.0)
        s_unit = "1"
        if isinstance(scale, str):
            parts = scale.strip().split(None, 1)
            try:
                number = float(parts[0])
            except ValueError:
                self.fail(f"{section}.{name}.scale: cannot read '{scale}'", loc, "write e.g. '0.02 m/V' or 0.02")
            s_unit = parts[1] if len(parts) > 1 else "1"
            scale = number * si_factor(s_unit)
            self.check_dimension(raw_unit, s_unit, target_unit, loc, f"{section}.{name}")
        y = y * float(scale)
        if spec.get("offset") is not None:
            y = y + to_si(spec["offset"], target_unit, location=loc, what=f"{section}.{name}.offset")
        return y

    def check_dimension(self, raw_unit, s_unit, target_unit, loc, what):
        reg = registry()
        try:
            got = (reg.Quantity(1.0, parse_unit(raw_unit)) * reg.Quantity(1.0, parse_unit(s_unit))).dimensionality
            want = reg.Quantity(1.0, parse_unit(target_unit)).dimensionality
        except Exception:
            return
        if raw_unit not in ("1", "") and got != want:
            self.fail(f"{what}: column unit '{raw_unit}' × scale unit '{s_unit}' gives {got}, but the output is in "
                      f"{target_unit} ({want})", loc, "fix the scale's unit, e.g. '0.02 m/V' for a position in volts")

