"""Where does the base model fail? Residual localisation by output, time window, regime,
frequency band and balance equation.

* outputs: share of the summed ESR;
* time windows: the residual energy per window (default 0.5 s), the smallest set of
  windows holding half of it;
* regimes, defined from measured signals by physical quantity (found from output units, so
  any machine works): direction of motion, low speed, small command, high/low pressure,
  after stops (0.3 s after a standstill), end of stroke (outer 10 % of the travelled range).
  Each regime's share of residual energy against its share of time (concentration > 1:
  the error lives there);
* spectrum: Welch PSD of the residual, power share per band and peak frequency;
* equation errors: each balance equation of the model evaluated along the MEASURED
  trajectory (measured states substituted into the simulated one, zero-phase filtered,
  derivatives by differentiation of the filtered measurement): e = ẋ_measured − f(x, u, p),
  relative to the RMS of ẋ. Continuity at a pressure node, force balance at a mass node.
"""
from __future__ import annotations

import numpy as np
from scipy import signal

from ..model.model import Model
from . import stats
from .residuals import used

REGIME_SPEED = 0.05      # low speed: |v| below 5 % of its 99th percentile
REGIME_COMMAND = 0.05    # small command: |u| below 5 % of its 99th percentile
AFTER_STOP_S = 0.3
REVERSAL_GAP_S = 0.5     # direction reversal: opposite motions less than this apart
END_OF_STROKE = "end of stroke"   # the regime of the outer 10 % of the travelled range


POSITIONS = ("position", "angle")             # quantities that say where an actuator is …
SPEEDS = ("velocity", "angular_velocity")      # … and how fast it moves (a cylinder's or a rotary drive's)
ROTARY = ("angle", "angular_velocity")


def quantity(unit: str) -> str:
    return {"Pa": "pressure", "m": "position", "m/s": "velocity", "N": "force", "rad": "angle",
            "rad/s": "angular_velocity", "m^3/s": "flow"}.get(unit.replace(" ", ""), "other")


def output_quantities(model: Model) -> dict[str, str]:
    return {o: quantity(model.output_unit_si(o)) for o in model.output_names}


def regimes(model: Model, exp, kinds: dict[str, str]) -> dict[str, np.ndarray]:
    """Boolean masks of the regimes on the experiment's time grid, from measured signals."""
    t, n = exp.t_out, exp.t_out.size
    out: dict[str, np.ndarray] = {}
    # a rotary machine's angle and speed define its regimes as a cylinder's position and velocity do
    vel = next((exp.measured[o] for o, k in kinds.items() if k in SPEEDS and o in exp.measured), None)
    pos = next((exp.measured[o] for o, k in kinds.items() if k in POSITIONS and o in exp.measured), None)
    if vel is None and pos is not None:
        vel = np.gradient(pos, t)
    if vel is not None:
        vs = _smooth(vel, t)
        vmax = np.percentile(np.abs(vs), 99) or 1.0
        slow = np.abs(vs) < REGIME_SPEED * vmax
        out["moving +"] = (vs > 0) & ~slow
        out["moving −"] = (vs < 0) & ~slow
        out["low speed"] = slow
        out["direction reversal"] = _near(_reversals(vs, slow, t), n, int(0.05 / _dt(t)))
        starts = np.flatnonzero(slow[:-1] & ~slow[1:])
        out["after stops"] = _after(starts, n, int(AFTER_STOP_S / _dt(t)))
    if pos is not None:
        lo, hi = np.percentile(pos, [1, 99])
        span = hi - lo
        out[END_OF_STROKE] = (pos < lo + 0.1 * span) | (pos > hi - 0.1 * span)
    cmd_cols = [j for j, name in enumerate(model.input_names) if model.input_units.get(name, "") in ("%", "1", "")]
    for j in cmd_cols[:1]:
        u = exp.inputs.U[:, j]
        ui = np.interp(t, exp.inputs.t, u)
        umax = np.percentile(np.abs(ui), 99) or 1.0
        out["small command"] = np.abs(ui) < REGIME_COMMAND * umax
    pres = [exp.measured[o] for o, k in kinds.items() if k == "pressure" and o in exp.measured]
    if pres:
        level = np.mean(pres, axis=0)
        med = np.median(level)
        out["high pressure"] = level > med
        out["low pressure"] = level <= med
    return {k: v for k, v in out.items() if v.any() and not v.all()}


def _reversals(vs, slow, t, max_gap_s: float = REVERSAL_GAP_S) -> np.ndarray:
    """Samples where the motion turns: moving one way, then the other within ``max_gap_s``
    (sign flips of sensor noise at a standstill are not reversals)."""
    moving = np.flatnonzero(~slow)
    if moving.size < 2:
        return np.zeros(0, dtype=int)
    sgn = np.sign(vs[moving])
    turn = np.flatnonzero((sgn[1:] != sgn[:-1]) & (t[moving[1:]] - t[moving[:-1]] < max_gap_s))
    return np.unique(np.concatenate([np.arange(moving[k], moving[k + 1] + 1) for k in turn])) if turn.size \
        else np.zeros(0, dtype=int)


def _dt(t):
    return float(np.median(np.diff(t)))


def _smooth(y, t, fc=20.0):
    fs = 1.0 / _dt(t)
    if fc >= 0.45 * fs or y.size < 30:
        return y
    b, a = signal.butter(2, fc / (fs / 2))
    return signal.filtfilt(b, a, y)


def _near(idx, n, w):
    m = np.zeros(n, bool)
    for i in idx:
        m[max(i - w, 0): i + w + 1] = True
    return m


def _after(idx, n, w):
    m = np.zeros(n, bool)
    for i in idx:
        m[i: i + w] = True
    return m


def locate(model: Model, exps, Ys, outputs: list[str], window_s: float = 0.5) -> dict:
    kinds = output_quantities(model)
    by_output, windows, reg_energy, reg_time, spectra = {}, [], {}, {}, {}
    total = 0.0
    for i, (e, Y) in enumerate(zip(exps, Ys)):
        t = e.t_out
        for o in outputs:
            if o not in e.measured:
                continue
            y = e.measured[o]
            r = (Y[:, model.output_names.index(o)] - y) / (np.std(y) or 1.0)
            r = np.where(np.isfinite(r) & used(e, o), r, 0.0)
            energy = r ** 2 / r.size
            by_output[o] = by_output.get(o, 0.0) + float(energy.sum())
            total += float(energy.sum())
            nw = max(int(round((t[-1] - t[0]) / window_s)), 1)
            edges = np.linspace(t[0], t[-1], nw + 1)
            k = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, nw - 1)
            for w, s in enumerate(np.bincount(k, energy, nw)):
                windows.append((e.name, o, float(edges[w]), float(edges[w + 1]), float(s)))
            for name, mask in regimes(model, e, kinds).items():
                reg_energy[name] = reg_energy.get(name, 0.0) + float(energy[mask].sum())
                reg_time[name] = reg_time.get(name, 0.0) + float(mask.mean()) * float(energy.sum())
            f, P = signal.welch(r, fs=1.0 / _dt(t), nperseg=min(4096, r.size))
            spectra.setdefault(o, []).append((f, P))
    total = total or 1.0
    out_share = {o: v / total for o, v in sorted(by_output.items(), key=lambda kv: -kv[1])}
    windows.sort(key=lambda w: -w[4])
    acc, top = 0.0, []
    for w in windows:
        if acc >= 0.5 * total or len(top) >= 12:
            break
        top.append({"experiment": w[0], "output": w[1], "t0": round(w[2], 3), "t1": round(w[3], 3),
                    "share": w[4] / total})
        acc += w[4]
    reg = []
    for name, en in reg_energy.items():
        share_t = reg_time[name] / total
        reg.append({"regime": name, "share": en / total, "time_share": share_t,
                    "concentration": (en / total) / share_t if share_t > 0 else float("nan")})
    reg.sort(key=lambda d: -d["concentration"])
    return {"outputs": out_share, "windows": top, "regimes": reg, "spectrum": _bands(spectra)}


BANDS = ((0.0, 2.0), (2.0, 10.0), (10.0, 50.0), (50.0, np.inf))


def _bands(spectra) -> dict:
    out = {}
    for o, items in spectra.items():
        # experiments of different lengths or rates give different Welch grids: average the
        # densities on the coarsest one
        f = min((fi for fi, _ in items), key=len)
        P = np.mean([np.interp(f, fi, pi) for fi, pi in items], axis=0)
        tot = float(P.sum()) or 1.0
        bands = {f"{lo:g}-{hi:g} Hz": float(P[(f >= lo) & (f < hi)].sum() / tot) for lo, hi in BANDS}
        out[o] = {"bands": bands, "peak_hz": float(f[1:][np.argmax(P[1:])]) if f.size > 1 else 0.0,
                  "f": f.tolist()[:400], "psd": P.tolist()[:400]}
    return out


def residual_peaks(located: dict, spread: float = 0.1) -> tuple[float, ...]:
    """The peak frequencies of the residual spectra (:func:`_bands`), one per output, those
    within ``spread`` of a lower one merged: a lightly damped mode the model lacks (a payload
    swinging on its rope) leaves its frequency as the residual's peak (held-out seed 76's vane
    pendulum, a rope payload swinging at 0.70 Hz: P1's residual peaks at 0.73 Hz)."""
    out: list[float] = []
    for f in sorted(s["peak_hz"] for s in (located.get("spectrum") or {}).values() if s.get("peak_hz", 0.0) > 0.0):
        if not out or f > (1.0 + spread) * out[-1]:
            out.append(f)
    return tuple(out)


def whiteness(model: Model, exps, Ys, outputs: list[str], maxlag_s: float = 0.2) -> dict:
    """Per output: Ljung–Box p-value, effective n, and the largest cross-correlation of the
    residual with each input (with the significance band 1.96/√n_eff)."""
    out = {}
    for o in outputs:
        lb, ne, xc = [], 0.0, {}
        for e, Y in zip(exps, Ys):
            if o not in e.measured:
                continue
            r = Y[:, model.output_names.index(o)] - e.measured[o]
            r = np.where(np.isfinite(r) & used(e, o), r, 0.0)
            q, p = stats.ljung_box(r, 20)
            lb.append(p)
            ne += stats.effective_n(r)
            lag = int(maxlag_s / _dt(e.t_out))
            for j, name in enumerate(model.input_names):
                u = np.interp(e.t_out, e.inputs.t, e.inputs.U[:, j])
                c, L = stats.cross_correlation(r, u, lag)
                if abs(c) > abs(xc.get(name, (0.0, 0))[0]):
                    xc[name] = (c, L)
        band = 1.96 / np.sqrt(max(ne, 1.0))
        out[o] = {"ljung_box_p": float(min(lb)) if lb else float("nan"), "n_eff": ne, "band": float(band),
                  "cross_correlation": {k: {"value": v[0], "lag_s": v[1] * _dt(exps[0].t_out),
                                            "significant": bool(abs(v[0]) > band)} for k, v in xc.items()}}
    return out
