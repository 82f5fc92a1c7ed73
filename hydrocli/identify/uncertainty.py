"""Uncertainty a user can check: intervals, identifiability, and the estimates' sensitivity to
the parameters the machine file keeps fixed — all from the residual Jacobian J = ∂r/∂θ that
the forward sensitivities give at the optimum.

* **Block-bootstrap intervals** (linearised, moving blocks): residual blocks of length L (ten
  correlation lengths) are resampled within each recorded signal, e*, and mapped to the
  estimate by the Gauss–Newton
  step δθ* = (JᵀJ)⁻¹Jᵀe*; the 2.5 / 97.5 % percentiles of θ̂ + δθ* (taken in the optimiser's
  coordinates, so a log-scaled parameter stays positive) are the 95 % interval. Coloured
  residuals widen the interval through the blocks, not through a model of the noise
  (Künsch 1989, the moving-block bootstrap; Efron & Tibshirani 1993, §9.4, residual
  bootstrap of a regression).
* **Identifiability**: singular values of the scaled Jacobian J·diag(|θ|) (the bounds' width
  for an estimate near zero); a direction v with σ/s_v > 10 % (its relative standard error,
  σ² allowing for correlated residuals) or s_v/s_max < 1e-4 is a combination the data do
  not determine; pairs with |correlation| > 0.95 are named too.
* **Window check (model error)**: the recording is cut into G = 10 contiguous time windows
  per experiment and each window's contribution to the linearised estimate,
  S_g = Σ_{t∈g} J⁺[:, t] r_t (all signals of an instant together), is compared across
  windows. Their spread gives a cluster-robust (sandwich) standard error that allows for any
  dependence inside a window (Bester, Conley & Hansen 2011, with t_{G−1} quantiles); when it
  exceeds the bootstrap's by more than the χ²_{G−1} 99 % point allows, the estimate moves
  between parts of the recording more than the residuals' noise explains — the signature of
  a model error, which no interval built from the residuals can bound. Such parameters are
  named; their window interval (θ̂ ± t_{G−1}·se) is reported beside the bootstrap one.
* **Fixed parameters**: ∂θ̂/∂φ = −(JᵀJ)⁻¹JᵀJ_φ (implicit function theorem at the optimum,
  J_φ = ∂r/∂φ), reported as what a 10 % error in φ does to each estimate, and flagged when
  that shift exceeds two standard errors and 1 % of the estimate.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import special   # quantiles without importing scipy.stats (0.3 s)

from .transforms import FreeParameters

N_BOOT = 400
BLOCK_CORR = 10        # bootstrap blocks: this many correlation lengths (see block_length)
LEVEL = 0.95
SHIFT = 0.10           # "a 10 % error in φ"
CORR_LIMIT = 0.95
N_WINDOWS = 10         # time windows per experiment for the model-error check
WINDOW_ALPHA = 0.01    # the check's false-alarm rate per parameter (χ² test of the variance ratio)


@dataclass
class FixedEffect:
    """What a 10 % error in one fixed parameter does to the estimates."""

    name: str
    value: float
    shift: np.ndarray          # relative change of each estimate for +10 % in the fixed parameter
    worst: str                 # the estimate it moves most (relative to its standard error)
    worst_shift: float         # that estimate's relative change
    sigmas: float              # that change in standard errors
    moved: list[tuple[str, float]] = field(default_factory=list)   # up to three (estimate, relative change)

    def message(self) -> str:
        what = ", ".join(f"{n} by {100 * r:+.1f} %" for n, r in (self.moved or [(self.worst, self.worst_shift)]))
        return (f"a 10 % error in {self.name} moves {what} ({self.sigmas:.0f} standard errors): "
                f"consider freeing {self.name} (--add-free {self.name})")


@dataclass
class Uncertainty:
    ci_lower: np.ndarray
    ci_upper: np.ndarray
    ci_method: str
    singular_values: np.ndarray
    identifiability: list[str] = field(default_factory=list)
    fixed_names: list[str] = field(default_factory=list)
    dtheta_dphi: np.ndarray | None = None      # k × m
    fixed_effects: list[FixedEffect] = field(default_factory=list)   # flagged ones, worst first
    window_lower: np.ndarray | None = None     # θ̂ ± t_{G−1}·se from the time windows (cluster-robust)
    window_upper: np.ndarray | None = None
    window_ratio: np.ndarray | None = None     # window standard error / bootstrap standard error
    window_messages: list[str] = field(default_factory=list)   # parameters the windows disagree on

    def as_dict(self) -> dict:
        """Entries added to the /identify group of the HDF5 result."""
        k = self.ci_lower.size
        fx = [e.name for e in self.fixed_effects]
        return {"ci_lower": self.ci_lower, "ci_upper": self.ci_upper, "ci_level": LEVEL, "ci_method": self.ci_method,
                "singular_values": self.singular_values,
                "identifiability": np.array(self.identifiability or [""], dtype=object),
                "fixed_names": np.array(self.fixed_names or [""], dtype=object),
                "dtheta_dphi": self.dtheta_dphi if self.dtheta_dphi is not None else np.zeros((k, 0)),
                "fixed_sensitive": np.array(fx or [""], dtype=object),
                "fixed_messages": np.array([e.message() for e in self.fixed_effects] or [""], dtype=object),
                "window_lower": self.window_lower if self.window_lower is not None else np.full(k, np.nan),
                "window_upper": self.window_upper if self.window_upper is not None else np.full(k, np.nan),
                "window_ratio": self.window_ratio if self.window_ratio is not None else np.full(k, np.nan),
                "window_messages": np.array(self.window_messages or [""], dtype=object)}


def block_length(n: int, n_eff: float) -> int:
    """Blocks ``BLOCK_CORR`` (10) correlation lengths long (n/n_eff samples per independent
    one), at least n^(1/3), at most a quarter of the signal. A block cuts the correlations
    across its ends: for AR(1) residuals the bootstrap variance is low by Σ|k|R(k)/(L·Σ R(k))
    = 2ρ/(1 − ρ²)/L, half a correlation length over L — 17 % with three correlation lengths
    (the session-3 choice; 80–88 % coverage on 30 s recordings with ρ = 0.9), 5 % with ten."""
    corr_len = n / max(n_eff, 1.0)
    return int(max(1, min(max(np.ceil(n ** (1 / 3)), np.ceil(BLOCK_CORR * corr_len)), n // 4)))


def bootstrap_intervals(J_z: np.ndarray, r: np.ndarray, segments: list[int], z: np.ndarray, fp: FreeParameters,
                        n_eff: float, n_boot: int = N_BOOT, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """95 % moving-block bootstrap intervals in parameter units (see :func:`bootstrap_z`)."""
    lo_z, hi_z = bootstrap_z(J_z, r, segments, z, n_eff, n_boot, seed)
    return _unclipped(fp, lo_z), _unclipped(fp, hi_z)


def bootstrap_z(J_z: np.ndarray, r: np.ndarray, segments: list[int], z: np.ndarray, n_eff: float,
                n_boot: int = N_BOOT, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """95 % moving-block bootstrap intervals in the optimiser's coordinates from the Jacobian
    there, ``J_z``, the residuals ``r`` and the lengths of the recorded signals they are
    stacked from."""
    rng = np.random.default_rng(seed)
    pinv = np.linalg.pinv(J_z)                                   # k × N
    starts, n_total = [], 0
    for n in segments:
        starts.append(n_total)
        n_total += n
    L = block_length(n_total, n_eff)
    draws = np.empty((n_boot, z.size))
    for b in range(n_boot):
        e = np.empty(r.size)
        for s0, n in zip(starts, segments):
            if n == 0:
                continue
            Lb = min(L, n)
            nb = int(np.ceil(n / Lb))
            idx = (rng.integers(0, n - Lb + 1, nb)[:, None] + np.arange(Lb)[None, :]).ravel()[:n]
            seg = r[s0:s0 + n]
            e[s0:s0 + n] = seg[idx] - seg.mean()
        draws[b] = z - pinv @ e
    lo_z, hi_z = np.percentile(draws, [50 * (1 - LEVEL), 50 * (1 + LEVEL)], axis=0)
    return lo_z, hi_z


def window_sums(J_z: np.ndarray, r: np.ndarray, rows: list[tuple[int, np.ndarray]],
                n_windows: int = N_WINDOWS) -> np.ndarray:
    """Each time window's contribution to the linearised estimate, S_g = Σ_{i∈g} J⁺[:, i] r_i
    (k × windows): ``rows`` gives, for each stacked signal, its experiment and the sample
    indices its residuals come from; every experiment is cut into ``n_windows`` contiguous
    windows of equal length, the same for all its signals. −Σ_g S_g is the Gauss–Newton step,
    zero at the optimum."""
    scale = np.linalg.norm(J_z, axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    pinv = np.linalg.pinv(J_z / scale[None, :]) / scale[:, None]         # k × N, columns balanced
    n_exp = 1 + max((e for e, _ in rows), default=-1)
    length = [1] * n_exp
    for e, idx in rows:
        if idx.size:
            length[e] = max(length[e], int(idx.max()) + 1)
    S = np.zeros((J_z.shape[1], n_exp * n_windows))
    start = 0
    for e, idx in rows:
        g = e * n_windows + np.minimum(idx * n_windows // length[e], n_windows - 1)
        contrib = pinv[:, start:start + idx.size] * r[start:start + idx.size][None, :]
        for j in range(S.shape[0]):
            S[j] += np.bincount(g, weights=contrib[j], minlength=S.shape[1])
        start += idx.size
    return S


def window_check(J_z: np.ndarray, r: np.ndarray, rows: list[tuple[int, np.ndarray]], z: np.ndarray,
                 fp: FreeParameters, lo_z: np.ndarray, hi_z: np.ndarray, names: list[str], estimates: np.ndarray,
                 skip: set[str] = frozenset(), n_windows: int = N_WINDOWS, boot_dof: float = np.inf) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """Cluster-robust (time-window) intervals in parameter units, the ratio of their standard
    error to the bootstrap interval's (half width / 1.96, in the optimiser's coordinates) and
    messages for the parameters (not in ``skip``: those at a bound, where the linearisation
    does not hold) whose ratio² exceeds the 99 % point of F(G − 1, ``boot_dof``): the
    bootstrap's variance is itself estimated from a finite number of blocks (``boot_dof``,
    blocks − 1; χ²_{G−1}/(G−1) when there are many)."""
    S = window_sums(J_z, r, rows, n_windows)
    G = S.shape[1]
    k = z.size
    if G < 3:
        nan = np.full(k, np.nan)
        return nan, nan, nan, []
    se_z = np.sqrt(G / (G - 1) * np.sum((S - S.mean(axis=1, keepdims=True)) ** 2, axis=1))
    q = float(special.stdtrit(G - 1, 0.5 + LEVEL / 2))           # t_{G−1} quantile
    lo, hi = _unclipped(fp, z - q * se_z), _unclipped(fp, z + q * se_z)
    se_boot = (hi_z - lo_z) / (2 * float(special.ndtri(0.5 + LEVEL / 2)))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(se_boot > 0, se_z / se_boot, np.nan)
    if np.isfinite(boot_dof) and boot_dof < 1e4:
        limit = np.sqrt(float(special.fdtri(G - 1, max(boot_dof, 1.0), 1 - WINDOW_ALPHA)))   # F upper 1 % point
    else:
        limit = np.sqrt(float(special.chdtri(G - 1, WINDOW_ALPHA)) / (G - 1))   # χ²_{G−1} upper 1 % point
    msgs = []
    for i in np.argsort(-np.nan_to_num(ratio)):
        if not (np.isfinite(ratio[i]) and ratio[i] > limit) or names[i] in skip:
            continue
        est = float(estimates[i])
        rel = f"±{100 * (hi[i] - lo[i]) / 2 / abs(est):.2g} %" if est else f"[{lo[i]:.4g}, {hi[i]:.4g}]"
        msgs.append(f"{names[i]}: its estimate moves between parts of the recording {ratio[i]:.1f}× more than "
                    f"the residuals' noise explains (above {limit:.2f}× in {G} time windows) — a model error its "
                    f"interval cannot show; from the windows alone {rel}")
    return lo, hi, ratio, msgs


def _unclipped(fp: FreeParameters, z: np.ndarray) -> np.ndarray:
    """p(z) without clipping to the bounds (an interval may extend past them)."""
    lin = fp.lo + z * (fp.hi - fp.lo)
    with np.errstate(invalid="ignore", divide="ignore"):
        lg = fp.lo * (fp.hi / np.where(fp.log, fp.lo, 1.0)) ** z
    return np.where(fp.log, lg, lin)


def scales(estimates: np.ndarray, fp: FreeParameters) -> np.ndarray:
    """What "relative" means for each estimate: its magnitude, or the width of its bounds
    when it sits near zero (a leakage identified as none)."""
    span = fp.hi - fp.lo
    return np.where(np.abs(estimates) > 1e-3 * span, np.abs(estimates), span)


def identifiability(J_p: np.ndarray, scale: np.ndarray, names: list[str], sigma2: float,
                    correlation: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Singular values of the scaled Jacobian J·diag(scale) and messages naming what the data
    do not determine."""
    Js = J_p * scale[None, :]
    if Js.size == 0:
        return np.zeros(0), []
    _, s, Vt = np.linalg.svd(Js, full_matrices=False)
    msgs, seen = [], set()
    smax = s[0] if s.size and s[0] > 0 else 1.0
    for sv, v in zip(s, Vt):
        rel_se = np.sqrt(sigma2) / sv if sv > 0 else np.inf
        if rel_se <= 0.10 and sv / smax >= 1e-4:
            continue
        order = np.argsort(-np.abs(v))
        parts = [f"{v[i]:+.2f}·{names[i]}" for i in order[:3] if abs(v[i]) >= 0.2]
        who = [names[i] for i in order[:3] if abs(v[i]) >= 0.2]
        if frozenset(who) in seen:
            continue
        seen.add(frozenset(who))
        what = f"±{100 * rel_se:.0f} %" if np.isfinite(rel_se) else "unbounded"
        if len(who) == 1:
            fix = (f"fix {who[0]} at a datasheet value, or record an experiment whose outputs react to it")
        else:
            fix = (f"fix one of {', '.join(who)}, or record an experiment that excites them differently "
                   f"(another command amplitude, frequency or load)")
        msgs.append(f"not determined by the data: the combination {' '.join(parts)} (relative changes; "
                    f"uncertainty {what}): {fix}")
    k = len(names)
    for i in range(k):
        for j in range(i + 1, k):
            c = correlation[i, j]
            if np.isfinite(c) and abs(c) > CORR_LIMIT:
                msgs.append(f"{names[i]} and {names[j]} are strongly correlated ({c:+.2f}): the data fix a combination "
                            f"of them; fix one, or add an experiment that moves them apart")
    return s, msgs


def fixed_parameter_effects(J_p: np.ndarray, J_phi: np.ndarray, scale: np.ndarray, stderr: np.ndarray,
                            names: list[str], fixed: list[str], values: np.ndarray,
                            skip: set[str] = frozenset()) -> tuple[np.ndarray, list[FixedEffect]]:
    """∂θ̂/∂φ = −(JᵀJ)⁻¹JᵀJ_φ and the fixed parameters whose 10 % error moves an estimate
    (not one in ``skip``, e.g. at a bound) by more than two standard errors and 1 % of its
    ``scale`` (largest relative shift first)."""
    if J_phi.size == 0:
        return np.zeros((len(names), 0)), []
    D = -np.linalg.lstsq(J_p, J_phi, rcond=None)[0]               # k × m
    flagged = []
    for j, (phi, v) in enumerate(zip(fixed, values)):
        dtheta = D[:, j] * SHIFT * v
        rel = dtheta / scale
        with np.errstate(divide="ignore", invalid="ignore"):
            sig = np.where(stderr > 0, np.abs(dtheta) / stderr, np.inf)
        ok = np.isfinite(sig) & (sig > 2.0) & np.array([n not in skip for n in names])
        if not ok.any():
            continue
        i = int(np.argmax(np.where(ok, np.abs(rel), -1.0)))
        if abs(rel[i]) > 0.01:
            top = [q for q in np.argsort(-np.abs(np.where(ok, rel, 0.0)))[:3] if ok[q] and abs(rel[q]) > 0.01]
            flagged.append(FixedEffect(phi, float(v), rel, names[i], float(rel[i]), float(sig[i]),
                                       [(names[q], float(rel[q])) for q in top]))
    flagged.sort(key=lambda e: -abs(e.worst_shift))
    return D, flagged


def fixed_candidates(model, free: list[str]) -> list[str]:
    """Parameters the file keeps fixed that could move the fit: non-zero and not free."""
    return [p.name for p in model.params if not p.free and p.name not in free and p.value != 0.0
            and np.isfinite(p.value)]


def assess_fit(model, res, fp: FreeParameters, z: np.ndarray, J_z: np.ndarray, r: np.ndarray,
               rows: list[tuple[int, np.ndarray]], fixed_jacobian=None, seed: int = 0) -> Uncertainty:
    """All of the above for a finished fit; ``rows``: for each stacked signal, its experiment
    and the sample indices of its residuals; ``fixed_jacobian(names) -> ∂r/∂φ`` (None: skip
    the fixed parameters, e.g. without sensitivities)."""
    d = fp.dp_dz(z)
    J_p = J_z / d[None, :]
    lo_z, hi_z = bootstrap_z(J_z, r, [idx.size for _, idx in rows], z, res.n_effective or r.size, seed=seed)
    lo, hi = _unclipped(fp, lo_z), _unclipped(fp, hi_z)
    lo, hi = np.clip(lo, fp.lo, fp.hi), np.clip(hi, fp.lo, fp.hi)      # the search box holds the parameter
    sigma2 = res.cost / max(res.n_residuals - len(res.names), 1) * r.size / max(res.n_effective or r.size, 1.0)
    scale = scales(res.estimates, fp)
    s, msgs = identifiability(J_p, scale, res.names, sigma2, res.correlation)
    out = Uncertainty(lo, hi, "moving-block bootstrap (linearised)", s, msgs)
    segments = [idx.size for _, idx in rows]
    L = block_length(sum(segments), res.n_effective or r.size)
    blocks = sum(int(np.ceil(n / min(L, n))) for n in segments if n)
    out.window_lower, out.window_upper, out.window_ratio, out.window_messages = \
        window_check(J_z, r, rows, z, fp, lo_z, hi_z, res.names, res.estimates,
                     set(fp.at_bound(res.estimates)), boot_dof=max(blocks - 1, 1))
    if fixed_jacobian is not None:
        fixed = fixed_candidates(model, res.names)
        if fixed:
            J_phi = fixed_jacobian(fixed)
            keep = np.any(J_phi != 0.0, axis=0)
            fixed = [n for n, k in zip(fixed, keep) if k]
            values = np.array([model.p0[model.param_index(n)] if res.p is None else res.p[model.param_index(n)]
                               for n in fixed])
            D, flagged = fixed_parameter_effects(J_p, J_phi[:, keep], scale, res.stderr, res.names, fixed,
                                                 values, set(fp.at_bound(res.estimates)))
            out.fixed_names, out.dtheta_dphi, out.fixed_effects = fixed, D, flagged
    return out
