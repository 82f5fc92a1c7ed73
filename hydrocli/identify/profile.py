"""Profile-likelihood intervals: refits with one parameter held at trial values.

For a parameter θ_i the profile cost is C_i(θ_i) = min over the other free parameters of the
least-squares cost. The 95 % interval is where C_i − Ĉ stays below χ²₁(95 %)·σ², with
σ² = Ĉ/(N − k)·N/n_eff the residual variance per sample inflated for correlated residuals
(the same n_eff as the printed standard errors), i.e. the likelihood-ratio interval of a
Gaussian model with that variance (Venzon & Moolgavkar 1988; Raue et al. 2009 for dynamic
models). Unlike the linearised bootstrap it follows the cost's curvature: a parameter whose
cost rises steeply on one side and barely on the other (a Stribeck velocity) gets an
asymmetric interval, one that reaches a bound only when the data allow it.

The refits must reproduce the optimum's cost far more precisely than Δ, which is small next to
the cost (5·10⁻⁵ of it on the 30 s EHA fit): a refit started at the estimate measures that
precision, and an interval whose refits miss by more than 0.2 Δ is marked unreliable.

The crossing is found on each side from the linearised half width: the profile cost grows
about quadratically, so h ← h·√(Δ/(C_i(θ̂ + h) − Ĉ)) converges in two or three refits. Each
refit starts from the linear prediction of the other parameters' shift, −(J_oᵀJ_o)⁻¹J_oᵀJ_i·h,
and is polished like the fit, so the costs compare at the tight tolerance.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import special

from .cost import Objective, make_targets
from .fit import FitResult, fit
from .transforms import FreeParameters

LEVEL = 0.95
MAX_REFITS = 4          # per side
TOL = 0.15              # accept a crossing within ±15 % of the threshold Δ
PRECISION = 0.2         # a refit's cost must reproduce the fit's within this fraction of Δ


@dataclass
class ProfileInterval:
    name: str
    lower: float
    upper: float
    refits: int
    points: list[tuple[float, float]] = field(default_factory=list)   # (value, profile cost − Ĉ)
    at_bound: tuple[bool, bool] = (False, False)
    precision: float = 0.0     # |refit at the estimate − the fit's cost| / Δ: above PRECISION, unreliable

    @property
    def reliable(self) -> bool:
        return self.precision <= PRECISION


def threshold(res: FitResult, level: float = LEVEL) -> float:
    """Δ = χ²₁(level)·σ², σ² = Ĉ/(N − k)·N/n_eff."""
    n, k = res.n_residuals, len(res.names)
    n_eff = res.n_effective or n
    sigma2 = res.cost / max(n - k, 1) * n / max(n_eff, 1.0)
    return float(special.chdtri(1, 1 - level)) * sigma2


def profile_intervals(model, experiments, res: FitResult, names: list[str] | None = None, *,
                      bounds: dict | None = None, level: float = LEVEL, max_evals: int = 60,
                      progress=None, **fit_kw) -> list[ProfileInterval]:
    """Profile-likelihood intervals of ``names`` (default: every free parameter of ``res``).
    ``fit_kw`` are the original fit's options (cost, outputs, weights, opts, gradient, workers)
    so the refits minimise the same cost; ``max_evals`` caps each refit's simulations."""
    fp = FreeParameters.from_model(model, res.names, bounds)
    z_hat = fp.to_z(res.estimates)
    d = fp.dp_dz(z_hat)
    J_z = res.jacobian * d[None, :] if res.jacobian is not None else None
    delta = threshold(res, level)
    out = []

    def refit(others, p):
        if others:
            return fit(model, experiments, others, p_start=p, bounds=bounds, max_evals=max_evals, **fit_kw).cost
        # one free parameter: the profile is the cost itself
        from ..solve.simulate import SolverOptions
        from dataclasses import replace

        from .fit import POLISH_RTOL
        opts = fit_kw.get("opts") or SolverOptions(rtol=1e-6)
        obj = Objective(model, make_targets(model, experiments, fit_kw.get("outputs"), fit_kw.get("cost", "esr"),
                                            fit_kw.get("weights")), replace(opts, rtol=opts.rtol * POLISH_RTOL))
        return obj.cost(p)

    for name in (names or res.names):
        i = res.names.index(name)
        others = [n for n in res.names if n != name]
        se_z = res.stderr[i] / d[i] if d[i] > 0 and np.isfinite(res.stderr[i]) and res.stderr[i] > 0 else 0.05
        shift = None
        if J_z is not None and others:
            o = [j for j in range(len(res.names)) if j != i]
            shift = -np.linalg.lstsq(J_z[:, o], J_z[:, i], rcond=None)[0]        # dz_o/dz_i along the valley
        # the reference: the same refit at the estimate, so that what the refits leave of the
        # optimisation (their stopping rule, the polish) cancels in the rise; how far it lands
        # from the fit's own cost measures the refits' precision
        c_hat = refit(others, res.p)
        noise = abs(c_hat - res.cost)
        c_hat = min(c_hat, res.cost)
        points, refits, ends, hits = [], 1, [], []
        for side in (-1.0, 1.0):
            room = z_hat[i] if side < 0 else 1.0 - z_hat[i]
            h = min(float(special.ndtri(0.5 + level / 2)) * se_z, room)
            found, last = None, None
            for _ in range(MAX_REFITS):
                if h <= 0:
                    break
                z = z_hat.copy()
                z[i] = z_hat[i] + side * h
                if shift is not None:
                    o = [j for j in range(len(res.names)) if j != i]
                    z[o] = np.clip(z_hat[o] + shift * side * h, 0.0, 1.0)
                p = fp.full_vector(res.p, fp.from_z(z))
                cost = refit(others, p)
                refits += 1
                if progress:
                    progress(name, refits)
                rise = cost - c_hat
                points.append((float(fp.from_z(z)[i]), float(rise)))
                last = (h, rise)
                if rise < 0:                         # a better optimum than the fit's: measure from it
                    c_hat, rise = cost, 0.0
                if abs(rise - delta) <= TOL * delta:
                    found = min(h * np.sqrt(delta / rise), room)     # the last correction needs no refit
                    break
                if rise <= 0:
                    h_new = 2.0 * h
                else:
                    h_new = h * np.sqrt(delta / rise)
                    h_new = min(max(h_new, 0.25 * h), 4.0 * h)
                if h >= room and h_new >= room:      # the cost stays below the threshold up to the bound
                    found = room
                    break
                h = min(h_new, room)
            if found is None:
                found = last[0] if last is not None else 0.0
                if last is not None and last[1] > 0:
                    found = min(last[0] * np.sqrt(delta / last[1]), room)
            hits.append(found >= room - 1e-12)
            ends.append(float(fp.from_z(np.clip(z_hat + side * found * np.eye(len(z_hat))[i], 0.0, 1.0))[i]))
        out.append(ProfileInterval(name, min(ends), max(ends), refits, sorted(points), (hits[0], hits[1]),
                                   noise / delta))
    return out
