"""The state an experiment starts from on a given model (the experiment itself is plain data).

x0 = the model's initial state, then every state an output reads directly (through variable
aliases) set to that output's first finite measured sample (``initial_from_data``), and with a
sensor's state the quantity it reads at rest (``Equations.rest``), then the
experiment's explicit ``initial:`` values, then the machine file's initial RULES
(:class:`~hydrocli.model.model.InitialRule`): ``output`` (this state moved so that the output
starts at its first measured sample: one Newton step, exact for an output affine in the
state, e.g. a stroke read relative to a moving body, x = x_rod − x_frame), ``same_as`` (start
where another state starts: a rod and the load it drives through a compliant link), and —
with the parameters ``p`` — ``balance`` (the value that makes another state's derivative zero
at t0: the force a spring carries so the node it holds starts at rest; without it a load
hung on a compliant link drops at t = 0 and rings). With ``settle`` > 0 (``initial: steady``)
the machine then runs that long with its inputs frozen at their first value and starts from
the end of that pre-roll.
"""
from __future__ import annotations

import numpy as np

from ..model.model import Model
from ..solve.simulate import InputTable, SolverOptions, simulate
from .experiment import Experiment


def initial_state(model: Model, exp: Experiment, p: np.ndarray | None = None) -> np.ndarray:
    """x0 of ``exp`` on ``model`` (balance rules and a settle pre-roll use parameters ``p``)."""
    x0 = given_state(model, exp)
    if depends_on_parameters(model):
        x0 = balanced(model, exp, x0, model.p0 if p is None else np.asarray(p, dtype=float))
    if exp.settle > 0:
        frozen = InputTable(np.array([0.0]), exp.inputs.U[:1].copy())
        traj = simulate(model, frozen, np.array([0.0, exp.settle]), p=p, x0=x0, opts=SolverOptions(rtol=1e-6))
        x0 = traj.X[-1].copy()
    return x0


def depends_on_parameters(model: Model) -> bool:
    """Whether the start state (before any settle pre-roll) depends on the parameters."""
    return any(r.kind == "balance" for r in model.initial_rules)


def given_state(model: Model, exp: Experiment) -> np.ndarray:
    """x0 before balance rules and any settle pre-roll: model defaults, measured states,
    explicit values, ``output`` and ``same_as`` rules."""
    x0, first = model.x0.copy(), {}
    if exp.initial_from_data:
        for out, values in exp.measured.items():
            state = direct_state(model, model.equations.output_exprs.get(out))
            finite = values[np.isfinite(values)] if state is not None else values[:0]
            if finite.size:
                first[state] = finite[0]
        # a sensor at rest reads what it senses: a lagging transducer's state starts at its first
        # sample and so does the quantity it senses, unless that is measured or given itself (a
        # chamber left at the file's 35 bar under a sensor reading 57 bar rings for the whole lag)
        for state, value in list(first.items()):
            sensed = sensed_state(model, state)
            if sensed is not None and sensed not in first and sensed not in exp.initial:
                first[sensed] = value
        for state, value in first.items():
            x0[model.state_index(state)] = value
    for name, v in exp.initial.items():
        x0[model.state_index(name)] = v
    for rule in model.initial_rules:
        if rule.kind == "output" and exp.initial_from_data and rule.state not in exp.initial:
            _to_output(model, exp, x0, rule)
    x0 = _same_as(model, x0, skip=set(exp.initial))
    return _sensors_at_rest(model, x0, skip=set(exp.initial) | set(first))


def _sensors_at_rest(model: Model, x0: np.ndarray, skip: set) -> np.ndarray:
    """x0 with every sensor state not in ``skip`` reading what it senses (``Equations.rest``):
    without a sample to start from, a transducer starts at rest on its node."""
    for state in model.equations.rest:
        sensed = sensed_state(model, state)
        if state not in skip and sensed is not None:
            x0[model.state_index(state)] = x0[model.state_index(sensed)]
    return x0


def sensed_state(model: Model, state: str) -> str | None:
    """The state a sensor's ``state`` reads at rest (``Equations.rest``, through variable
    aliases): the chamber pressure under a transducer, the rod under an encoder; else None."""
    return direct_state(model, model.equations.rest.get(state))


def _same_as(model: Model, x0: np.ndarray, skip: set) -> np.ndarray:
    """x0 with every ``same_as`` rule's state (not in ``skip``) set to its reference's start."""
    for rule in model.initial_rules:
        if rule.kind == "same_as" and rule.state not in skip:
            x0[model.state_index(rule.state)] = x0[model.state_index(rule.ref)]
    return x0


def _evaluate(model: Model, t0: float, u0, x0: np.ndarray, p: np.ndarray):
    """(dx, y) of the model at (t0, x0, u0) with parameters p."""
    dx, y, _, _ = model.numpy_evaluate()(t0, list(x0), p, list(u0))
    return np.array([float(np.asarray(d)) for d in dx]), np.array([float(np.asarray(v)) for v in y])


def _to_output(model: Model, exp: Experiment, x0: np.ndarray, rule) -> None:
    values = exp.measured.get(rule.ref)
    finite = values[np.isfinite(values)] if values is not None else np.zeros(0)
    if not finite.size:
        return
    i, o = model.state_index(rule.state), model.output_names.index(rule.ref)
    t0, u0 = float(exp.inputs.t[0]), exp.inputs.U[0]
    h = 1e-6 * max(abs(x0[i]), 1e-3)
    _, y0 = _evaluate(model, t0, u0, x0, model.p0)
    x1 = x0.copy()
    x1[i] += h
    _, y1 = _evaluate(model, t0, u0, x1, model.p0)
    slope = (y1[o] - y0[o]) / h
    if np.isfinite(slope) and abs(slope) > 1e-9:
        x0[i] += (finite[0] - y0[o]) / slope


def balanced(model: Model, exp: Experiment, x0: np.ndarray, p: np.ndarray) -> np.ndarray:
    """x0 with every ``balance`` rule's state set so that its reference state's derivative
    is zero at t0 (inputs at their first sample)."""
    return _balance(model, float(exp.inputs.t[0]), exp.inputs.U[0], x0, p, skip=set(exp.initial))


def start_without_data(model: Model, p: np.ndarray | None = None) -> np.ndarray:
    """The start state when no experiment is at hand (an exported FMU: inputs at 0, t = 0):
    the model's defaults with ``same_as`` and ``balance`` rules applied; ``output`` rules need a
    recording and are left at the file's number."""
    x0 = _same_as(model, model.x0.copy(), skip=set())
    u0 = np.zeros(len(model.input_names))
    return _balance(model, 0.0, u0, x0, model.p0 if p is None else np.asarray(p, dtype=float), skip=set())


BALANCE_ITERATIONS = 25   # Newton steps at most: a spring's balance is linear (one step, one to
                          # confirm); a joint with clearance starts in its dead band, where the
                          # slope is nearly zero, and reaches its contact in a few more


def _balance(model: Model, t0: float, u0, x0: np.ndarray, p: np.ndarray, skip: set) -> np.ndarray:
    """Newton on the (small, linear for springs) system ∂ẋ_ref/∂x_state = 0 of the balance rules."""
    rules = [r for r in model.initial_rules if r.kind == "balance" and r.state not in skip]
    if not rules:
        return x0
    x0 = x0.copy()
    si = [model.state_index(r.state) for r in rules]
    ri = [model.state_index(r.ref) for r in rules]
    for _ in range(BALANCE_ITERATIONS):
        dx, _ = _evaluate(model, t0, u0, x0, p)
        g = dx[ri]
        if not np.all(np.isfinite(g)):
            return x0
        J = np.empty((len(rules), len(rules)))
        for c, i in enumerate(si):
            h = 1e-6 * max(abs(x0[i]), 1.0)
            x1 = x0.copy()
            x1[i] += h
            J[:, c] = (_evaluate(model, t0, u0, x1, p)[0][ri] - g) / h
        try:
            step = np.linalg.solve(J, -g)
        except np.linalg.LinAlgError:
            return x0
        x0[si] += step
        if np.all(np.abs(step) <= 1e-9 * np.maximum(np.abs(x0[si]), 1.0)):
            break
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
