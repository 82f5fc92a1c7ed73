"""Run a built model over an input table: the one place that picks the integrator.

The default backend integrates entirely in compiled code (``solve.compiled``); the
``python`` backend (SciPy Radau on the generated NumPy right-hand side) is the fallback
when no C compiler is available and an independent cross-check in tests.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import Problem, SolverError
from ..model.model import Model


@dataclass
class SolverOptions:
    """Integrator settings.

    ``error_control="nominal"`` (default, unchanged for identify/diagnose): per-state
    absolute tolerance ``atol_i = atol_factor · rtol · nominal_i`` with the components'
    small nominal magnitudes (1 bar, 1 cm/s, 1 mm); fast, but the achieved error is
    10²–10⁴ × rtol × signal scale on the EHA.  ``"scaled"``: ``atol_i = rtol · scale_i``
    with the state's signal scale (:func:`state_scales`: 100 bar, 0.1 m/s, 0.1 m …) and, at
    rtol ≤ 1e-5, steps that end on the kinks of the linearly interpolated inputs, so the
    achieved error is a small multiple of rtol × signal scale (docs/solver.md has the
    measurements).  ``method`` picks the Rosenbrock coefficient set (:func:`method_for`).
    ``hydro simulate`` uses :func:`simulate_options` (``"scaled"``, rtol 1.5e-5).
    """

    rtol: float = 1e-6
    atol_factor: float = 1e3     # "nominal": atol_i = atol_factor · rtol · nominal magnitude of state i
    max_step: float = np.inf
    max_steps: int = 20_000_000
    backend: str = "auto"        # auto | compiled | python
    error_control: str = "nominal"   # nominal | scaled
    method: str = "auto"         # auto | rodas5p | rodas4p | rodas4 (compiled backend; see method_for)


#: ``"scaled"`` above this rtol: Rodas4P (6 stages) instead of Rodas5P (8) and steps cross the
#: inputs' kinks instead of ending on them (see :func:`method_for`, docs/solver.md)
LOOSE_RTOL = 1e-5
#: the default tolerance of ``hydro simulate`` / ``Machine.simulate``: ``"scaled"`` at this
#: rtol, i.e. an accuracy.  On the EHA (20 s) the achieved error between rtol 1e-5 and 5e-5 is
#: decided by stick-slip events and scatters 2-4x with small changes of rtol (0.009-0.042
#: bar); over 1.2e-5 … 3e-5 it stayed ≤ 0.039 bar, 0.27 mm/s, below the hand-written BDF
#: model's error (≤ half of it over 1.2e-5 … 1.8e-5 in pressure), so the default sits there
#: rather than at the fastest lucky value (docs/solver.md, sessions 4 and 17)
SIMULATE_RTOL = 1.5e-5


def simulate_options(rtol: float | None = None, backend: str = "auto",
                     error_control: str = "scaled") -> SolverOptions:
    """The options of ``hydro simulate`` and ``Machine.simulate``: by default a tolerance that
    means an accuracy (``error_control="scaled"`` at :data:`SIMULATE_RTOL`; ``"nominal"``
    without an rtol is ``SolverOptions()``, rtol 1e-6).  Fitting (identify, diagnose,
    validate) keeps ``SolverOptions()``'s ``"nominal"`` control."""
    if rtol is None:   # the default of each control: 1.5e-5 scaled, the fitting default 1e-6 nominal
        rtol = SIMULATE_RTOL if error_control == "scaled" else SolverOptions.rtol
    return SolverOptions(rtol=float(rtol), backend=backend, error_control=error_control)


def method_for(opts: SolverOptions) -> str:
    """The Rosenbrock method of the compiled backend for these options.

    ``"auto"``: Rodas4P under ``"scaled"`` with rtol > :data:`LOOSE_RTOL`, else Rodas5P.
    Measured on the EHA (20 s, one process): at the accuracy of scipy BDF (~0.02–0.04 bar)
    Rodas4P needs 25 % fewer right-hand sides than Rodas5P (6 stages instead of 8 at ~15 %
    more steps); at tighter tolerances Rodas5P's order 5 wins (docs/solver.md)."""
    if opts.method != "auto":
        return opts.method
    return "rodas4p" if opts.error_control == "scaled" and opts.rtol > LOOSE_RTOL else "rodas5p"


@dataclass
class Trajectory:
    t: np.ndarray
    X: np.ndarray                # samples × states
    Y: np.ndarray                # samples × outputs
    stats: dict = field(default_factory=dict)


@dataclass
class InputTable:
    """Machine inputs as a table on one time grid (SI values), columns in model order."""

    t: np.ndarray
    U: np.ndarray                # samples × inputs

    @staticmethod
    def constant(model: Model, t0: float = 0.0, values: dict[str, float] | None = None) -> "InputTable":
        vals = values or {}
        row = [vals.get(n, 0.0) for n in model.input_names]
        return InputTable(np.array([t0]), np.array([row], dtype=float).reshape(1, len(row)))


#: signal scale of a state by its SI unit: the magnitude a hydraulic machine's signal of
#: that kind typically spans (pressures up to ~100 bar, strokes and speeds ~0.1 m, m/s).
UNIT_SCALE = {"Pa": 1e7, "m": 0.1, "m/s": 0.1, "m/s^2": 10.0, "rad": 1.0, "rad/s": 1.0,
              "m^3/s": 1e-4, "m^3": 1e-3, "N": 1e3, "N*m": 1e2, "A": 0.1, "V": 10.0}


def state_scales(model: Model) -> np.ndarray:
    """Signal scale of each state: ``max(UNIT_SCALE[unit] or 100·nominal, nominal, |x0|)``.

    Used as the absolute-tolerance scale of ``error_control="scaled"``, so that
    ``atol_i = rtol · scale_i`` asks for the same relative accuracy of every signal.
    """
    out = []
    for s in model.states:
        base = UNIT_SCALE.get(s.unit.replace(" ", ""), 100.0 * abs(s.nominal))
        out.append(max(base, abs(s.nominal), abs(s.initial)))
    return np.array(out, dtype=float)


def atol_vector(model: Model, opts: SolverOptions) -> np.ndarray:
    if opts.error_control == "scaled":
        return state_scales(model) * opts.rtol
    if opts.error_control != "nominal":
        raise ValueError(f"error_control must be 'nominal' or 'scaled', got {opts.error_control!r}")
    return np.array([s.nominal for s in model.states], dtype=float) * opts.atol_factor * opts.rtol


def simulate(model: Model, inputs: InputTable, t_out: np.ndarray, p: np.ndarray | None = None,
             x0: np.ndarray | None = None, opts: SolverOptions | None = None) -> Trajectory:
    """Integrate from ``t_out[0]``; raise SolverError (exit 4) with the diverging state."""
    opts = opts or SolverOptions()
    p = model.p0 if p is None else np.asarray(p, dtype=float)
    x0 = model.x0 if x0 is None else np.asarray(x0, dtype=float)
    t_out = np.asarray(t_out, dtype=float)
    backend = opts.backend
    if backend in ("auto", "compiled"):
        from .library import _UNAVAILABLE, compiled_or_none
        lib = compiled_or_none(model, method=method_for(opts))   # explicit, cached, warned fallback
        if lib is not None:
            return _run_compiled(model, lib, inputs, t_out, p, x0, opts)
        if backend == "compiled":
            import hashlib
            why = _UNAVAILABLE.get(hashlib.sha256(model.c_source.encode("utf-8")).hexdigest(), "")
            raise SolverError(f"cannot compile the model: {why}",
                              hint="install a C compiler (gcc) or use --backend python")
    return _run_python(model, inputs, t_out, p, x0, opts)


def _hold_flags(model: Model, opts: SolverOptions | None = None) -> np.ndarray:
    """Per input: 1 zero-order hold; linear inputs 0, or 2 (steps end on their kinks) under
    ``error_control="scaled"`` with rtol ≤ :data:`LOOSE_RTOL` (a crossed kink's O(h²) error
    matters only at tight tolerances; at looser ones landing on every 1 kHz sample inside
    a transient costs steps and buys no accuracy, docs/solver.md)."""
    lin = 2 if opts is not None and opts.error_control == "scaled" and opts.rtol <= LOOSE_RTOL else 0
    return np.array([1 if model.input_hold.get(n) == "zoh" else lin for n in model.input_names], dtype=np.int32)


def _run_compiled(model, lib, inputs, t_out, p, x0, opts) -> Trajectory:
    res = lib.simulate(p, inputs.t, inputs.U, _hold_flags(model, opts), float(t_out[0]), x0, t_out,
                       rtol=opts.rtol, atol=atol_vector(model, opts), hmax=opts.max_step,
                       max_steps=opts.max_steps)
    if res.status != 0:
        err = _solver_error(model, res.status, res.stats, res.message)
        n_ok = int(np.searchsorted(t_out, res.stats.get("time_reached", t_out[0]), side="right"))
        err.partial = Trajectory(t_out[:n_ok], res.X[:n_ok], res.Y[:n_ok], dict(res.stats, backend="compiled"))
        raise err
    return Trajectory(t_out, res.X, res.Y, dict(res.stats, backend="compiled"))


def _solver_error(model: Model, status: int, stats: dict, message: str) -> SolverError:
    t_fail = stats.get("time_reached", stats.get("t", float("nan")))
    if status >= 100:
        return SolverError(Problem(f"at t = {t_fail:.6g} s: {model.guard_message(status - 100)}",
                                   hint="the model left its valid range; see the message for what to add"))
    worst = int(stats.get("worst_state", -1))
    what = {1: "step size underflow (stiffness blow-up or a discontinuity)",
            2: "too many steps", 3: "a state became NaN or infinite"}.get(status, message)
    if 0 <= worst < len(model.state_names):
        what += f"; state '{model.state_names[worst]}' diverged"
    else:
        what += " (the implicit step's linear system became singular)"
    return SolverError(Problem(f"at t = {t_fail:.6g} s: {what}",
                               hint="check parameters of the components around that state (volumes, "
                                    "masses, stiffness), add end stops, or loosen --rtol"))


def _interp_inputs(model: Model, inputs: InputTable):
    hold = _hold_flags(model)
    t_in, U = inputs.t, inputs.U

    def u_at(t: float) -> np.ndarray:
        if U.shape[1] == 0:
            return np.zeros(0)
        out = np.empty(U.shape[1])
        for j in range(U.shape[1]):
            if hold[j]:
                k = max(np.searchsorted(t_in, t, side="right") - 1, 0)
                out[j] = U[k, j]
            else:
                out[j] = np.interp(t, t_in, U[:, j])
        return out
    return u_at


def _run_python(model, inputs, t_out, p, x0, opts) -> Trajectory:
    from scipy.integrate import solve_ivp

    ev = model.numpy_evaluate()
    u_at = _interp_inputs(model, inputs)
    status_box = [0]

    def f(t, x):
        dx, _, _, status = ev(t, x, p, u_at(t))
        if status:
            status_box[0] = status
        return np.asarray(dx, dtype=float)

    sol = solve_ivp(f, (t_out[0], t_out[-1]), x0, method="Radau", t_eval=t_out, rtol=opts.rtol,
                    atol=atol_vector(model, opts), max_step=opts.max_step)
    if status_box[0]:
        raise _solver_error(model, 100 + status_box[0], {"time_reached": float(sol.t[-1]) if sol.t.size else 0.0}, "")
    if not sol.success or sol.y.shape[1] != t_out.size:
        raise SolverError(Problem(f"integration failed at t = {sol.t[-1] if sol.t.size else t_out[0]:.6g} s: "
                                  f"{sol.message}", hint="check parameters or loosen --rtol"))
    X = sol.y.T
    U = np.array([u_at(t) for t in t_out]).reshape(t_out.size, -1)
    _, y, _, _ = ev(t_out, list(X.T), p, list(U.T))
    Y = np.column_stack([np.broadcast_to(np.asarray(v, float), t_out.shape) for v in y]) if y else np.zeros((t_out.size, 0))
    return Trajectory(t_out, X, Y, {"backend": "python", "rhs_evals": int(sol.nfev), "jac_evals": int(sol.njev),
                                    "lu_decompositions": int(sol.nlu)})
