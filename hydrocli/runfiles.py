"""Run files: the one place a simulated run is written (format picked by the suffix) and
read back with located errors.

``write_run(path, res)``: ``.csv`` → one CSV table in SI (``t[s]``, the inputs, outputs and
states, headers ``name[unit]`` as ``experiments.recording.read_csv`` reads them back); any
other suffix (``.h5``, ``.hdf5``, …) → the HDF5 layout of ../shared/DESIGN.md
(``results.write_result``). Both write through a temporary file and a rename. A new output
format is one writer function and one entry in :data:`WRITERS`.
``load_run(path)``: ``results.read_result`` with a missing or malformed file turned into a
located DataError (exit 3).
"""
from __future__ import annotations

import csv
from pathlib import Path
from typing import Callable

from .errors import DataError, HydroError, Location, Problem
from .fileio import atomic_path
from .results import RunResult, read_result, write_result


def _write_csv(path: str | Path, res: RunResult) -> None:
    cols = [("t", "s", res.t)]
    for group, values in (("inputs", res.inputs), ("outputs", res.outputs), ("states", res.states)):
        cols += [(n, res.units.get(f"{group}/{n}", "") or "1", v) for n, v in values.items()]
    seen: set[str] = set()
    cols = [c for c in cols if not (c[0] in seen or seen.add(c[0]))]   # an output named like a state: once
    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow([f"{n}[{u}]" for n, u, _ in cols])
            for i in range(res.t.size):
                w.writerow([repr(float(v[i])) for _, _, v in cols])


#: suffix → writer; anything else is HDF5
WRITERS: dict[str, Callable[[str | Path, RunResult], None]] = {".csv": _write_csv}


def write_run(path: str | Path, res: RunResult) -> None:
    """Write one run; the format follows the suffix (default HDF5). Never a half file."""
    WRITERS.get(Path(path).suffix.lower(), write_result)(path, res)


def load_run(path: str | Path) -> RunResult:
    """read_result, with any malformed-file surprise turned into a located DataError."""
    path = Path(path)
    if not path.is_file():
        raise DataError(Problem(f"result file not found: {path}", Location(str(path)), "check the path"))
    try:
        return read_result(path)
    except HydroError:
        raise
    except Exception as exc:  # missing datasets, wrong dtypes…
        raise DataError(Problem(f"{path} is not a readable hydrocli result file ({exc.__class__.__name__}: {exc})",
                                Location(str(path)),
                                "give an HDF5 file written by 'hydro simulate', 'identify' or 'validate --out-dir'")) from None
