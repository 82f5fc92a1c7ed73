"""Options shared by several commands (one definition each)."""
from __future__ import annotations

import typer

SET = typer.Option(None, "--set", help="override a parameter: comp.param=VALUE (units allowed), repeatable")
RTOL = typer.Option(1e-6, "--rtol", help="relative tolerance of the integrator")
SIM_RTOL = typer.Option(None, "--rtol", help="relative tolerance of the integrator; under the default "
                        "--error-control scaled the achieved error is a few x rtol x each signal's scale "
                        "(100 bar, 0.1 m/s ...); default 1.5e-5")
ERROR_CONTROL = typer.Option("scaled", "--error-control",
                             help="scaled: tolerance = accuracy relative to signal scale | nominal: the fitting "
                                  "commands' faster, looser control")
ERROR_CONTROLS = ("scaled", "nominal")
BACKEND = typer.Option("auto", "--backend", help="integrator backend: auto | compiled | python")
BACKENDS = ("auto", "compiled", "python")


def check_choice(option: str, value: str, choices: tuple[str, ...]) -> None:
    """A value outside ``choices`` is a usage error (exit 2) with "did you mean"."""
    from ..suggest import suggest
    from ..errors import Location, Problem, UsageError
    if value not in choices:
        raise UsageError(Problem(f"{option} {value}: unknown choice{suggest(str(value), choices)}",
                                 Location(path=option), f"choose one of: {', '.join(choices)}"))


def check_positive(option: str, value: float, upper: float | None = None) -> None:
    """A count or tolerance that must be finite, > 0 (and < ``upper``)."""
    import math

    from ..errors import Location, Problem, UsageError
    if value is None:
        return
    if not (math.isfinite(value) and value > 0 and (upper is None or value < upper)):
        rng = f"between 0 and {upper:g} (exclusive)" if upper else "greater than 0"
        raise UsageError(Problem(f"{option} {value}: must be {rng}", Location(path=option),
                                 f"e.g. {option} {'1e-6' if upper else '2'}"))
