"""``hydro validate MACHINE -e V1 [-e V2 …] [--thresholds FILE] [--max-esr dp=10] [--junit FILE]
[--markdown FILE] [--out-dir DIR]`` and ``hydro validate --results run.h5 …``.

Exit 0 when every threshold holds (or none is given), 1 when one fails."""
from __future__ import annotations

import re
from pathlib import Path
from typing import Optional

import typer

from .options import BACKEND, RTOL, SET


def register(app: typer.Typer) -> None:
    @app.command("validate")
    def validate_cmd(
        machine: Optional[Path] = typer.Argument(None, help="machine YAML file (not needed with --results)"),
        experiments: list[Path] = typer.Option(None, "--experiment", "-e",
                                               help="held-out experiment(s): a YAML file (all its experiments; "
                                                    "FILE#NAME picks one) or a recording; repeatable"),
        results: list[Path] = typer.Option(None, "--results", "-r",
                                           help="result .h5 with /outputs and /measured (no re-simulation); repeatable"),
        thresholds: Optional[Path] = typer.Option(None, "--thresholds", "-t",
                                                  help="validation YAML: 'max_esr: {dp: 10}', optionally per experiment"),
        max_esr: list[str] = typer.Option(None, "--max-esr",
                                          help="OUTPUT=PERCENT or EXPERIMENT:OUTPUT=PERCENT; repeatable, beats the file"),
        junit: Optional[Path] = typer.Option(None, "--junit", help="write JUnit XML (one testcase per threshold)"),
        markdown: Optional[Path] = typer.Option(None, "--markdown", help="write a Markdown summary table"),
        out_dir: Optional[Path] = typer.Option(None, "--out-dir", help="write each experiment's HDF5 result here"),
        sets: list[str] = SET,
        rtol: float = RTOL,
        backend: str = BACKEND,
    ) -> None:
        """Score a machine on held-out experiments (ESR, NRMSE, fit %) and gate on thresholds."""
        from .main import run_guarded
        if not experiments and not results:
            raise typer.BadParameter("give --experiment (with MACHINE) or --results", param_hint="--experiment")
        if experiments and machine is None:
            raise typer.BadParameter("--experiment needs the MACHINE argument", param_hint="MACHINE")
        cli_th = _parse_max_esr(max_esr)
        code = run_guarded(_run, machine, experiments or [], results or [], thresholds, cli_th,
                           junit, markdown, out_dir, sets, rtol, backend)
        raise typer.Exit(code)


def _parse_max_esr(items):
    """A malformed --max-esr is a usage error (exit 2)."""
    from ..errors import HydroError
    from ..validate import parse_max_esr
    try:
        return parse_max_esr(items)
    except HydroError as err:
        raise typer.BadParameter(err.problems[0].message + " (e.g. --max-esr dp=10)", param_hint="--max-esr") from None


def _run(machine, experiments, results, thresholds, cli_th, junit, markdown, out_dir, sets, rtol, backend) -> int:
    from ..netlist.yamldoc import write_atomic
    from ..report import ci
    from ..runfiles import write_run
    from ..solve.simulate import SolverOptions
    from ..validate import Thresholds, Verdict, load_thresholds, validate_machine, validate_results

    from ..fileio import guard_output, guard_output_dir
    from .options import BACKENDS, check_choice, check_positive
    check_choice("--backend", backend, BACKENDS)
    check_positive("--rtol", rtol, upper=1.0)
    inputs = (machine, thresholds, *experiments, *results)
    for opt, path in (("--junit", junit), ("--markdown", markdown)):
        if path is not None:
            guard_output(path, inputs, opt)
    if out_dir is not None:
        guard_output_dir(out_dir, (), inputs, "--out-dir")
    th = (load_thresholds(thresholds) if thresholds else Thresholds()).overridden_by(cli_th)
    written: list[Path] = []

    def save(res) -> None:
        if out_dir is not None:
            safe = re.sub(r"[^\w.-]+", "_", res.experiment or "result")
            path = _unique(Path(out_dir) / f"{safe}.h5", written)
            guard_output(path, inputs, "--out-dir")
            write_run(path, res)
            written.append(path)

    verdict = Verdict("")
    if experiments:
        verdict = validate_machine(machine, experiments, th, sets, SolverOptions(rtol=rtol, backend=backend), save)
    if results:
        more = validate_results(results, th)
        verdict.machine = verdict.machine or more.machine
        verdict.rows += more.rows
        verdict.results += more.results
    _print(verdict)
    for path, text in ((junit, ci.junit_xml), (markdown, ci.markdown)):
        if path:
            write_atomic(path, text(verdict))
    for p in written:
        typer.echo(f"wrote {p}")
    return verdict.exit_code


def _unique(path: Path, taken: list[Path]) -> Path:
    stem, k = path.stem, 2
    while path in taken:
        path = path.with_name(f"{stem}_{k}.h5")
        k += 1
    return path


def _print(verdict) -> None:
    from . import tables
    from rich.table import Table
    from ..report.ci import fmt, summary

    console = tables.console()
    table = Table(title=f"Validation of {verdict.machine}", title_justify="left")
    for col, just in (("Experiment", "left"), ("Output", "left"), ("ESR %", "right"), ("NRMSE %", "right"),
                      ("Fit %", "right"), ("Max ESR %", "right"), ("Result", "center")):
        table.add_column(col, justify=just)
    for r in verdict.rows:
        status = {None: "[dim]—[/dim]", True: "[green]pass[/green]", False: "[bold red]FAIL[/bold red]"}[r.passed]
        table.add_row(r.experiment, r.output, fmt(r.esr), fmt(100 * r.nrmse), fmt(r.fit),
                      fmt(r.threshold) if r.threshold is not None else "", status + (f" ({r.note})" if r.note else ""))
    console.print(table)
    for n in verdict.notes:
        console.print(f"[dim]{n}[/dim]")
    console.print(summary(verdict).replace("**FAIL**", "[bold red]FAIL[/bold red]")
                  .replace("**PASS**", "[bold green]PASS[/bold green]"))
