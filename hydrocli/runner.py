"""Shared steps of the commands: load a machine (with --set overrides), build it, and
simulate one experiment into a :class:`~hydrocli.results.RunResult`."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .experiments.experiment import Experiment
from .experiments.initial import initial_state
from .model.builder import build_model
from .model.model import Model
from .netlist.loader import load_netlist
from .netlist.model import Netlist
from .results import RunResult, run_result
from .solve.simulate import SolverOptions, simulate


def load_machine(path: str | Path, sets: list[str] | None = None) -> tuple[Netlist, Model]:
    net = load_netlist(path)
    if sets:
        from .netlist.overrides import apply_overrides
        net = apply_overrides(net, sets)
    return net, build_model(net)


def simulate_experiment(model: Model, exp: Experiment, p: np.ndarray | None = None,
                        opts: SolverOptions | None = None, command: str = "") -> RunResult:
    p = model.p0 if p is None else p
    traj = simulate(model, exp.inputs, exp.t_out, p=p, x0=initial_state(model, exp, p), opts=opts)
    return run_result(model, exp, traj, p, command)
