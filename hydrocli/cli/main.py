"""The ``hydro`` command: one typer app; each command lives in its own module with a
``register(app)`` function. This is the one place that turns HydroError subclasses into
exit codes (DESIGN.md): 0 ok, 1 validation threshold failed, 2 usage, 3 invalid input,
4 solver or identification failure."""
from __future__ import annotations

import importlib
import sys

import typer

from ..errors import HydroError

COMMANDS = ("check", "components", "schema", "simulate", "identify", "validate", "report", "diagnose", "export", "bench")

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  help="Model, simulate, identify, validate and diagnose hydraulic machines.")
_state = {"debug": False}


def _print_version(value: bool) -> None:
    if value:
        from ..version import __version__
        typer.echo(f"hydrocli {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(debug: bool = typer.Option(False, "--debug", help="show tracebacks on errors"),
          version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                       help="print the version and exit")) -> None:
    _state["debug"] = debug


for _name in COMMANDS:
    try:
        _mod = importlib.import_module(f"hydrocli.cli.{_name}")
    except ModuleNotFoundError as _exc:  # a command not written yet must not break the others
        if _exc.name != f"hydrocli.cli.{_name}":
            raise
        continue
    _mod.register(app)


def fail(err: HydroError) -> None:
    """Print a located error to stderr and exit with its code."""
    if _state["debug"]:
        raise err
    typer.echo(err.render(), err=True)
    raise typer.Exit(err.exit_code)


def run_guarded(fn, *args, **kwargs):
    """Call ``fn``; HydroErrors become messages and exit codes, Ctrl-C exits 130,
    anything unexpected is reported in one line (traceback only with --debug)."""
    try:
        return fn(*args, **kwargs)
    except HydroError as err:
        fail(err)
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        raise typer.Exit(130)
    except typer.Exit:
        raise
    except Exception as exc:  # a bug: say so plainly
        if _state["debug"]:
            raise
        typer.echo(f"internal error: {exc.__class__.__name__}: {exc} (run with --debug for the traceback, "
                   "and please report it)", err=True)
        raise typer.Exit(4)


def main() -> None:  # pragma: no cover
    app()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(app())
