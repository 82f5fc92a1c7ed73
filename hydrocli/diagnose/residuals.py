"""Simulated outputs, residuals and ESR of a parameter vector on a set of experiments —
the shared numerical core of screening and acceptance. Residuals are those of the
identification cost (``identify.cost``, ESR scaling: r = (ŷ − y)/(std(y)·√N)), so the
sum of squares is Σ ESR/100 and sensitivities are comparable across outputs."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import HydroError
from ..experiments.experiment import Experiment
from ..experiments.initial import initial_state
from ..identify.cost import Objective, make_targets
from ..metrics import effective_samples, esr
from ..model.model import Model
from ..solve.simulate import SolverOptions, simulate

OPTS = SolverOptions(rtol=1e-6)


def objective(model: Model, exps: list[Experiment]) -> Objective:
    """The identification cost on each experiment's ``fit_outputs`` (see :func:`focus`)."""
    return Objective(model, make_targets(model, exps, None, "esr"), OPTS)


def focus(exps: list[Experiment], outputs: list[str]) -> list[Experiment]:
    """Copies that fit, in every experiment, the diagnosis outputs it measures (a sensor moved
    between runs — chamber A in some recordings, B in others — still counts where it was)."""
    return [replace(e, fit_outputs=[o for o in outputs if o in e.measured]) for e in exps]


def simulate_outputs(model: Model, exps: list[Experiment], p: np.ndarray) -> list[np.ndarray]:
    """Y (samples × outputs) per experiment. When the solver stops early (a model leaving
    its valid range, e.g. a piston without end stops emptying a chamber), the outputs are
    held at their last computed value: the model is scored on what it predicted, so an
    effect that lets it run through is measured against a finite, honest baseline. NaN
    rows only when nothing was computed."""
    out = []
    for e in exps:
        try:
            out.append(simulate(model, e.inputs, e.t_out, p=p, x0=initial_state(model, e, p), opts=OPTS).Y)
        except HydroError as exc:
            out.append(held_after_failure(getattr(exc, "partial", None), e.t_out.size, len(model.output_names)))
    return out


def held_after_failure(partial, n: int, n_out: int) -> np.ndarray:
    """n × n_out outputs from a partial trajectory, its last row held to the end."""
    Y = np.full((n, n_out), np.nan)
    if partial is not None and len(partial.Y):
        k = min(len(partial.Y), n)
        Y[:k] = partial.Y[:k]
        Y[k:] = partial.Y[k - 1]
    return Y


def used(e: Experiment, o: str) -> np.ndarray:
    """Samples of output o that count: the experiment's mask (sensor clipping, windows)."""
    return e.mask.get(o, np.ones(e.t_out.size, dtype=bool))


def esr_table(model: Model, exps: list[Experiment], Ys: list[np.ndarray], outputs: list[str]) -> dict[str, float]:
    """ESR (%) per output, pooled over the experiments (mean of the per-experiment ESRs)."""
    vals: dict[str, list[float]] = {o: [] for o in outputs}
    for e, Y in zip(exps, Ys):
        for o in outputs:
            if o in e.measured:
                vals[o].append(esr(e.measured[o], Y[:, model.output_names.index(o)], e.mask.get(o)))
    return {o: float(np.mean(v)) if v else float("nan") for o, v in vals.items()}


def total(table: dict[str, float]) -> float:
    return float(np.nansum(list(table.values())))


def residual_series(model: Model, exps: list[Experiment], Ys: list[np.ndarray], outputs: list[str]):
    """{(experiment index, output): ŷ − y} in SI (0 where the experiment masks the output)."""
    out = {}
    for i, (e, Y) in enumerate(zip(exps, Ys)):
        for o in outputs:
            if o in e.measured:
                out[(i, o)] = np.where(used(e, o), Y[:, model.output_names.index(o)] - e.measured[o], 0.0)
    return out


def effective_n(model: Model, exps: list[Experiment], Ys: list[np.ndarray], outputs: list[str]) -> float:
    """Independent samples in a model's residual series: Σ n(1 − ρ₁)/(1 + ρ₁) (AR(1))."""
    return float(sum(effective_samples(np.nan_to_num(r)) for r in residual_series(model, exps, Ys, outputs).values()))


def sensitivities(obj: Objective, p: np.ndarray, index: list[int], steps: list[float],
                  r0: np.ndarray | None = None, memo: dict | None = None) -> np.ndarray:
    """Columns (r(p + h_j e_j) − r(p))/h_j: output sensitivities by forward differences.
    ``memo`` ({(j, h): column}, for one ``p``) keeps columns already simulated: secants taken at
    several sizes of one parameter share every other column."""
    r0 = obj.residuals(p) if r0 is None else r0
    memo = {} if memo is None else memo
    cols = []
    for i, h in zip(index, steps):
        if (i, h) not in memo:
            q = p.copy()
            q[i] += h
            memo[(i, h)] = (obj.residuals(q) - r0) / h
        cols.append(memo[(i, h)])
    return np.column_stack(cols) if cols else np.zeros((r0.size, 0))
