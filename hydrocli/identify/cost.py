"""Residuals and costs of a parameter set over one or several experiments.

For experiment e and fitted output o with N_eo used samples the residual is
r = (ŷ − y)/(s_eo·sqrt(N_eo)), so that the cost Σr² is

* ``esr`` (default): s = std(y) → cost = Σ ESR_eo/100, every output weighted by its
  own variance (ESR, seed 004 eq. 14);
* ``seed004``: s = max|y| → seed 004's normalised squared error, eq. 13;
* ``wls``: s = 1/w_o with user weights (weighted least squares).
"""
from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from ..errors import HydroError, IdentifyError, Problem
from ..experiments.experiment import Experiment
from ..experiments.initial import balanced, depends_on_parameters, given_state, initial_state
from ..model.model import Model
from ..solve.simulate import SolverOptions, simulate

COSTS = ("esr", "seed004", "wls")
FAIL_RESIDUAL = 10.0   # per-sample residual of a failed simulation (≫ any fit)
DIVERGED = 1e50        # |residual| or |∂r/∂p| beyond this, in any units, is a run that blew up


def bounded_residual(r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The residual with every sample that is NaN or beyond ±DIVERGED set to the failure's value,
    and the mask of those samples: a run that blew up without failing, whose squares would
    overflow the optimiser's sums (and LAPACK's scaling) if left as they were."""
    bad = ~(np.abs(r) < DIVERGED)
    return (np.where(bad, FAIL_RESIDUAL, r) if bad.any() else r), bad


@dataclass
class Target:
    """One experiment's fitted outputs: indices, measured values, masks and scales."""

    exp: Experiment
    outputs: list[str]
    cols: list[int]
    values: list[np.ndarray]
    masks: list[np.ndarray]
    scales: list[float]

    @property
    def size(self) -> int:
        return int(sum(m.sum() for m in self.masks))


def make_targets(model: Model, experiments: list[Experiment], outputs: list[str] | None = None,
                 cost: str = "esr", weights: dict[str, float] | None = None) -> list[Target]:
    if cost not in COSTS:
        raise IdentifyError(Problem(f"unknown cost '{cost}'", hint=f"use one of {', '.join(COSTS)}"))
    targets = []
    for exp in experiments:
        names = [o for o in (outputs or exp.fit_outputs or list(exp.measured)) if o in exp.measured]
        if outputs:
            missing = [o for o in outputs if o not in exp.measured]
            if missing:
                raise IdentifyError(Problem(f"experiment '{exp.name}' has no measurement of {', '.join(missing)}",
                                            hint="map the recording's columns to these outputs in the experiment file"))
        if not names:
            raise IdentifyError(Problem(f"experiment '{exp.name}' measures none of the machine's outputs "
                                        f"({', '.join(model.output_names)})",
                                        hint="name recording columns like the outputs or map them in the experiment file"))
        cols, vals, masks, scales = [], [], [], []
        for o in names:
            y = exp.measured[o]
            m = np.isfinite(y) & exp.mask.get(o, np.ones_like(y, dtype=bool))
            if cost == "esr":
                s = float(np.std(y[m]))
            elif cost == "seed004":
                s = float(np.max(np.abs(y[m])))
            else:
                w = (weights or {}).get(o, exp.weights.get(o, 1.0))
                s = 1.0 / w if w else np.inf
            if not np.isfinite(s) or s <= 0:
                s = 1.0
            cols.append(model.output_names.index(o))
            vals.append(y)
            masks.append(m)
            scales.append(s)
        targets.append(Target(exp, names, cols, vals, masks, scales))
    return targets


class Objective:
    """Simulate all experiments for a full parameter vector; return stacked residuals.

    Thread-safe: the compiled solver releases the GIL, so Jacobian columns can be
    evaluated in parallel threads (fit's ``workers``)."""

    def __init__(self, model: Model, targets: list[Target], opts: SolverOptions | None = None):
        self.model, self.targets = model, targets
        self.opts = opts or SolverOptions(rtol=1e-6)
        self.n_evals = 0
        self.n_failed = 0
        self.size = sum(t.size for t in targets)
        self._lock = threading.Lock()
        # cached unless the start depends on the parameters (a settle pre-roll, a balance rule)
        self._x0 = [None if t.exp.settle > 0 or depends_on_parameters(model) else initial_state(model, t.exp)
                    for t in targets]

    def x0(self, i: int, p: np.ndarray) -> np.ndarray:
        """Initial state of target i (settled with parameters p when the experiment asks)."""
        return self._x0[i] if self._x0[i] is not None else initial_state(self.model, self.targets[i].exp, p)

    def residuals(self, p: np.ndarray) -> np.ndarray:
        with self._lock:
            self.n_evals += 1
        out = []
        for i, t in enumerate(self.targets):
            try:
                Y = simulate(self.model, t.exp.inputs, t.exp.t_out, p=p, x0=self.x0(i, p), opts=self.opts).Y
            except HydroError:
                with self._lock:
                    self.n_failed += 1
                out.extend(np.full(int(m.sum()), FAIL_RESIDUAL) for m in t.masks)
                continue
            for col, y, m, s in zip(t.cols, t.values, t.masks, t.scales):
                out.append(bounded_residual((Y[m, col] - y[m]) / (s * np.sqrt(m.sum())))[0])
        return np.concatenate(out) if out else np.zeros(0)

    def residuals_jacobian(self, p: np.ndarray, wrt: list[str], threads: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Residuals and ∂r/∂p[wrt] from forward sensitivities: one simulation per experiment
        (``solve.sensitivities``; pipelined in two threads when ``threads`` ≥ 2); an
        experiment that settles first carries ∂x0/∂p from its settling run. A failed
        simulation gives the failure residual and zero derivatives."""
        from ..solve.sensitivities import output_sensitivities
        with self._lock:
            self.n_evals += 1
        out_r, out_j = [], []
        for i, t in enumerate(self.targets):
            try:
                dx0 = None
                x0 = self._x0[i]
                if x0 is None and t.exp.settle > 0:
                    x0, dx0 = self._settle_sensitivities(t.exp, p, wrt)
                elif x0 is None:
                    x0, dx0 = self._start_sensitivities(t.exp, p, wrt)
                tr = output_sensitivities(self.model, t.exp.inputs, t.exp.t_out, p=p, x0=x0, wrt=wrt,
                                          opts=self.opts, s0=dx0, threads=threads)
            except HydroError:
                with self._lock:
                    self.n_failed += 1
                for m in t.masks:
                    out_r.append(np.full(int(m.sum()), FAIL_RESIDUAL))
                    out_j.append(np.zeros((int(m.sum()), len(wrt))))
                continue
            for col, y, m, s in zip(t.cols, t.values, t.masks, t.scales):
                k = s * np.sqrt(m.sum())
                r, bad = bounded_residual((tr.Y[m, col] - y[m]) / k)
                jr = tr.dY[m, col, :]
                jr /= k
                jr[bad] = 0.0                   # no slope where the residual is the failure's
                jr[~(np.abs(jr) < DIVERGED)] = 0.0
                out_r.append(r)
                out_j.append(jr)
        if not out_r:
            return np.zeros(0), np.zeros((0, len(wrt)))
        return np.concatenate(out_r), (out_j[0] if len(out_j) == 1 else np.concatenate(out_j))

    def _settle_sensitivities(self, exp: Experiment, p: np.ndarray, wrt: list[str]):
        """x0 after the experiment's settling run and ∂x0/∂p[wrt] (its state sensitivities)."""
        from ..solve.sensitivities import output_sensitivities
        from ..solve.simulate import InputTable
        frozen = InputTable(np.array([0.0]), exp.inputs.U[:1].copy())
        start, ds = self._start_sensitivities(exp, p, wrt)
        tr = output_sensitivities(self.model, frozen, np.array([0.0, exp.settle]), p=p,
                                  x0=start, wrt=wrt, opts=SolverOptions(rtol=1e-6), states=True, s0=ds)
        return tr.X[-1].copy(), tr.dX[-1]

    def _start_sensitivities(self, exp: Experiment, p: np.ndarray, wrt: list[str]):
        """x0 before any settle run and ∂x0/∂p[wrt]: none unless balance rules make the start
        depend on the parameters (then finite differences of the balance: algebra at t0 only).
        The step is relative to the parameter OR to its bounds' width, so a parameter at 0 (a
        weight or a friction not yet used) still moves the balance by a representable amount."""
        from ..solve.sensitivities import X0_PREFIX
        x0 = given_state(self.model, exp)
        if not depends_on_parameters(self.model):
            return x0, None
        base = balanced(self.model, exp, x0, p)
        ds = np.zeros((len(x0), len(wrt)))
        for c, name in enumerate(wrt):
            if name.startswith(X0_PREFIX):
                continue
            k = self.model.param_index(name)
            lo, hi = self.model.params[k].bounds or (0.0, 0.0)
            width = hi - lo if np.isfinite(hi - lo) else 0.0
            q = p.copy()
            q[k] += 1e-6 * max(abs(p[k]), 1e-3 * width, 1e-12)
            ds[:, c] = (balanced(self.model, exp, x0, q) - base) / (q[k] - p[k])
        return base, ds

    def cost(self, p: np.ndarray) -> float:
        r = self.residuals(p)
        return float(r @ r)
