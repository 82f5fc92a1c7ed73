"""Step 1 of the diagnosis: re-identify the base model (the machine's free parameters plus
the pressure-sensor nuisance lags), warm-started from the file, and judge the estimates.

A parameter is flagged when it ends
* at a bound that is not a natural zero (the data push it out of its range),
* as a bulk modulus far below 1 GPa (hides a compliance, trapped air or a line),
* far (× 3) from the value the machine file gave (it may absorb a missing effect, e.g.
  friction absorbing leakage),
* poorly determined once the standard error is inflated for autocorrelated residuals
  (se·√(N/n_eff) > 50 % of the value).
"""
from __future__ import annotations

import numpy as np

from ..identify.fit import FitResult, fit, sensitivities_available
from ..identify.transforms import FreeParameters
from ..model.model import Model
from .residuals import OPTS

MAX_FAR = 3.0


def identify(model: Model, exps, free=None, p_start=None, iterations: int = 30, progress=None,
             gradient: str = "auto", opts=None, threads: int = 1) -> FitResult:
    """Least squares on ESR-scaled residuals of each experiment's ``fit_outputs``, at most
    ``iterations`` optimiser iterations: the simulation budget is sized for the Jacobian at
    hand (one sensitivity run per iteration, or one run per free parameter when the model has
    no analytic sensitivities), so a budget means the same search either way. ``gradient``:
    "auto" (sensitivities when the model has them) or "finite-differences". ``opts``: solver
    settings (default the diagnosis's ``residuals.OPTS``). ``threads``: the fits the diagnosis
    runs alone (base, restrained, polish, backward steps) split each Jacobian between the
    cores its pool would use; the result does not depend on it."""
    n_free = len(free if free is not None else model.free_params)
    per = 2 if gradient != "finite-differences" and sensitivities_available(model) else n_free + 1
    return fit(model, exps, free, method="least-squares", cost="esr", p_start=p_start,
               max_evals=iterations * per + n_free + 2, opts=opts or OPTS, progress=progress, gradient=gradient,
               polish=False, workers=max(1, int(threads)))


def inflated_stderr(res: FitResult, n_eff: float) -> np.ndarray:
    """Gauss–Newton (white-residual) standard errors × √(N/n_eff), with the diagnosis's n_eff
    (summed over the residual series of the current model) so candidates are compared alike."""
    white = res.stderr if res.stderr_white is None else res.stderr_white
    return white * np.sqrt(max(res.n_residuals, 1) / max(n_eff, 1.0))


def judge(model: Model, res: FitResult, n_eff: float) -> list[dict]:
    fp = FreeParameters.from_model(model, res.names)
    at_bound = set(fp.at_bound(res.estimates))
    se = inflated_stderr(res, n_eff)
    out = []
    for i, name in enumerate(res.names):
        v, v0, lo, hi = res.estimates[i], res.initial[i], fp.lo[i], fp.hi[i]
        info = model.params[model.param_index(name)]
        reasons = []
        if name in at_bound:
            at_low = abs(v - lo) < abs(v - hi)
            natural_zero = at_low and lo <= 0.0     # an optional effect's coefficient at 0: effect absent
            if not natural_zero:
                reasons.append(f"ended at its {'lower' if at_low else 'upper'} bound")
        if info.unit == "Pa" and name.split(".")[-1].startswith("beta") and v < 1.0e9:
            reasons.append(f"bulk modulus {v / 1e9:.2f} GPa is far below 1 GPa: it likely hides a compliance "
                           "(entrained air, hoses, structure)")
        if v0 > 0 and v > 0 and (v / v0 > MAX_FAR or v0 / v > MAX_FAR):
            reasons.append(f"moved ×{v / v0:.2g} from the file's {v0:.4g}: it may absorb a missing effect")
        if np.isfinite(se[i]) and v != 0 and se[i] / abs(v) > 0.5 and abs(v) > 1e-3 * max(abs(hi), abs(lo)):
            reasons.append(f"poorly determined (±{100 * se[i] / abs(v):.0f} %)")
        out.append({"name": name, "value": float(v), "initial": float(v0), "stderr": float(se[i]),
                    "unit": info.unit, "implausible": bool(reasons), "why": "; ".join(reasons)})
    return out
