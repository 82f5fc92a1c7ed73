"""``hydro report RESULT.h5 [RESULT2.h5 …] --out report.pdf [--title …]``."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer


def register(app: typer.Typer) -> None:
    @app.command("report")
    def report_cmd(
        results: list[Path] = typer.Argument(..., help="result .h5 files (simulate / identify / validate --out-dir)"),
        out: Path = typer.Option(Path("report.pdf"), "--out", "-o", help="PDF file to write"),
        title: Optional[str] = typer.Option(None, "--title", help="title of the report (default: the machine)"),
    ) -> None:
        """Write a multi-page PDF: summary, measured vs simulated, worst windows, parameters."""
        from .main import run_guarded
        run_guarded(_run, results, out, title)


def _run(results, out, title) -> None:
    from ..fileio import guard_output
    from ..report.build import build_report
    guard_output(out, results)
    n = build_report(results, out, title)
    typer.echo(f"wrote {out} ({n} pages from {len(results)} result file{'s' if len(results) > 1 else ''})")
