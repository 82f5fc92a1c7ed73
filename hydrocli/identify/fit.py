"""Fit free parameters of a built model to one or several experiments.

Build once, solve many: every trial only changes the parameter array. Methods:
``least-squares`` (SciPy trust-region reflective on the residual vector; default),
``nelder-mead`` (seed 004 §IV), ``differential-evolution`` (global, slower). The
least-squares Jacobian comes from forward sensitivities integrated with the states
(``gradient="sensitivities"``, one simulation per Jacobian, exact to the integrator's
accuracy) or from forward differences (``"finite-differences"``, one simulation per free
parameter). Standard errors and correlations come from the residual Jacobian at the
optimum, cov = σ²(JᵀJ)⁻¹ with σ² = SSR/(m − k) (Gauss–Newton approximation), mapped from the
unit box to parameter units. ``max_evals`` caps every simulation (residuals, Jacobian
columns, sensitivity runs): the progress callback counts the same simulations. Ctrl-C stops
the search and keeps the best point so far.
"""
from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import optimize

from ..blas import single_threaded
from ..errors import IdentifyError, Problem
from ..experiments.experiment import Experiment
from ..metrics import effective_samples
from ..model.model import Model
from ..solve.simulate import SolverOptions
from .cost import FAIL_RESIDUAL, Objective, make_targets
from .transforms import FreeParameters
from .uncertainty import Uncertainty, assess_fit

METHODS = ("least-squares", "nelder-mead", "differential-evolution")
GRADIENTS = ("auto", "sensitivities", "finite-differences")
FTOL = 1e-6    # least-squares stops when a step lowers the cost by less than this fraction
POLISH_RTOL = 0.01   # the polish's residuals at this fraction of the search's rtol
POLISH_STEPS = 4     # Gauss–Newton steps of the polish at most (each kept only when it lowers the cost)
UNDETERMINED = 1e-12  # a Jacobian column this small against the largest: no output is sensitive to the parameter


@dataclass
class FitResult:
    names: list[str]
    initial: np.ndarray
    estimates: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    stderr: np.ndarray
    correlation: np.ndarray
    cost_initial: float
    cost: float
    cost_history: list[float]
    p: np.ndarray                      # full parameter vector at the optimum
    n_evals: int
    n_failed: int
    n_residuals: int
    method: str
    message: str
    interrupted: bool = False
    seconds: float = 0.0
    warnings: list[str] = field(default_factory=list)
    stderr_white: np.ndarray | None = None   # Gauss–Newton, assuming white residuals
    n_effective: float = 0.0                 # independent residual samples (AR(1) estimate)
    gradient: str = "finite-differences"     # how the least-squares Jacobian was computed
    jacobian: np.ndarray | None = None       # ∂r/∂p at the optimum (parameter units), for the reports
    uncertainty: Uncertainty | None = None   # intervals, identifiability, fixed-parameter effects (assess=True)

    def as_dict(self) -> dict:
        """The /identify group of the HDF5 result."""
        return {"names": np.array(self.names, dtype=object), "initial": self.initial, "estimates": self.estimates,
                "lower": self.lower, "upper": self.upper, "stderr": self.stderr, "correlation": self.correlation,
                "cost_history": np.array(self.cost_history), "cost": self.cost, "cost_initial": self.cost_initial,
                "method": self.method, "message": self.message, "n_evals": self.n_evals,
                "interrupted": int(self.interrupted), "seconds": self.seconds,
                "stderr_white": self.stderr if self.stderr_white is None else self.stderr_white,
                "n_effective": self.n_effective or self.n_residuals,
                "warnings": np.array(self.warnings or [""], dtype=object), "gradient": self.gradient,
                **(self.uncertainty.as_dict() if self.uncertainty is not None else {})}


class _Budget(Exception):
    """The simulation budget (``max_evals``) is spent."""


class _Tracker:
    """Counts simulations, keeps the best point and the cost history, reports progress."""

    def __init__(self, progress=None, max_evals: int | None = None):
        self.best_cost = np.inf
        self.best_z = None
        self.history: list[float] = []
        self.progress = progress
        self.max_evals = max_evals
        self.n_sims = 0

    def spend(self, n: int = 1) -> None:
        """Book n simulations; raise _Budget when the cap would be exceeded."""
        if self.max_evals is not None and self.n_sims + n > self.max_evals:
            raise _Budget
        self.n_sims += n

    def see(self, z: np.ndarray, cost: float) -> None:
        if cost < self.best_cost:
            self.best_cost, self.best_z = cost, np.array(z, copy=True)
        self.history.append(self.best_cost)
        if self.progress:
            self.progress(self.n_sims, cost, self.best_cost)


RESTARTS = 2          # least squares restarted at most this often after a step-size (xtol) stop …
RESTART_GAIN = 0.01   # … that followed a cost decrease of at least this fraction


def gauss_newton_gain(J: np.ndarray, r: np.ndarray, z: np.ndarray, edge: float = 1e-8) -> float:
    """The fraction of the cost r·r that one Gauss–Newton step from ``z`` is predicted to remove,
    ‖J δ‖²/‖r‖² with δ = J⁺r (the projection of r on the columns of J), over the variables
    free to move: a variable at a bound of the unit box whose descent direction −(Jᵀr)ᵢ
    points out of it is left out. At a stationary point (Jᵀr = 0) it is 0. A restart after a
    step-size stop is worth a run only when this says a step is left to take (the trust
    region collapsed, not the optimum reached): at the optimum of a loosely integrated stick-slip
    model the restart only re-fits the integration's own noise."""
    J, r, z = np.asarray(J, float), np.asarray(r, float), np.asarray(z, float)
    rr = float(r @ r)
    if not (rr > 0.0 and np.all(np.isfinite(J)) and np.all(np.isfinite(r))):
        return 0.0
    g = J.T @ r
    free = ~(((z <= edge) & (g > 0)) | ((z >= 1.0 - edge) & (g < 0)))
    if not free.any():
        return 0.0
    Jf = J[:, free]
    delta = np.linalg.lstsq(Jf, r, rcond=1e-10)[0]
    step = Jf @ delta
    return float(step @ step) / rr


def fit(model: Model, experiments: list[Experiment], free: list[str] | None = None, **kw) -> FitResult:
    """``workers`` > 1 evaluates finite-difference Jacobian columns between that many threads,
    or pipelines each sensitivity run in two (``solve.sensitivities``; the compiled solver
    releases the GIL); the result does not depend on it. ``gradient``:
    ``auto`` uses sensitivities when the model has an analytic Jacobian. ``assess`` adds
    bootstrap intervals, the identifiability report and the effect of the fixed parameters
    (:mod:`.uncertainty`; one more sensitivity simulation). The linear algebra runs on one
    BLAS thread (:mod:`hydrocli.blas`: its matrices are tall and thin)."""
    with single_threaded():
        return _fit(model, experiments, free, **kw)


def _fit(model: Model, experiments: list[Experiment], free: list[str] | None = None, *,
         method: str = "least-squares", cost: str = "esr", outputs: list[str] | None = None,
         weights: dict[str, float] | None = None, bounds: dict[str, tuple[float, float]] | None = None,
         p_start: np.ndarray | None = None, max_evals: int = 400, opts: SolverOptions | None = None,
         progress=None, seed: int = 0, workers: int = 1, gradient: str = "auto", assess: bool = False,
         polish: bool = True) -> FitResult:
    if method not in METHODS:
        raise IdentifyError(Problem(f"unknown method '{method}'", hint=f"use one of {', '.join(METHODS)}"))
    if gradient not in GRADIENTS:
        raise IdentifyError(Problem(f"unknown gradient '{gradient}'", hint=f"use one of {', '.join(GRADIENTS)}"))
    fp = FreeParameters.from_model(model, free, bounds)
    base = model.p0 if p_start is None else np.asarray(p_start, float)
    objective = Objective(model, make_targets(model, experiments, outputs, cost, weights), opts)
    z0 = fp.to_z(base[fp.index])
    use_sens = sensitivities_available(model, gradient)
    # simulations kept for after the search: residuals and Jacobian at the optimum (+ the fixed parameters')
    polish = polish and method == "least-squares"
    reserve = (1 + 1 + int(assess)) if use_sens else len(z0) + 1
    # the polish's simulations, unless the budget is too small to spare them (then it is skipped)
    reserve += min(1 + POLISH_STEPS, max(0, (max_evals - reserve) // 4)) if polish else 0
    tracker = _Tracker(progress, max(max_evals - reserve, 1))
    lock = threading.Lock()
    last: dict = {}

    def residuals(z):
        with lock:
            tracker.spend()
        r = objective.residuals(fp.full_vector(base, fp.from_z(z)))
        with lock:
            tracker.see(z, float(r @ r))
        return r

    def fun(z):
        if "z" in last and np.array_equal(last["z"], z):
            return last["r"]
        r = residuals(z)
        last["z"], last["r"] = np.array(z, copy=True), r
        return r

    def jac(z):
        if use_sens:
            with lock:
                tracker.spend()
            r, Jp = objective.residuals_jacobian(fp.full_vector(base, fp.from_z(z)), fp.names, threads=workers)
            with lock:
                tracker.see(z, float(r @ r))
            J = Jp * fp.dp_dz(z)[None, :]
        else:
            J = jacobian(residuals, z, fun(z), workers)
        last["jz"], last["J"] = np.array(z, copy=True), J
        return J

    def scalar(z):
        return float(np.sum(residuals(z) ** 2))

    t0 = time.perf_counter()
    r0 = fun(z0)
    cost0 = float(r0 @ r0)
    interrupted, message = False, ""
    try:
        if method == "least-squares":
            z_run, c_run, x_scale = z0, cost0, 1.0
            for restart in range(2 + RESTARTS):
                sol = optimize.least_squares(fun, z_run, jac=jac, bounds=(0.0, 1.0), method="trf", x_scale=x_scale,
                                             max_nfev=max_evals, xtol=1e-6, ftol=FTOL)
                message = sol.message + (f" (after {restart} restart{'s' * (restart > 1)})" if restart else "")
                if restart == 0 and sol.status == 3 and not tracker.best_cost < c_run:
                    # a first step-size stop without a single accepted step: the trust region shrank on a
                    # badly scaled Jacobian (a parameter at a bound beside one whose column is 10⁷×
                    # larger) — run again with the variables scaled by the Jacobian's column norms
                    x_scale = "jac"
                    continue
                # a step-size stop (xtol) right after progress is the trust region collapsing on a
                # Jacobian that is only as accurate as the integration (forward sensitivities at a
                # loose tolerance, stick-slip): restarted from the best point with a fresh radius, at
                # most RESTARTS times (the rescaled run above is not one of them)
                if (restart >= RESTARTS + (x_scale == "jac") or sol.status != 3 or tracker.best_z is None
                        or not tracker.best_cost < (1 - RESTART_GAIN) * c_run
                        or gauss_newton_gain(sol.jac, sol.fun, sol.x) < RESTART_GAIN):
                    break
                z_run, c_run = tracker.best_z.copy(), tracker.best_cost
        elif method == "nelder-mead":
            sol = optimize.minimize(scalar, z0, method="Nelder-Mead", bounds=[(0, 1)] * len(z0),
                                    options={"maxfev": max_evals, "xatol": 1e-5, "fatol": 1e-10, "adaptive": True})
            message = sol.message
        else:
            sol = optimize.differential_evolution(scalar, [(0, 1)] * len(z0), x0=z0, maxiter=max(max_evals // (15 * len(z0)), 1),
                                                  popsize=15, seed=seed, polish=False, tol=1e-8)
            message = sol.message
    except KeyboardInterrupt:
        interrupted, message = True, "interrupted: kept the best parameters so far"
    except _Budget:
        message = f"stopped after {tracker.n_sims} simulations (--max-evals {max_evals}): kept the best parameters"
    z_best = tracker.best_z if tracker.best_z is not None else z0
    if objective.n_evals and objective.n_failed == objective.n_evals:
        raise IdentifyError(Problem(f"every trial simulation failed ({objective.n_failed})",
                                    hint="check the bounds, the initial state and the machine with 'hydro simulate'"))
    est = fp.from_z(z_best)
    p_best = fp.full_vector(base, est)
    untracked = lambda z: objective.residuals(fp.full_vector(base, fp.from_z(z)))   # noqa: E731
    J = last["J"] if "jz" in last and np.array_equal(last["jz"], z_best) else None   # reuse the last Jacobian
    # residuals at the optimum: the last evaluation's when it was there, else one more simulation
    # (skipped after Ctrl-C, like the uncertainty itself)
    r_best = last["r"] if "z" in last and np.array_equal(last["z"], z_best) else \
        (None if interrupted else untracked(z_best))
    if J is None and use_sens and not interrupted:
        r_best, Jp = objective.residuals_jacobian(p_best, fp.names, threads=workers)
        J = Jp * fp.dp_dz(z_best)[None, :]
    best_cost, n_polish = tracker.best_cost, 0
    # what the budget leaves for the polish: its first simulation and at least one step
    spare = max_evals - objective.n_evals - (0 if J is not None else (1 if use_sens else len(z_best))) \
        - int(assess and use_sens)
    if polish and not interrupted and r_best is not None and spare >= 2:
        if J is None:
            J = jacobian(untracked, z_best, r_best, workers)
        tight = Objective(model, objective.targets, replace(objective.opts, rtol=objective.opts.rtol * POLISH_RTOL))
        z_pol, r_pol, cost_pol = polish_step(lambda z: tight.residuals(fp.full_vector(base, fp.from_z(z))), z_best, J,
                                             min(POLISH_STEPS, spare - 1))
        n_polish = tight.n_evals
        if r_pol is not None:
            J = J / fp.dp_dz(z_best)[None, :] * fp.dp_dz(z_pol)[None, :]
            message = (f"{message}; polished at rtol {tight.opts.rtol:g} "
                       f"(cost {best_cost:.6g} → {cost_pol:.6g} there, {n_polish} simulations)")
            z_best, r_best, best_cost = z_pol, r_pol, cost_pol
            tracker.history.append(best_cost)
            est = fp.from_z(z_best)
            p_best = fp.full_vector(base, est)
    white, corr = _uncertainty(untracked, z_best, fp, best_cost, objective.size, interrupted, workers, J, r_best)
    n_eff = effective_samples(r_best) if r_best is not None else float(objective.size)
    stderr = white * np.sqrt(objective.size / n_eff) if n_eff > 0 else white
    res = FitResult(names=fp.names, initial=base[fp.index], estimates=est, lower=fp.lo, upper=fp.hi,
                    stderr=stderr, stderr_white=white, n_effective=n_eff, correlation=corr, cost_initial=cost0,
                    cost=best_cost,
                    cost_history=tracker.history, p=p_best, n_evals=objective.n_evals + n_polish,
                    n_failed=objective.n_failed,
                    n_residuals=objective.size, method=method, message=str(message), interrupted=interrupted,
                    seconds=time.perf_counter() - t0,
                    gradient="sensitivities" if use_sens else "finite-differences",
                    jacobian=None if J is None else J / fp.dp_dz(z_best)[None, :])
    res.warnings = fit_warnings(res, fp)
    if assess and J is not None and r_best is not None and not interrupted:
        fixed_fn = (lambda names: objective.residuals_jacobian(p_best, names)[1]) if use_sens else None
        rows = [(e, np.flatnonzero(m)) for e, t in enumerate(objective.targets) for m in t.masks]
        res.uncertainty = assess_fit(model, res, fp, z_best, J, r_best, rows, fixed_fn, seed)
    res.n_evals = objective.n_evals + n_polish
    if progress:
        progress(res.n_evals, res.cost, res.cost)       # the bar ends on every simulation the fit ran
    return res


def polish_step(residual_fn, z: np.ndarray, J_z: np.ndarray, steps: int | None = None):
    """Gauss–Newton steps z ← z − J⁺r(z) in the unit box with residuals ``residual_fn`` from a
    tighter integration and the search's Jacobian ``J_z``; a step is kept only when it lowers
    the cost. Returns (z, r, cost), or (z, None, nan) when the tighter simulation fails.

    The search's integrator tolerance leaves an error in the outputs (0.5–2 % around the EHA's
    stick-slip at rtol 1e-6) that moves the optimum by as much as the estimates' standard
    errors on a 30 s recording; the polish removes it at the cost of a few plain simulations.
    The fixed point solves J_zᵀ r = 0: the Jacobian's own error changes the answer only to
    second order."""
    from ..errors import HydroError
    try:
        r = residual_fn(z)
    except HydroError:
        return z, None, np.nan
    if not np.all(np.isfinite(r)) or np.any(np.abs(r) >= 0.999 * FAIL_RESIDUAL):
        return z, None, np.nan
    cost = float(r @ r)
    scale = np.linalg.norm(J_z, axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    pinv = np.linalg.pinv(J_z / scale[None, :]) / scale[:, None]
    for _ in range(POLISH_STEPS if steps is None else steps):
        z_new = np.clip(z - pinv @ r, 0.0, 1.0)
        if np.array_equal(z_new, z):
            break
        r_new = residual_fn(z_new)
        c_new = float(r_new @ r_new)
        if not c_new < cost:
            break
        small = cost - c_new <= FTOL * cost
        z, r, cost = z_new, r_new, c_new
        if small:
            break
    return z, r, cost


def sensitivities_available(model: Model, gradient: str = "auto") -> bool:
    """Whether the Jacobian comes from sensitivities (compiles the sensitivity library)."""
    if gradient == "finite-differences":
        return False
    from ..solve.sensitivities import sensitivity_library
    try:
        return sensitivity_library(model).has_sensitivities
    except Exception as exc:  # no compiler, or a model too large for the analytic derivatives
        if gradient == "sensitivities":
            raise IdentifyError(Problem(f"sensitivities are not available for this model: {exc}",
                                        hint="use --gradient finite-differences")) from None
        return False


def jacobian(residual_fn, z: np.ndarray, r0: np.ndarray, workers: int = 1, step: float = 1e-3) -> np.ndarray:
    """Forward differences in the unit box (step ``step``, backwards near the upper bound);
    columns in ``workers`` threads."""
    z = np.asarray(z, float)

    def column(i):
        h = step if z[i] + step <= 1.0 else -step
        zz = z.copy()
        zz[i] += h
        return (residual_fn(zz) - r0) / h

    if workers > 1 and len(z) > 1:
        with ThreadPoolExecutor(max_workers=workers) as ex:
            cols = list(ex.map(column, range(len(z))))
    else:
        cols = [column(i) for i in range(len(z))]
    return np.column_stack(cols) if cols else np.zeros((r0.size, 0))


def _uncertainty(residual_fn, z, fp: FreeParameters, ssr: float, m: int, interrupted: bool, workers: int = 1,
                 J: np.ndarray | None = None, r0: np.ndarray | None = None):
    k = len(z)
    nan = np.full(k, np.nan), np.full((k, k), np.nan)
    if interrupted or k == 0:
        return nan
    if J is None:
        try:
            J = jacobian(residual_fn, z, residual_fn(z) if r0 is None else r0, workers)
        except KeyboardInterrupt:
            return nan
    dof = max(m - k, 1)
    sigma2 = ssr / dof
    try:
        cov_z = sigma2 * np.linalg.pinv(J.T @ J)
    except np.linalg.LinAlgError:
        return nan
    d = fp.dp_dz(z)
    cov = cov_z * np.outer(d, d)
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    # a parameter no output is sensitive to (its Jacobian column zero: a valve never commanded
    # in the recording) has no information at all; the pseudo-inverse gives it variance 0, i.e.
    # "known exactly". Its standard error is infinite.
    cols = np.linalg.norm(J, axis=0)
    dead = cols <= UNDETERMINED * max(float(cols.max(initial=0.0)), np.finfo(float).tiny)
    se[dead] = np.inf
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    corr[dead, :] = np.nan
    corr[:, dead] = np.nan
    return se, corr


def fit_warnings(res: FitResult, fp: FreeParameters) -> list[str]:
    out = []
    at_bound = fp.at_bound(res.estimates)
    for n in at_bound:
        out.append(f"{n} ended at a bound: widen its bounds or check the model")
    for n, v, s in zip(res.names, res.estimates, res.stderr):
        if n not in at_bound and np.isposinf(s):
            out.append(f"{n} is not determined by these data: no output is sensitive to it "
                       "(fix it, or record an experiment that excites it)")
        elif n not in at_bound and np.isfinite(s) and v != 0 and s / abs(v) > 0.5:
            out.append(f"{n} is poorly determined (standard error {100 * s / abs(v):.0f} % of its value)")
    k = len(res.names)
    for i in range(k):
        for j in range(i + 1, k):
            c = res.correlation[i, j]
            if np.isfinite(c) and abs(c) > 0.95:
                out.append(f"{res.names[i]} and {res.names[j]} are strongly correlated ({c:+.2f})")
    if res.n_failed:
        out.append(f"{res.n_failed} trial simulation(s) failed and were penalised")
    return out
