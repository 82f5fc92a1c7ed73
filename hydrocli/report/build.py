"""``build_report(paths, out)``: the multi-page PDF of one or more result files, written to a
temporary file in the target folder and renamed (a crash never leaves a half PDF)."""
from __future__ import annotations

import datetime as _dt
from pathlib import Path

from ..errors import DataError, Location, Problem
from . import style
from .data import Loaded, load
from .pages_params import parameter_pages
from .pages_signals import experiment_pages
from .pages_summary import title_pages
from ..fileio import atomic_path


def build_report(paths, out: str | Path, title: str | None = None) -> int:
    """Write the PDF; returns the number of pages."""
    runs = [load(p) for p in paths]          # every file is checked before anything is written
    out = Path(out)
    try:
        with atomic_path(out, suffix=".tmp.pdf") as tmp:
            n = _write(tmp, runs, title)
    except OSError as exc:
        raise DataError(Problem(f"cannot write the report {out}: {exc.strerror or exc}", Location(str(out)),
                                "choose a writable folder with --out")) from None
    return n


def _write(path: str, runs: list[Loaded], title: str | None) -> int:
    from matplotlib.backends.backend_pdf import PdfPages
    import matplotlib.pyplot as plt

    machines = ", ".join(sorted({r.res.machine for r in runs}))
    with plt.rc_context(style.RC), PdfPages(path) as pdf:
        pages = style.Pages(pdf, f"{title or machines} — {_dt.date.today().isoformat()}")
        title_pages(pages, runs, title)
        for run in runs:
            experiment_pages(pages, run)
        for run in _distinct_parameter_sets(runs):
            parameter_pages(pages, run)
        info = pdf.infodict()
        info.update({"Title": title or f"Model report — {machines}", "Creator": "hydrocli (hydro report)",
                     "Subject": ", ".join(r.res.experiment for r in runs)})
        return pages.count


def _distinct_parameter_sets(runs: list[Loaded]) -> list[Loaded]:
    """One parameter section per machine and distinct identification (results of one
    identification share it); nominal parameters only for a machine without any."""
    seen, out = set(), []
    identified = {r.res.machine for r in runs if r.res.identify}
    for run in runs:
        d = run.res.identify
        if d is None and run.res.machine in identified:
            continue
        key = (run.res.machine, tuple(map(str, d.get("names", []))), tuple(map(float, d.get("estimates", [])))) \
            if d else (run.res.machine, tuple(run.res.parameters))
        if key not in seen:
            seen.add(key)
            out.append(run)
    return out
