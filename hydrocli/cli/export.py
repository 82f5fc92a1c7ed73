"""``hydro export MACHINE --fmu OUT.fmu [--fmi 2|3] [--kind cs|me|both] [--set …]``."""
from __future__ import annotations

from pathlib import Path

import typer

from .options import SET


def register(app: typer.Typer) -> None:
    @app.command("export")
    def export_cmd(
        machine: Path = typer.Argument(..., help="machine YAML file"),
        fmu: Path = typer.Option(..., "--fmu", help="FMU file to write (.fmu)"),
        fmi: int = typer.Option(2, "--fmi", help="FMI version: 2 or 3 (3: co-simulation only)"),
        kind: str = typer.Option("cs", "--kind", help="cs (co-simulation) | me (model exchange) | both (FMI 2)"),
        sets: list[str] = SET,
        rtol: float = typer.Option(1e-6, "--rtol", help="default tolerance of the FMU's integrator (co-simulation)"),
        stop_time: float = typer.Option(1.0, "--stop-time", help="DefaultExperiment stop time [s]"),
    ) -> None:
        """Export the machine as an FMU (FMI 2.0 CS/ME, FMI 3.0 CS).

        Current parameter values (identified values included) become start values; the FMU
        holds the C sources and a Linux x86-64 binary built now."""
        from .main import run_guarded
        run_guarded(_run, machine, fmu, fmi, kind, sets, rtol, stop_time)


def _run(machine: Path, fmu: Path, fmi: int, kind: str, sets, rtol: float, stop_time: float) -> None:
    from ..api import load_machine
    from ..errors import Problem
    from ..export.fmu import ExportOptions, UsageError

    if fmu.resolve() == machine.resolve():
        raise UsageError(Problem(f"--fmu {fmu} is the machine file itself", hint="write the FMU to another path"))
    if fmu.suffix.lower() != ".fmu":
        raise UsageError(Problem(f"--fmu {fmu}: the file name must end in .fmu", hint="e.g. --fmu eha.fmu"))
    m = load_machine(machine, set=sets)
    for w in m.model.warnings:
        typer.echo(f"warning: {w}", err=True)
    out = m.export_fmu(fmu, ExportOptions(fmi=fmi, kind=kind, rtol=rtol, stop_time=stop_time))
    md = m.model
    typer.echo(f"exported {md.name} as FMI {fmi}.0 {kind.upper()} → {out} ({len(md.params)} parameters, "
               f"{len(md.input_names)} inputs, {len(md.output_names)} outputs, {len(md.state_names)} states)")
