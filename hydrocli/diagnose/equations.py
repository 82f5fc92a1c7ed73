"""Equation errors: each balance equation of the model evaluated along the measured
trajectory (Ljung, *System Identification* §7.3, equation-error view; seed 004 uses the
same idea when it identifies friction from m·a − ΣF).

States that an output measures directly (a chamber pressure — through its sensor — a
position, a velocity) are replaced by the measurement, zero-phase low-pass filtered; the
other states (e.g. the spool) come from the simulation. With X the hybrid trajectory,
e_s = dx_s/dt|measured − f_s(X, U, p) for each measured state s. Nothing here knows the
EHA: the equations come from ``model.numpy_evaluate`` and the state↔output map from the
output expressions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal

from ..errors import HydroError
from ..model.model import Model
from ..experiments.initial import direct_state, initial_state, sensed_state
from ..solve.simulate import simulate
from .residuals import OPTS

FC_HZ = 25.0


def measured_states(model: Model, exp) -> dict[str, str]:
    """{state: output} for outputs that read a state directly (through variable aliases),
    and for a sensor's state what it senses at rest (``Equations.rest``: a chamber under its
    pressure transducer)."""
    out = {}
    for o in exp.measured:
        s = direct_state(model, model.equations.output_exprs.get(o))
        if s is None:
            continue
        sensed = sensed_state(model, s)
        if sensed:
            out[sensed] = o
        out.setdefault(s, o)
    return out


def _lowpass(y, fs, fc=FC_HZ):
    b, a = signal.butter(2, min(fc / (fs / 2), 0.9))
    return signal.filtfilt(b, a, y, axis=0)


@dataclass
class Hybrid:
    """A trajectory whose measured states are the (low-passed) measurements and whose other
    states are simulated; ``measured``: {state: output}."""
    t: np.ndarray
    X: np.ndarray
    U: np.ndarray
    measured: dict[str, str]
    fs: float
    fc: float = FC_HZ

    def lowpass(self, y):
        return _lowpass(y, self.fs, self.fc)


def hybrid_trajectory(model: Model, exp, p: np.ndarray, fc: float = FC_HZ) -> Hybrid:
    """The model simulated along ``exp`` with parameters ``p``, each measured state replaced by
    its measurement, zero-phase low-pass filtered at ``fc``."""
    t = exp.t_out
    fs = 1.0 / float(np.median(np.diff(t)))
    traj = simulate(model, exp.inputs, t, p=p, x0=initial_state(model, exp, p), opts=OPTS)
    X = traj.X.copy()
    ms = measured_states(model, exp)
    for s, o in ms.items():
        X[:, model.state_index(s)] = _lowpass(exp.measured[o], fs, fc)
    U = np.column_stack([np.interp(t, exp.inputs.t, exp.inputs.U[:, j]) for j in range(exp.inputs.U.shape[1])]) \
        if exp.inputs.U.shape[1] else np.zeros((t.size, 0))
    return Hybrid(t, X, U, ms, fs, fc)


def balance_of(model: Model, state: str) -> str | None:
    """The balance whose equation is ``state``'s derivative: continuity for a pressure, force
    or torque balance for a velocity; None for a kinematic state (dx/dt = v) or a sensor's."""
    unit = model.states[model.state_index(state)].unit
    if unit == "m" or state.endswith(".y"):
        return None
    node = state.rsplit(".", 1)[0]
    return {"Pa": f"continuity at '{node}'", "m/s": f"force balance at '{node}'",
            "rad/s": f"torque balance at '{node}'"}.get(unit, f"equation of '{state}'")


def equation_errors(model: Model, exp, p: np.ndarray) -> dict[str, dict]:
    """{state: {"output", "balance", "relative_rms", "error"}} along the measured trajectory."""
    h = hybrid_trajectory(model, exp, p)
    dx, _, _, _ = model.numpy_evaluate()(h.t, list(h.X.T), p, list(h.U.T))
    out = {}
    for s, o in h.measured.items():
        balance = balance_of(model, s)
        if balance is None:
            continue
        i = model.state_index(s)
        meas = np.gradient(h.X[:, i], h.t)
        f = h.lowpass(np.broadcast_to(np.asarray(dx[i], float), h.t.shape))
        e = meas - f
        scale = float(np.sqrt(np.mean(meas ** 2))) or 1.0
        out[s] = {"output": o, "balance": balance, "relative_rms": float(np.sqrt(np.mean(e ** 2))) / scale,
                  "error": e}
    return out


def located_equations(model: Model, exp, p: np.ndarray) -> tuple[dict[str, dict], str | None]:
    """(:func:`equation_errors` without the error series — what the diagnosis reports under
    ``located.equations`` — and None), or ({}, why) when the model cannot follow the record
    (a stroke overrun): the equations only say where the error lands, they are not needed
    for a verdict."""
    try:
        errors = equation_errors(model, exp, p)
    except HydroError as exc:
        return {}, exc.problems[0].message
    return {s: {k: v for k, v in d.items() if k != "error"} for s, d in errors.items()}, None
