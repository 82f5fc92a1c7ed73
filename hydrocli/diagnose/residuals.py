"""Simulated outputs, residuals and ESR of a parameter vector on a set of experiments —
the shared numerical core of screening and acceptance. Residuals are those of the
identification cost (``identify.cost``, ESR scaling: r = (ŷ − y)/(std(y)·√N)), so the
sum of squares is Σ ESR/100 and sensitivities are comparable across outputs."""
from __future__ import annotations

import numpy as np

from ..errors import HydroError
from ..experiments.experiment import Experiment
from ..identify.cost import Objective, make_targets
from ..metrics import esr
from ..model.model import Model
from ..solve.simulate import SolverOptions, simulate

OPTS = SolverOptions(rtol=1e-5)


def objective(model: Model, exps: list[Experiment], outputs: list[str]) -> Objective:
    return Objective(model, make_targets(model, exps, outputs, "esr"), OPTS)


def simulate_outputs(model: Model, exps: list[Experiment], p: np.ndarray) -> list[np.ndarray]:
    """Y (samples × outputs) per experiment; NaN rows when the solver fails."""
    out = []
    for e in exps:
        try:
            out.append(simulate(model, e.inputs, e.t_out, p=p, x0=e.x0(model), opts=OPTS).Y)
        except HydroError:
            out.append(np.full((e.t_out.size, len(model.output_names)), np.nan))
    return out


def esr_table(model: Model, exps: list[Experiment], Ys: list[np.ndarray], outputs: list[str]) -> dict[str, float]:
    """ESR (%) per output, pooled over the experiments (mean of the per-experiment ESRs)."""
    vals: dict[str, list[float]] = {o: [] for o in outputs}
    for e, Y in zip(exps, Ys):
        for o in outputs:
            if o in e.measured:
                vals[o].append(esr(e.measured[o], Y[:, model.output_names.index(o)]))
    return {o: float(np.mean(v)) if v else float("nan") for o, v in vals.items()}


def total(table: dict[str, float]) -> float:
    return float(np.nansum(list(table.values())))


def residual_series(model: Model, exps: list[Experiment], Ys: list[np.ndarray], outputs: list[str]):
    """{(experiment index, output): ŷ − y} in SI."""
    out = {}
    for i, (e, Y) in enumerate(zip(exps, Ys)):
        for o in outputs:
            if o in e.measured:
                out[(i, o)] = Y[:, model.output_names.index(o)] - e.measured[o]
    return out


def sensitivities(obj: Objective, p: np.ndarray, index: list[int], steps: list[float],
                  r0: np.ndarray | None = None) -> np.ndarray:
    """Columns (r(p + h_j e_j) − r(p))/h_j: output sensitivities by forward differences."""
    r0 = obj.residuals(p) if r0 is None else r0
    cols = []
    for i, h in zip(index, steps):
        q = p.copy()
        q[i] += h
        cols.append((obj.residuals(q) - r0) / h)
    return np.column_stack(cols) if cols else np.zeros((r0.size, 0))
