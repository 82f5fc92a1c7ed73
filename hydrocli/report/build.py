"""``build_report(paths, out)``: the multi-page PDF of one or more result files (written
atomically by ``report.document.write_pdf``)."""
from __future__ import annotations

import datetime as _dt
from pathlib import Path

from .data import Loaded, load
from .document import write_pdf
from .pages_params import parameter_pages
from .pages_signals import experiment_pages
from .pages_summary import title_pages


def build_report(paths, out: str | Path, title: str | None = None) -> int:
    """Write the PDF; returns the number of pages."""
    runs = [load(p) for p in paths]          # every file is checked before anything is written
    machines = ", ".join(sorted({r.res.machine for r in runs}))

    def fill(pages) -> None:
        title_pages(pages, runs, title)
        for run in runs:
            experiment_pages(pages, run)
        for run in _distinct_parameter_sets(runs):
            parameter_pages(pages, run)

    return write_pdf(out, fill, f"{title or machines} — {_dt.date.today().isoformat()}",
                     {"Title": title or f"Model report — {machines}", "Creator": "hydrocli (hydro report)",
                      "Subject": ", ".join(r.res.experiment for r in runs)})


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
