"""The travel the recordings show: each position or angle output's measured range, and which
of its ends the recording's mask hides (a clipping sensor). The end-stop candidate places its
stops from these, :mod:`.runaway` places stops there when the base cannot follow the record,
and :func:`findings.beyond_training` compares the training's range with the held-out one."""
from __future__ import annotations

import numpy as np

from . import augment, locate, residuals


def output_ranges(model, exps) -> dict[str, tuple[float, float]]:
    """{position or angle output: (min, max) measured over ``exps``}."""
    out = {}
    for o, k in locate.output_quantities(model).items():
        if k in locate.POSITIONS:
            vals = np.concatenate([e.measured[o][residuals.used(e, o)] for e in exps if o in e.measured]
                                  or [np.zeros(1)])
            out[o] = (float(np.min(vals)), float(np.max(vals)))
    return out


CENSOR_NEAR = 0.05   # share of the span: a mask edge this close to an end hides what lies beyond it


def ends(model, exps) -> tuple[dict[str, tuple[float, float]], dict[str, tuple[bool, bool]]]:
    """For each model symbol a position/angle output reads: its measured (min, max), and
    (min censored, max censored). An end is censored when the recording's mask (a clipping
    sensor, samples set aside) starts or stops next to it: the machine may have gone further
    than the samples that count show."""
    ranges, censored = {}, {}
    for o, (lo, hi) in output_ranges(model, exps).items():
        near = CENSOR_NEAR * max(hi - lo, 1e-12)
        c_lo = c_hi = False
        for e in exps:
            if o not in e.measured:
                continue
            u = residuals.used(e, o)
            edges = np.flatnonzero(u[:-1] != u[1:])
            vals = e.measured[o][np.where(u[edges], edges, edges + 1)]
            c_lo |= bool(np.any(vals <= lo + near))
            c_hi |= bool(np.any(vals >= hi - near))
        for s in augment.output_symbols_expr(model, o):
            ranges[s], censored[s] = (lo, hi), (c_lo, c_hi)
    return ranges, censored
