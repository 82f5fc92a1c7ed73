"""Recordings: a time column and named signal columns, read from CSV (``name[unit]``
headers), HDF5 or MATLAB ``.mat``; values converted to SI once, here."""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DataError, Location, Problem
from ..units import si_factor

_HEADER = re.compile(r"^\s*([^\[\]]+?)\s*(?:\[([^\]]*)\])?\s*$")


@dataclass
class Recording:
    file: str
    t: np.ndarray
    columns: dict[str, np.ndarray]              # SI values
    units: dict[str, str] = field(default_factory=dict)  # unit as written in the file

    def column(self, name: str) -> np.ndarray:
        return self.columns[name]


def read_csv(path: str | Path, time_column: str | None = None) -> Recording:
    """CSV with a header row ``t[s],u[%],P1[bar],…``; the first column is time unless named."""
    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            reader = csv.reader(fh)
            header = next(reader, None)
            rows = list(reader)
    except FileNotFoundError:
        raise DataError(Problem(f"recording not found: {path}", Location(str(path)), "check the path")) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(Problem(f"cannot read {path}: {exc}", Location(str(path)))) from None
    if not header:
        raise DataError(Problem("empty CSV file: a header row 'name[unit],…' is required", Location(str(path), 1, 1)))
    names, units = [], []
    for j, cell in enumerate(header):
        m = _HEADER.match(cell)
        if not m or not m.group(1):
            raise DataError(Problem(f"bad header cell '{cell}'", Location(str(path), 1, j + 1),
                                    "write headers as name[unit], e.g. P1[bar]"))
        names.append(m.group(1).strip())
        units.append((m.group(2) or "").strip() or "1")
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise DataError(Problem(f"duplicate column(s) {sorted(dup)}", Location(str(path), 1, 1)))
    data = np.empty((len(rows), len(names)))
    for i, row in enumerate(rows):
        if len(row) != len(names):
            raise DataError(Problem(f"row has {len(row)} values but the header has {len(names)} columns",
                                    Location(str(path), i + 2, 1), "every row needs one value per column"))
        for j, cell in enumerate(row):
            try:
                data[i, j] = float(cell)
            except ValueError:
                raise DataError(Problem(f"'{cell}' in column '{names[j]}' is not a number",
                                        Location(str(path), i + 2, j + 1))) from None
    factors = {}
    for n, u in zip(names, units):
        try:
            factors[n] = si_factor(u)
        except Exception as exc:
            raise DataError(Problem(f"column '{n}': unknown unit '{u}'", Location(str(path), 1, names.index(n) + 1),
                                    "use units such as s, bar, Pa, mm, m/s, %, N")) from None
    tname = time_column or names[0]
    if tname not in names:
        raise DataError(Problem(f"time column '{tname}' not found (columns: {', '.join(names)})",
                                Location(str(path), 1, 1)))
    cols = {n: data[:, j] * factors[n] for j, n in enumerate(names)}
    rec = Recording(str(path), cols.pop(tname), cols, dict(zip(names, units)))
    check_recording(rec, row_offset=2)
    return rec


def check_recording(rec: Recording, row_offset: int = 1) -> None:
    """NaN, infinities and non-monotonic time are data errors with the row."""
    t = rec.t
    if t.size < 2:
        raise DataError(Problem("a recording needs at least two samples", Location(rec.file)))
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise DataError(Problem(f"time is not a finite number at row {bad[0] + row_offset}",
                                Location(rec.file, int(bad[0] + row_offset))))
    nonmono = np.flatnonzero(np.diff(t) <= 0)
    if nonmono.size:
        r = int(nonmono[0] + 1 + row_offset)
        raise DataError(Problem(f"time is not strictly increasing at row {r} (t = {t[nonmono[0] + 1]:g} s after "
                                f"{t[nonmono[0]]:g} s)", Location(rec.file, r),
                                "sort the samples by time and remove duplicates"))
    for name, col in rec.columns.items():
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise DataError(Problem(f"column '{name}' has a non-finite value (NaN/inf) at row {bad[0] + row_offset}",
                                    Location(rec.file, int(bad[0] + row_offset)),
                                    "remove or interpolate the sample, or mask it in the experiment file"))
