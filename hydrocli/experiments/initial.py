"""The state an experiment starts from on a given model (the experiment itself is plain data).

x0 = the model's initial state, then every state an output reads directly (through variable
aliases) set to that output's first finite measured sample (``initial_from_data``), then the
experiment's explicit ``initial:`` values; with ``settle`` > 0 (``initial: steady``) the
machine then runs that long with its inputs frozen at their first value (parameters ``p``)
and starts from the end of that pre-roll.
"""
from __future__ import annotations

import numpy as np

from ..model.model import Model
from ..solve.simulate import InputTable, SolverOptions, simulate
from .experiment import Experiment


def initial_state(model: Model, exp: Experiment, p: np.ndarray | None = None) -> np.ndarray:
    """x0 of ``exp`` on ``model`` (a settle pre-roll runs with parameters ``p``)."""
    x0 = given_state(model, exp)
    if exp.settle > 0:
        frozen = InputTable(np.array([0.0]), exp.inputs.U[:1].copy())
        traj = simulate(model, frozen, np.array([0.0, exp.settle]), p=p, x0=x0, opts=SolverOptions(rtol=1e-6))
        x0 = traj.X[-1].copy()
    return x0


def given_state(model: Model, exp: Experiment) -> np.ndarray:
    """x0 before any settle pre-roll: model defaults, measured states, explicit values."""
    x0 = model.x0.copy()
    if exp.initial_from_data:
        for out, values in exp.measured.items():
            state = direct_state(model, model.equations.output_exprs.get(out))
            finite = values[np.isfinite(values)] if state is not None else values[:0]
            if finite.size:
                x0[model.state_index(state)] = finite[0]
    for name, v in exp.initial.items():
        x0[model.state_index(name)] = v
    return x0


def direct_state(model: Model, e) -> str | None:
    """The state an output expression reads directly (through variable aliases), if any."""
    seen = 0
    while e is not None and e.op == "sym" and seen < 20:
        kind, name = e.args
        if kind == "state":
            return name
        if kind != "var":
            return None
        e = model.equations.variables.get(name)
        seen += 1
    return None
