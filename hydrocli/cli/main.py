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

_state = {"debug": False}


class _Group(typer.core.TyperGroup):
    """Accepts ``--debug`` anywhere on the command line (before or after the command)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        for cmd in [self, *self.commands.values()]:
            for param in cmd.params:
                _plain_metavar(param)
            cmd.get_help_option = _plain_help(cmd.get_help_option)

    def parse_args(self, ctx, args):
        end = args.index("--") if "--" in args else len(args)
        _state["debug"] = "--debug" in args[:end]
        if _state["debug"]:
            args = [a for a in args[:end] if a != "--debug"] + args[end:]
        return super().parse_args(ctx, args)


def _plain_help(get_help_option):
    def patched(ctx):
        opt = get_help_option(ctx)
        if opt is not None:
            opt.display_type_rich = lambda ctx: None
        return opt
    return patched


def _plain_metavar(param) -> None:
    """Help shows MACHINE, FILE, N, X, TEXT instead of Python type names (<list[Path]>, {machine})."""
    desc = getattr(param, "type_descriptor", None)
    if desc is None:
        return
    annotation = str(desc.annotation)
    label = ("" if desc.annotation is bool else "FILE" if desc.is_path or "Path" in annotation
             else "N" if "int" in annotation else "X" if "float" in annotation else "TEXT")
    many = "..." if param.nargs != 1 or getattr(param, "multiple", False) else ""
    if param.param_type_name == "argument":
        name = (param.metavar or param.name or "ARG").strip("[]").upper()
        param.metavar = name
        usage = (name if param.required else f"[{name}]") + many
        param._usage_display_name = lambda: usage
        param.display_type_rich = lambda ctx: None
    else:
        param.display_type_rich = lambda ctx: label or None     # repeatable options say so in their help


app = typer.Typer(cls=_Group, add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  help="Model, simulate, identify, validate and diagnose hydraulic machines.")


def _print_version(value: bool) -> None:
    if value:
        from ..version import __version__
        typer.echo(f"hydrocli {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(debug: bool = typer.Option(False, "--debug", help="show tracebacks on errors (anywhere on the line)"),
          version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                       help="print the version and exit")) -> None:
    _state["debug"] = _state["debug"] or debug


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
    from ..fileio import command_scope
    try:
        with command_scope():
            return fn(*args, **kwargs)
    except HydroError as err:
        fail(err)
    except KeyboardInterrupt:
        typer.echo("interrupted", err=True)
        raise typer.Exit(130)
    except typer.Exit:
        raise
    except RecursionError:
        if _state["debug"]:
            raise
        typer.echo("error: an input is nested too deeply to evaluate (e.g. thousands of nested "
                   "parentheses or minus signs); simplify it", err=True)
        raise typer.Exit(3)
    except MemoryError:
        typer.echo("error: out of memory (a very long experiment or a very high sample rate?)", err=True)
        raise typer.Exit(3)
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
