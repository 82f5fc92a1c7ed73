"""Output sensitivities ∂y(t)/∂θ of a built model, from the compiled integrator.

θ are parameters (dotted names, ``valve.tau``) and initial states (``x0:piston.x``). The
sensitivities are integrated with the states (forward, direct-decoupled, reusing each step's
factorisation: ``csrc/hy_sens.h``) from ∂f/∂p, ∂g/∂x, ∂g/∂p generated symbolically
(``model/jacobian.py``). One simulation gives every column; finite differences need one
simulation per column and lose half the digits.

The library with sensitivities is a second compiled library (built on first use, cached
on disk like the plain one); plain simulations keep using the smaller library.
"""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from ..errors import Problem, SolverError
from ..model.codegen import generate_c
from ..model.model import Model
from .simulate import InputTable, SolverOptions, _hold_flags, _solver_error, atol_vector

X0_PREFIX = "x0:"
#: above this estimated size of the analytic Jacobian's code the sensitivity code (about ten
#: times larger: the crane's would be 19 MB of C) costs more to compile than it saves; the
#: harvester (135 k) is below, the knuckle-boom crane (1.1 M) above
MAX_JACOBIAN_CHARS = 200_000


class SensitivitiesUnavailable(Exception):
    """The model is too large for generated sensitivity code (use finite differences)."""


@dataclass
class SensTrajectory:
    t: np.ndarray
    X: np.ndarray                # samples × states
    Y: np.ndarray                # samples × outputs
    dY: np.ndarray               # samples × outputs × len(wrt)
    wrt: list[str]
    stats: dict = field(default_factory=dict)
    dX: np.ndarray | None = None  # samples × states × len(wrt) (``states=True``)


def sensitivity_library(model: Model):
    """The model compiled with ``hy_simulate_sens`` (built once per model object)."""
    lib = model.__dict__.get("_sens_compiled")
    if lib is None:
        from ..model.codegen import _Names
        from ..model.jacobian import jacobian_size
        size = jacobian_size(model.equations, _Names(model.equations))
        if size > MAX_JACOBIAN_CHARS:
            raise SensitivitiesUnavailable(f"the model's analytic Jacobian would be ~{size // 1000} k characters of C "
                                           f"(limit {MAX_JACOBIAN_CHARS // 1000} k)")
        from .compiled import SENS_CFLAGS, CompiledModel, build_library
        so = build_library(generate_c(model.equations, model.name, sensitivities=True), cflags=SENS_CFLAGS)
        eq = model.equations
        lib = CompiledModel(so, len(eq.states), len(eq.params), len(eq.inputs), len(eq.outputs))
        model.__dict__["_sens_compiled"] = lib
    return lib


def columns(model: Model, wrt: list[str], dx0_dp: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(col_p, S0) for ``wrt``: a parameter's column starts at ``dx0_dp`` (nx × np, zero when
    the initial state does not depend on the parameters), ``x0:STATE`` at a unit vector."""
    nx = len(model.state_names)
    col_p = np.empty(len(wrt), dtype=np.intc)
    S0 = np.zeros((nx, len(wrt)))
    for c, name in enumerate(wrt):
        if name.startswith(X0_PREFIX):
            st = name[len(X0_PREFIX):]
            if st not in model.state_names:
                raise SolverError(Problem(f"unknown state '{st}' in sensitivity column '{name}'",
                                          hint="'hydro check MACHINE' lists the states"))
            col_p[c] = -1
            S0[model.state_index(st), c] = 1.0
        else:
            k = model.param_index(name)
            col_p[c] = k
            if dx0_dp is not None:
                S0[:, c] = dx0_dp[:, k]
    return col_p, S0


#: a run is given at least this many columns: below it the repeated state integration and
#: the per-step Jacobians cost more than the columns saved
MIN_COLUMNS_PER_THREAD = 4


def column_split(n: int, runs: int) -> list[slice]:
    """Contiguous column ranges for ``runs`` parallel sensitivity runs of ``n`` columns
    (fewer runs when a run would get under :data:`MIN_COLUMNS_PER_THREAD` columns)."""
    k = max(1, min(int(runs), n // MIN_COLUMNS_PER_THREAD))
    edges = [round(i * n / k) for i in range(k + 1)]
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:])]


def output_sensitivities(model: Model, inputs: InputTable, t_out: np.ndarray, p: np.ndarray | None = None,
                         x0: np.ndarray | None = None, wrt: list[str] | None = None,
                         opts: SolverOptions | None = None, dx0_dp: np.ndarray | None = None,
                         states: bool = False, s0: np.ndarray | None = None, threads: int = 1) -> SensTrajectory:
    """Simulate and return ``(Y, dY)``-carrying :class:`SensTrajectory`; ``dY[i, o, c]`` =
    ∂y_o(t_i)/∂wrt[c]; with ``states`` also ``dX[i, j, c]`` = ∂x_j(t_i)/∂wrt[c]. ``wrt``
    defaults to the free parameters; ``dx0_dp`` (states × all parameters) is ∂x0/∂p when the
    initial state depends on the parameters, or ``s0`` (states × len(wrt)) the initial
    sensitivities themselves. ``threads`` ≥ 2: each run is pipelined in two threads (the
    states and the per-step Jacobians in one, the columns a few steps behind in the other:
    ``csrc/hy_sens_pipe.h``; EHA 30 s, 15 columns: 170 → 95 ms), and with ``threads`` ≥ 4
    the columns are split between ``threads // 2`` such runs (each integrates the states
    again). A model above the library's dense-LU limit (``CompiledModel.pipelinable``,
    ``HY_DENSE_MAX`` read from the compiled library: a sparse LU) cannot be pipelined:
    its columns are split between ``threads`` runs. The columns are bitwise those of one
    sequential run either way: the state steps do not depend on the columns. Raises SolverError (exit 4) like
    :func:`~hydrocli.solve.simulate.simulate`."""
    opts = opts or SolverOptions()
    p = model.p0 if p is None else np.asarray(p, dtype=float)
    x0 = model.x0 if x0 is None else np.asarray(x0, dtype=float)
    t_out = np.asarray(t_out, dtype=float)
    wrt = list(model.free_params if wrt is None else wrt)
    lib = sensitivity_library(model)
    col_p, S0 = columns(model, wrt, dx0_dp)
    if s0 is not None:
        S0 = S0 + np.asarray(s0, dtype=float)

    hold, atol = _hold_flags(model), atol_vector(model, opts)

    pipelined = int(threads) >= 2 and lib.pipelinable

    def run(cols: slice):
        return lib.simulate_sens(p, inputs.t, inputs.U, hold, float(t_out[0]), x0, t_out, col_p[cols], S0[:, cols],
                                 rtol=opts.rtol, atol=atol, hmax=opts.max_step, max_steps=opts.max_steps, states=states,
                                 pipelined=pipelined)

    parts = column_split(len(wrt), int(threads) // 2 if pipelined else int(threads))
    if len(parts) == 1:
        res = run(parts[0])
    else:
        with ThreadPoolExecutor(max_workers=len(parts)) as ex:      # the compiled solver releases the GIL
            runs = list(ex.map(run, parts))
        res = next((r for r in runs if r.status != 0), runs[0])
        if res.status == 0:
            res.dY = np.concatenate([r.dY for r in runs], axis=2)
            res.dX = None if not states else np.concatenate([r.dX for r in runs], axis=2)
            res.stats["sensitivity_evals"] = sum(r.stats["sensitivity_evals"] for r in runs)
    if res.status != 0:
        raise _solver_error(model, res.status, res.stats, res.message)
    return SensTrajectory(t_out, res.X, res.Y, res.dY, wrt, dict(res.stats, backend="compiled"), res.dX)
