"""What ``hydro identify`` prints and writes: the progress bar, the parameter table with
standard errors, the correlation matrix, warnings, the diff of the machine file, the
identified YAML and the HDF5 results. Terminal output lives in cli/, never in the
library (identify/ returns data: FitResult, BatchResult)."""
from __future__ import annotations

import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import typer


class _Progress:
    """Progress in simulations: the bar's total is ``--max-evals``, the cap fit() honours
    (every simulation counts: residuals, Jacobian columns, sensitivity runs). Without a
    terminal, one line on stderr every ``every`` seconds instead of the bar."""

    def __init__(self, prog, task, total: int, terminal: bool, every: float = 5.0):
        self.prog, self.task, self.total, self.terminal, self.every = prog, task, total, terminal, every
        self.offset = 0            # simulations of earlier stages (staged identification)
        self.last_n = 0
        self.label = "identify"
        self._t0 = self._last = time.monotonic()

    def update(self, n: int, cost: float, best: float) -> None:
        done = self.offset + n
        self.last_n = n
        info = f"simulation {done}/{self.total}  cost {cost:.5g}  best {best:.5g}"
        self.prog.update(self.task, completed=done, info=info)
        now = time.monotonic()
        if not self.terminal and now - self._last >= self.every:
            self._last = now
            typer.echo(f"{self.label}: {info}  ({now - self._t0:.0f} s)", err=True)

    def stage(self, text: str) -> None:
        self.offset += self.last_n
        self.last_n = 0
        self.label = text
        self.prog.update(self.task, description=text)


@contextmanager
def progress_bar(total: int, every: float = 5.0):
    """A rich progress bar on stderr (simulations of ``total``, cost, best cost); without a
    terminal a plain progress line every ``every`` seconds."""
    from . import tables
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
    console = tables.console(stderr=True)
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.fields[info]}"),
                  TimeElapsedColumn(), console=console, transient=False, disable=not console.is_terminal) as prog:
        task = prog.add_task("identify", total=total, info="")
        yield _Progress(prog, task, total, console.is_terminal, every)


def _fmt(v: float) -> str:
    return f"{v:.5g}" if np.isfinite(v) else "-"


def print_fit(res) -> None:
    typer.echo(f"{res.method}: {res.message} ({res.n_evals} simulations, {res.seconds:.1f} s, "
               f"Jacobian from {res.gradient}"
               + (", interrupted" if res.interrupted else "") + ")")
    typer.echo(f"cost {res.cost_initial:.6g} → {res.cost:.6g} over {res.n_residuals} residuals")
    if res.n_effective and res.n_effective < res.n_residuals:
        typer.echo(f"standard errors allow for correlated residuals: {res.n_effective:.0f} independent of "
                   f"{res.n_residuals} (× {np.sqrt(res.n_residuals / res.n_effective):.2g} on the white-noise values)")
    unc = res.uncertainty
    rows = [["parameter", "initial", "estimate", "std error", "rel %"]
            + (["95 % interval (bootstrap)"] if unc is not None else []) + ["lower", "upper"]]
    for i, n in enumerate(res.names):
        se, v = res.stderr[i], res.estimates[i]
        rel = 100 * se / abs(v) if np.isfinite(se) and v != 0 else np.nan
        ci = [f"[{_fmt(unc.ci_lower[i])}, {_fmt(unc.ci_upper[i])}]"] if unc is not None else []
        rows.append([n, _fmt(res.initial[i]), _fmt(v), _fmt(se), _fmt(rel)] + ci
                    + [_fmt(res.lower[i]), _fmt(res.upper[i])])
    print_table(rows)
    k = len(res.names)
    if k > 1 and np.isfinite(res.correlation).any():
        typer.echo("correlation matrix:")
        short = [f"p{i + 1}" for i in range(k)]
        lines = ["      " + " ".join(f"{s:>6}" for s in short)]
        for i in range(k):
            lines.append(f"{short[i]:>5} " + " ".join(f"{res.correlation[i, j]:+6.2f}" if np.isfinite(res.correlation[i, j])
                                                     else f"{'-':>6}" for j in range(k)) + f"  {res.names[i]}")
        typer.echo("\n".join(lines))
    hist = res.cost_history
    if hist:
        marks = sorted({0, len(hist) // 4, len(hist) // 2, 3 * len(hist) // 4, len(hist) - 1})
        typer.echo("best cost by evaluation: " + ", ".join(f"#{i + 1}: {hist[i]:.5g}" for i in marks))
    if unc is not None:
        print_assessment(unc)
    for w in res.warnings:
        typer.echo(f"warning: {w}", err=True)


def print_assessment(unc) -> None:
    """Identifiability and the fixed parameters the estimates depend on."""
    if unc.identifiability:
        typer.echo("identifiability:")
        for m in unc.identifiability:
            typer.echo(f"  {m}")
    if unc.fixed_names:
        if unc.fixed_effects:
            typer.echo("fixed parameters the estimates are sensitive to:")
            for e in unc.fixed_effects:
                typer.echo(f"  {e.message()}")
        else:
            typer.echo(f"fixed parameters: a 10 % error in any of the {len(unc.fixed_names)} fixed parameters moves "
                       f"no estimate by more than two standard errors")
    if unc.window_messages:
        typer.echo("model error (the estimates differ between parts of the recording):")
        for m in unc.window_messages:
            typer.echo(f"  {m}")


def print_table(rows: list[list]) -> None:
    widths = [max(len(str(r[j])) for r in rows) for j in range(len(rows[0]))]
    for i, r in enumerate(rows):
        typer.echo("  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip())
        if i == 0:
            typer.echo("  ".join("-" * w for w in widths))


def write_outputs(net, model, exps, p, names, identify: dict, out: Path, results: Path | None, opts) -> None:
    """Identified YAML (+ printed diff) and, with ``results``, one HDF5 per experiment."""
    from ..metrics import esr
    from ..netlist.writer import diff_text, identified_netlist, write_back
    from ..runfiles import write_run
    from ..runner import simulate_experiment

    values = {n: float(p[model.param_index(n)]) for n in names}
    new_text = write_back(net, values, out)
    typer.echo(diff_text(Path(net.file).read_text(encoding="utf-8"), new_text, Path(net.file).name)
               or "(no change to the machine file)")
    typer.echo(f"identified machine → {out}")
    for exp in exps:
        res = simulate_experiment(model, exp, p=p, opts=opts)
        scores = ", ".join(f"{o} {esr(exp.measured[o], res.outputs[o], exp.mask.get(o)):.3g} %"
                           for o in exp.measured)
        typer.echo(f"ESR on {exp.name}: {scores}")
        if results:
            res.identify = identify
            res.netlist_sha, res.netlist_text = identified_netlist(new_text, out)
            path = results if len(exps) == 1 else results.with_name(f"{results.stem}_{exp.name}{results.suffix}")
            write_run(path, res)
            typer.echo(f"result → {path}")
