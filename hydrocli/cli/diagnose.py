"""``hydro diagnose MACHINE --train E1 [--train E2 …] --validate V1 … --out DIR``."""
from __future__ import annotations

from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    @app.command("diagnose")
    def diagnose_cmd(
        machine: Path = typer.Argument(..., help="machine YAML file"),
        train: list[Path] = typer.Option(..., "--train", help="training experiment(s): a YAML file (all its "
                                         "experiments; FILE#NAME picks one) or a recording; repeatable"),
        validate: list[Path] = typer.Option(..., "--validate", help="held-out experiment(s), as --train; repeatable"),
        out: Path = typer.Option(Path("diagnosis"), "--out", "-o", help="directory for diagnosis.json, "
                                 "augmented.yaml and report.pdf"),
        max_effects: int = typer.Option(3, "--max-effects", min=0, help="effects to add at most"),
        jobs: int = typer.Option(2, "--jobs", "-j", min=1, help="worker processes for candidate fits"),
        top: int = typer.Option(3, "--top", min=1, help="effects re-identified per round (their best-screening forms)"),
        no_pdf: bool = typer.Option(False, "--no-pdf", help="skip the PDF report"),
        scheduler: str = typer.Option(None, "--scheduler", help="Dask scheduler address (tcp://HOST:PORT) for "
                                      "the candidate fits; default: a local process pool of --jobs workers"),
        no_nuisance: bool = typer.Option(False, "--no-nuisance", help="keep the valves' spool dynamics fixed in "
                                         "the base fit"),
        only: list[str] = typer.Option(None, "--only", help="try only this effect (repeatable): e.g. the two a "
                                       "proposed experiment is to decide between"),
    ) -> None:
        """Locate the model/recording mismatch, name the missing physics, add it, show the fit improve."""
        from .main import run_guarded
        run_guarded(_run, machine, train, validate, out, max_effects, jobs, top, no_pdf, scheduler, no_nuisance, only)


def _run(machine, train, validate, out, max_effects, jobs, top, no_pdf, scheduler=None, no_nuisance=False,
         only=None) -> None:
    from ..diagnose import Settings, diagnose
    from ..diagnose.candidates.base import VOCABULARY
    from ..errors import UsageError
    from ..suggest import suggest
    for e in only or ():
        if e not in VOCABULARY:
            raise UsageError(f"--only {e}: not an effect of the diagnosis vocabulary" + suggest(e, VOCABULARY))
    from ..diagnose.summary import console_summary, write_augmented, write_json, write_proposals
    from ..fileio import guard_output_dir
    files = ("diagnosis.json", "augmented.yaml") + (() if no_pdf else ("report.pdf",))
    guard_output_dir(out, files, (machine, *train, *validate))   # before the long diagnosis

    from ..progress import Heartbeat
    with Heartbeat(lambda m: typer.echo(m, err=True)) as progress:   # a status line every 5 s
        diag = diagnose(machine, train, validate, Settings(max_effects=max_effects, jobs=jobs, top=top,
                                                             scheduler=scheduler, nuisance=not no_nuisance,
                                                             only=tuple(only or ())),
                        progress=progress)
    guard_output_dir(out, files)            # every input is known now
    out.mkdir(parents=True, exist_ok=True)
    proposals = write_proposals(diag, out)
    write_json(diag, out / "diagnosis.json")
    write_augmented(diag, out / "augmented.yaml")
    if not no_pdf:
        from ..report.diagnosis import write_report
        write_report(diag, out / "report.pdf")
    typer.echo(console_summary(diag))
    typer.echo(f"→ {out}/diagnosis.json, {out}/augmented.yaml" + ("" if no_pdf else f", {out}/report.pdf")
               + "".join(f", {p}" for p in proposals))
