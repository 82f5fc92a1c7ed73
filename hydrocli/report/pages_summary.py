"""The title page: machine, experiments, netlist sha, dates, and the ESR table of every run."""
from __future__ import annotations

import datetime as _dt
import textwrap

from . import style
from .data import Loaded, display

ROWS_MORE = 26           # table rows on continuation pages


def esr_colour(esr: float) -> str | None:
    if esr != esr:       # NaN
        return None
    return "#e3f4e1" if esr < 1.0 else "#fde2e1" if esr > 10.0 else None


def metric_rows(runs: list[Loaded]) -> tuple[list[list[str]], dict[int, str]]:
    rows, colours = [], {}
    for run in runs:
        for name, m in run.metrics().items():
            _, unit = display(run.res, "outputs", name, run.res.outputs[name][:1])
            c = esr_colour(m["esr"])
            if c:
                colours[len(rows)] = c
            rows.append([run.res.experiment, name, unit, f"{m['esr']:.3g}", f"{100 * m['nrmse']:.3g}", f"{m['fit']:.3g}"])
    return rows, colours


def title_pages(out, runs: list[Loaded], title: str | None) -> None:
    machines = sorted({r.res.machine for r in runs})
    shas = sorted({r.res.netlist_sha for r in runs})
    now = _dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    fig = style.page(title or f"Model report — {', '.join(machines)}",
                     f"hydrocli {runs[0].meta.get('tool_version', '')}, generated {now}")
    info = [("Machine", ", ".join(machines)),
            ("Netlist sha256", "\n".join(shas) + ("  (results come from different netlists!)" if len(shas) > 1 else "")),
            ("Experiments", ", ".join(r.res.experiment for r in runs)),
            ("Parameters", _param_source(runs)),
            ("Runs", "\n".join(f"{r.res.experiment}: {r.path}  ({r.meta.get('timestamp', '?')})" for r in runs[:6])
             + (f"\n… and {len(runs) - 6} more" if len(runs) > 6 else ""))]
    y = 0.86
    info = [(k, "\n".join(textwrap.fill(line, 110) for line in v.split("\n"))) for k, v in info]
    for key, value in info:
        fig.text(0.04, y, key, weight="bold", va="top")
        fig.text(0.20, y, value, va="top", family="monospace" if key == "Netlist sha256" else None)
        y -= 0.035 + 0.022 * value.count("\n")
    rows, colours = metric_rows(runs)
    header = ["Experiment", "Output", "Unit", "ESR %", "NRMSE %", "Fit %"]
    widths = [0.28, 0.16, 0.12, 0.14, 0.15, 0.15]
    top = y - 0.03
    fig.text(0.04, top, "Fit on each run (ESR = 100·Var(y − ŷ)/Var(y); green < 1 %, red > 10 %)", weight="bold", va="top")
    ax = fig.add_axes([0.04, 0.06, 0.62, max(top - 0.1, 0.1)])
    first = style.rows_fitting(top - 0.1)
    style.table(ax, header, rows[:first], widths, {i: c for i, c in colours.items() if i < first}, left=3)
    out.add(fig)
    for start in range(first, len(rows), ROWS_MORE):
        fig = style.page("Fit on each run (continued)")
        ax = fig.add_axes([0.04, 0.06, 0.62, 0.84])
        part = {i - start: c for i, c in colours.items() if start <= i < start + ROWS_MORE}
        style.table(ax, header, rows[start:start + ROWS_MORE], widths, part, left=3)
        out.add(fig)


def _param_source(runs: list[Loaded]) -> str:
    ident = [r for r in runs if r.res.identify]
    if not ident:
        return "nominal values from the machine file (no /identify in the results)"
    d = ident[0].res.identify
    return f"identified ({d.get('method', '?')}, {len(d.get('names', []))} free parameters, cost " \
           f"{float(d.get('cost_initial', float('nan'))):.3g} → {float(d.get('cost', float('nan'))):.3g})"
