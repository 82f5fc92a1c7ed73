"""Recordings: a time column and named signal columns, read from CSV (``name[unit]``
headers), HDF5 or MATLAB ``.mat``; values converted to SI once, here.

* CSV: a header row ``t[s],u[%],P1[bar],…``; the unit in brackets converts the column to SI.
* HDF5: every 1-D numeric dataset (any depth) is a column named by its path without the
  leading slash (``daq/p1``); a ``unit`` attribute, when present, converts it to SI.
* MATLAB ``.mat`` (v5, ``scipy.io.loadmat``): every numeric vector (N×1 or 1×N) of the
  recording's length is a column; .mat files carry no units, so values are taken as written
  (give ``unit:``/``scale:`` in the experiment file).
The time column is ``t`` or ``time`` unless named (for CSV, the first column when neither is
present: a recording whose columns come in another order still reads its clock).
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..fileio import note_input
from .unit_check import check_time_unit
from ..errors import DataError, Location, Problem
from ..units import si_factor

_HEADER = re.compile(r"^\s*([^\[\]]+?)\s*(?:\[([^\]]*)\])?\s*$")


@dataclass
class Recording:
    file: str
    t: np.ndarray
    columns: dict[str, np.ndarray]              # SI values
    units: dict[str, str] = field(default_factory=dict)  # unit as written in the file
    other_lengths: dict[str, int] = field(default_factory=dict)  # vectors of another length (not columns)
    first_row: int = 1           # file row of sample 0 (CSV: 2, after the header)

    def column(self, name: str) -> np.ndarray:
        return self.columns[name]


def read_csv(path: str | Path, time_column: str | None = None, check_columns: bool = True) -> Recording:
    """CSV with a header row ``t[s],u[%],P1[bar],…``; the first column is time unless named."""
    path = Path(path)
    note_input(path)
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
        except Exception:
            raise DataError(Problem(f"column '{n}': unknown unit '{u}'", Location(str(path), 1, names.index(n) + 1),
                                    "use units such as s, bar, Pa, mm, m/s, %, N")) from None
    tname = time_column or _conventional_time(names, CLOCK_NAMES) or names[0]
    if tname not in names:
        raise DataError(Problem(f"time column '{tname}' not found (columns: {', '.join(names)})",
                                Location(str(path), 1, 1)))
    cols = {n: data[:, j] * factors[n] for j, n in enumerate(names)}
    rec = Recording(str(path), cols.pop(tname), cols, dict(zip(names, units)), first_row=2)
    check_time_unit(rec, tname)
    check_recording(rec, row_offset=2, check_columns=check_columns)
    return rec


def read_recording(path: str | Path, time_column: str | None = None, check_columns: bool = True) -> Recording:
    """Dispatch on the suffix: .csv, .h5/.hdf5, .mat."""
    path = Path(path)
    if not path.exists():
        raise DataError(Problem(f"recording not found: {path}", Location(str(path)),
                                "check the path (relative paths in an experiment file are read from "
                                "the experiment file's folder)"))
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return read_csv(path, time_column, check_columns)
    if suffix in (".h5", ".hdf5"):
        return read_hdf5(path, time_column, check_columns)
    if suffix == ".mat":
        return read_mat(path, time_column, check_columns)
    raise DataError(Problem(f"unknown recording format '{suffix}'", Location(str(path)),
                            "use a .csv (name[unit] headers), .h5/.hdf5 or MATLAB v5 .mat file"))


def read_hdf5(path: str | Path, time_column: str | None = None, check_columns: bool = True) -> Recording:
    import h5py

    path = Path(path)
    cols: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    try:
        with h5py.File(path, "r") as h:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fiu" and obj.ndim >= 1 \
                        and max(obj.shape) == obj.size:
                    cols[name] = np.asarray(obj[()], dtype=float).ravel()
                    u = obj.attrs.get("unit", "1")
                    units[name] = u.decode() if isinstance(u, bytes) else str(u)
            h.visititems(visit)
    except OSError as exc:
        raise DataError(Problem(f"cannot read HDF5 file {path}: {exc}", Location(str(path)),
                                "give an HDF5 file with one 1-D dataset per signal")) from None
    for name in list(cols):
        try:
            cols[name] = cols[name] * si_factor(units[name])
        except Exception:
            raise DataError(Problem(f"dataset '{name}': unknown unit '{units[name]}'", Location(str(path), path=name),
                                    "set the dataset's 'unit' attribute to e.g. s, bar, mm")) from None
    return _assemble(str(path), cols, units, time_column, check_columns)


def read_mat(path: str | Path, time_column: str | None = None, check_columns: bool = True) -> Recording:
    from scipy import io as sio

    path = Path(path)
    try:
        raw = sio.loadmat(str(path))
    except NotImplementedError:
        raise DataError(Problem(f"{path} is a MATLAB v7.3 file (HDF5 inside)", Location(str(path)),
                                "save it with save(..., '-v7') or read it as .h5")) from None
    except Exception as exc:
        raise DataError(Problem(f"cannot read MATLAB file {path}: {exc}", Location(str(path)),
                                "give a MATLAB v5 .mat file with column vectors")) from None
    cols = {}
    for k, v in raw.items():
        if k.startswith("__") or not isinstance(v, np.ndarray) or v.dtype.kind not in "fiu":
            continue
        if v.ndim == 2 and min(v.shape) == 1 and v.size > 1:
            cols[k] = v.astype(float).ravel()
    return _assemble(str(path), cols, {k: "1" for k in cols}, time_column, check_columns)


#: names a recording's clock conventionally has, in order of preference. A CSV falls back to
#: its first column, so a bare ``T`` (a tank pressure, a temperature) is not guessed there;
#: HDF5 and .mat recordings, with no column order to fall back on, also take ``T``
CLOCK_NAMES = ("t", "time", "Time")
CLOCK_NAMES_UNORDERED = CLOCK_NAMES + ("T",)


def _conventional_time(names, candidates: tuple[str, ...]) -> str | None:
    """The first of ``candidates`` among the recording's column names, if any."""
    return next((n for n in candidates if n in names), None)


def _assemble(file: str, cols: dict, units: dict, time_column: str | None, check_columns: bool) -> Recording:
    """Pick the time column, keep the columns of the recording's length."""
    tname = time_column or _conventional_time(cols, CLOCK_NAMES_UNORDERED)
    if tname is None or tname not in cols:
        raise DataError(Problem(f"time column '{time_column or 't'}' not found (signals: {', '.join(cols) or 'none'})",
                                Location(file), "name the time column with 'time:' in the experiment file"))
    note_input(file)
    t = cols.pop(tname)
    other = {k: v.size for k, v in cols.items() if v.size != t.size}
    cols = {k: v for k, v in cols.items() if v.size == t.size}
    rec = Recording(file, t, cols, units, other)
    check_time_unit(rec, tname)
    check_recording(rec, check_columns=check_columns)
    return rec


def check_recording(rec: Recording, row_offset: int = 1, check_columns: bool = True) -> None:
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
    for name, col in (rec.columns.items() if check_columns else ()):
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise DataError(Problem(f"column '{name}' has a non-finite value (NaN/inf) at row {bad[0] + row_offset}",
                                    Location(rec.file, int(bad[0] + row_offset)),
                                    "remove or interpolate the sample, or mask it in the experiment file"))
