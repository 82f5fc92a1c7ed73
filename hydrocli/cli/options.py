"""Options shared by several commands (one definition each)."""
from __future__ import annotations

import typer

SET = typer.Option(None, "--set", help="override a parameter: comp.param=VALUE (units allowed), repeatable")
RTOL = typer.Option(1e-6, "--rtol", help="relative tolerance of the integrator")
BACKEND = typer.Option("auto", "--backend", help="integrator backend: auto | compiled | python")
