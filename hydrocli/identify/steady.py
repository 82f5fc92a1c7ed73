"""Steady-state identification from plateaus (seed 000 §5.1–5.2, eqs. 27–28 and 34).

Seed 000 calibrates static characteristics first — friction from steady cylinder forces,
valve/CBV parameters from steady flows — by minimising the squared deviation between measured
and modelled *steady* values, before any dynamic fit. Here:

1. ``detect_plateaus``: samples where every watched signal (the fitted outputs and the inputs)
   stays within ``tol`` × its overall range over a window of ``min_duration``; consecutive
   samples form a plateau; its first ``skip`` fraction is dropped (transient tail);
2. each plateau becomes a tiny experiment: inputs frozen at the plateau means, initial state
   from the plateau means of the outputs that read states directly, and one comparison
   sample after ``settle`` seconds — a short settle simulation per plateau. This is sound for
   any machine (no algebraic solve of the network is needed, and states that keep moving on a
   plateau, such as a position at constant speed, simply are not fitted);
3. ``fit`` minimises Σ_plateaus Σ_outputs ((ŷ − ȳ)/s_o)² with s_o the spread (standard
   deviation) of output o across plateaus — weighted least squares (eq. 27/34 summed).
"""
from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d

from ..errors import IdentifyError, Problem
from ..experiments.experiment import Experiment
from ..model.model import Model
from ..solve.simulate import InputTable


def detect_plateaus(t: np.ndarray, signals: dict[str, np.ndarray], min_duration: float = 0.3,
                    tol: float = 0.02, skip: float = 0.3) -> list[tuple[int, int]]:
    """Index ranges [i0, i1) where all signals are steady (see module docstring)."""
    dt = float(np.median(np.diff(t)))
    w = max(int(round(min_duration / dt)), 3)
    ok = np.ones(t.size, dtype=bool)          # ok[i]: the window [i, i + w) is steady for every signal
    ok[t.size - w + 1:] = False
    for y in signals.values():
        y = np.asarray(y, float)
        span = float(np.nanmax(y) - np.nanmin(y))
        if not np.isfinite(span) or span == 0.0:
            continue
        yf = np.where(np.isfinite(y), y, np.nanmean(y))
        rng = maximum_filter1d(yf, w, origin=-(w // 2)) - minimum_filter1d(yf, w, origin=-(w // 2))
        ok &= rng <= tol * span
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
    out = []
    for a, b in zip(edges[::2], edges[1::2]):      # a run of steady window starts → samples [a, b - 1 + w)
        i0, i1 = int(a), int(min(b - 1 + w, t.size))
        out.append((int(i0 + skip * (i1 - i0)), i1))
    return out


def plateau_experiments(model: Model, exp: Experiment, plateaus, outputs: list[str],
                        settle: float = 0.3) -> list[Experiment]:
    """One small experiment per plateau (inputs frozen at their means, one comparison sample)."""
    out = []
    for k, (i0, i1) in enumerate(plateaus):
        ti = exp.inputs.t
        sel = (ti >= exp.t_out[i0]) & (ti <= exp.t_out[i1 - 1])
        u = exp.inputs.U[sel].mean(axis=0) if sel.any() else exp.inputs.U[np.searchsorted(ti, exp.t_out[i0])]
        measured = {o: np.full(2, np.nanmean(y[i0:i1])) for o, y in exp.measured.items()}
        mask = {o: np.array([False, o in outputs]) for o in measured}
        out.append(Experiment(name=f"{exp.name}_plateau{k + 1}", file=exp.file,
                              inputs=InputTable(np.array([0.0]), u.reshape(1, -1)), t_out=np.array([0.0, settle]),
                              measured=measured, mask=mask, initial=dict(exp.initial),
                              fit_outputs=list(outputs)))
    return out


def steady_weights(plateau_exps: list[Experiment], outputs: list[str]) -> dict[str, float]:
    w = {}
    for o in outputs:
        vals = np.array([e.measured[o][1] for e in plateau_exps])
        s = float(np.std(vals)) if vals.size > 1 else 0.0
        s = s if s > 0 else max(abs(float(np.mean(vals))), 1e-12)
        w[o] = 1.0 / s
    return w


def fit_steady(model: Model, experiments: list[Experiment], free: list[str] | None = None, *,
               outputs: list[str] | None = None, min_duration: float = 0.3, tol: float = 0.02,
               settle: float = 0.3, steady_signals: list[str] | None = None, **fit_kwargs):
    """Fit static characteristics to plateau averages; returns (FitResult, plateau experiments)."""
    from .fit import fit
    plateau_exps = []
    for exp in experiments:
        outs = outputs or exp.fit_outputs or list(exp.measured)
        watch = {o: exp.measured[o] for o in (steady_signals or outs) if o in exp.measured}
        for j, n in enumerate(model.input_names):
            if steady_signals is None or n in steady_signals:
                watch[n] = np.interp(exp.t_out, exp.inputs.t, exp.inputs.U[:, j])
        plateaus = detect_plateaus(exp.t_out, watch, min_duration, tol)
        plateau_exps += plateau_experiments(model, exp, plateaus, outs, settle)
    outs = outputs or experiments[0].fit_outputs or list(experiments[0].measured)
    free_n = len(free or model.free_params)
    if len(plateau_exps) * len(outs) < free_n:
        raise IdentifyError(Problem(f"found {len(plateau_exps)} steady plateau(s), too few to fit {free_n} parameter(s)",
                                    hint="record longer constant-command steps, or relax the plateau tolerance "
                                         "(stage keys 'plateau_tol', 'min_duration')"))
    res = fit(model, plateau_exps, free, cost="wls", outputs=outs, weights=steady_weights(plateau_exps, outs),
              **fit_kwargs)
    return res, plateau_exps
