"""Helpers for the multibody tests: build a machine from YAML text, simulate, linearise."""
from __future__ import annotations

import numpy as np

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate


def build(text: str):
    return build_model(load_netlist_text(text))


def run(model, t_end: float, n: int = 401, rtol: float = 1e-8, x0=None, inputs=None):
    t = np.linspace(0.0, t_end, n)
    u = inputs if inputs is not None else InputTable.constant(model)
    tr = simulate(model, u, t, p=model.p0, x0=model.x0 if x0 is None else x0, opts=SolverOptions(rtol=rtol))
    return t, tr


def state(model, tr, name):
    return tr.X[:, model.state_names.index(name)]


def jacobian(model, x0, h=1e-7):
    """Finite-difference Jacobian of the right-hand side at x0 (no inputs)."""
    ev = model.numpy_evaluate()
    u = np.zeros(len(model.input_names))
    f0 = np.asarray(ev(0.0, x0, model.p0, u)[0], float)
    J = np.empty((x0.size, x0.size))
    for j in range(x0.size):
        x = x0.copy()
        dx = h * max(1.0, abs(x0[j]))
        x[j] += dx
        J[:, j] = (np.asarray(ev(0.0, x, model.p0, u)[0], float) - f0) / dx
    return J
