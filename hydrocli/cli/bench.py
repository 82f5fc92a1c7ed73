"""``hydro bench``: speed figures with the baseline run in the same process."""
from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    @app.command("bench")
    def bench_cmd(quick: bool = typer.Option(False, "--quick", help="fewer repeats, shorter scaling runs"),
                  only: str = typer.Option("all", "--only", help="all | eha | wp | scaling | build"),
                  plot: str = typer.Option("work_precision.png", "--plot",
                                           help="work–precision figure to write (.png or .pdf)")) -> None:
        """Compare the compiled model with solve_ivp (BDF/LSODA) on seed 004's EHA; work–precision table and
        plot (EHA and 10 circuits); scaling; build time."""
        from .main import run_guarded
        from .. import bench

        if only not in ("all", "eha", "wp", "scaling", "build"):
            raise typer.BadParameter(f"unknown part {only!r}; use all, eha, wp, scaling or build",
                                     param_hint="--only")
        if plot and not plot.lower().endswith((".png", ".pdf", ".svg")):
            raise typer.BadParameter(f"{plot!r}: the figure must end in .png, .pdf or .svg", param_hint="--plot")

        def run():
            if only == "eha":
                bench.bench_eha(repeat=3 if quick else 7, echo=typer.echo)
            elif only == "wp":
                bench.bench_work_precision(quick=quick, plot=plot, echo=typer.echo)
            elif only == "scaling":
                bench.bench_scaling(t_end=2.0 if quick else 5.0, echo=typer.echo)
            elif only == "build":
                bench.bench_build(echo=typer.echo)
            else:
                bench.run_all(quick=quick, echo=typer.echo, plot=plot)
        run_guarded(run)
