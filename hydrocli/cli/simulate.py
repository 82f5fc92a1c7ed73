"""``hydro simulate MACHINE --experiment EXP --out RESULT.h5``."""
from __future__ import annotations

import time
from pathlib import Path

import typer

from .options import BACKEND, ERROR_CONTROL, SET, SIM_RTOL


def register(app: typer.Typer) -> None:
    @app.command("simulate")
    def simulate_cmd(
        machine: Path = typer.Argument(..., help="machine YAML file"),
        experiment: Path = typer.Option(..., "--experiment", "-e", help="experiment YAML or recording (.csv/.h5/.mat)"),
        out: Path = typer.Option(Path("result.h5"), "--out", "-o", help="HDF5 result file to write"),
        sets: list[str] = SET,
        rtol: float = SIM_RTOL,
        backend: str = BACKEND,
        error_control: str = ERROR_CONTROL,
    ) -> None:
        """Simulate a machine against recorded or designed inputs and write HDF5."""
        from .main import run_guarded
        run_guarded(_run, machine, experiment, out, sets, rtol, backend, error_control)


def _run(machine, experiment, out, sets, rtol, backend, error_control="scaled") -> None:
    from ..api import load_experiment, load_machine   # the Python API: one path for CLI and notebooks

    from ..fileio import guard_output
    from .options import BACKENDS, ERROR_CONTROLS, check_choice, check_positive
    check_choice("--backend", backend, BACKENDS)
    check_choice("--error-control", error_control, ERROR_CONTROLS)
    check_positive("--rtol", rtol, upper=1.0)
    guard_output(out, (machine, experiment))
    t0 = time.perf_counter()
    m = load_machine(machine, set=sets)
    model = m.model
    for w in model.warnings:
        typer.echo(f"warning: {w}", err=True)
    exp = load_experiment(experiment, m)
    guard_output(out)                       # now that the recording an experiment names is known
    t1 = time.perf_counter()
    sim = m.simulate(exp, rtol=rtol, backend=backend, error_control=error_control)
    t2 = time.perf_counter()
    res = sim.run
    sim.save(out)
    st = res.solver_stats
    typer.echo(f"simulated {model.name} on {exp.name}: {res.t[-1] - res.t[0]:.3g} s in {t2 - t1:.3g} s "
               f"(load+build {t1 - t0:.2g} s; {st.get('backend', '?')} backend, "
               f"{int(st.get('steps_accepted', 0))} steps, {int(st.get('rhs_evals', 0))} rhs evals) → {out}")
