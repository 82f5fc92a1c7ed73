"""``hydro schema [--out FILE]``: the JSON Schema of machine files (from the component specs)."""
from __future__ import annotations

import json
from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    @app.command("schema")
    def schema_cmd(out: Path = typer.Option(None, "--out", "-o", help="write the schema to this file")) -> None:
        """Print or write the JSON Schema that editors use to complete and check machine files."""
        from .main import run_guarded
        run_guarded(write_schema, out)


def write_schema(out: Path | None) -> None:
    from ..netlist.yamldoc import write_atomic
    from ..schema import machine_schema
    text = json.dumps(machine_schema(), indent=2) + "\n"
    if out is None:
        typer.echo(text, nl=False)
        return
    write_atomic(out, text)     # the output guard refuses directories and devices
    typer.echo(f"wrote {out}", err=True)
