"""Short-horizon prediction: force, flow and valve laws judged where a simulation of the whole
record cannot follow the machine.

A breakaway that makes the position loop hunt (stick–slip) is a limit cycle. The rod sticks
and slips at moments that a small error in the chamber pressures shifts, so an output-error
fit of the breakaway, replayed over the whole record, loses the cycles' phase and predicts the
held-out record worse than the base model, even at the truth's own values (docs/diagnose.md
§ Session 37). The prediction-error view (Ljung, *System Identification*, §7.2–7.3; Bock's
multiple shooting) re-synchronises the model with the machine: every window of ``WINDOW_S``
starts from the measured state (each measured state from its low-passed measurement, the others
from the base model's simulation, :func:`.equations.hybrid_trajectory`) and the model predicts
only that window's outputs. Shorter than a stick–slip cycle, a window leaves no room for the
phase to drift, and a law that acts when the rod breaks away predicts when it does.

Used when the whole-record rounds end with the held-out error well above the noise and no
candidate passing (the verdict would be ``unexplained_mismatch``): every candidate that adds
no state (its model's states are the base's, so the window's start is measured or simulated
alike: friction and seal laws, leak laws, valve-edge laws, stops) is fitted on the training
windows with its own parameters and those of the element it attaches to, next to a control
that fits the same base parameters alone. A candidate stands when it predicts the HELD-OUT
windows better than its control in a one-sided paired t-test over the windows (each window
restarts from the measurement, so windows are nearly independent), at ``ALPHA`` shared between
the candidates tested (Bonferroni); when it removes at least ``MIN_GAIN`` of their error; when it
lowers the BIC of the training windows (each window counted as one independent sample); and when
it predicts the held-out windows better than holding every output at its measured start (the
same paired test: a model that cannot beat persistence shows nothing on 50 ms). A sensor's lag is not
tested (:func:`state_free`). The best such law whose model, run over the whole held-out record,
still follows the recorded travel (:func:`wandered`) is named; the whole-record ESR it reaches
is reported as it is, worse or not.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats as sps
from scipy.optimize import minimize

from ..errors import HydroError, SolverError
from ..identify.transforms import FreeParameters
from ..model.model import Model
from ..solve.simulate import simulate
from . import augment, findings, locate, measurement, residuals, stats
from .candidates import Candidate, catalogue
from .equations import hybrid_trajectory
from .residuals import OPTS, used
from .stage import Setup, Settings, Stage, context, log, make_stage
from .workers import model_from_text, parameter_rows, run_all, warm_vector

WINDOW_S = 0.05      # s: a few spool time constants, shorter than a stick–slip cycle
FC_START_HZ = 100.0  # the measured states at a window's start: low-passed this far (noise vs. a slip's speed)
ALPHA = 1e-3         # the paired test's level, shared between the candidates tested
# and the share of the held-out windows' error a named law must remove: a law that fits a sticking
# rod's breakaway removes most of it (dev lift and counterbalanced lift breakaways: 44–68 %); laws
# that merely tune the windows' starts remove a few per cent (a pressure sensor's lag 3–8 %, a leak
# < 1 %; on a vane pendulum whose missing payload swing has states of its own, every law < 1 %)
MIN_GAIN = 0.10
TRAVEL_ESR = 1.0     # %: a named law's whole-record model must keep the positions this close (wandered)
FAILED = 10.0        # a window the model cannot simulate costs this many times its outputs' variance
FEV = 20             # the window fits' budget: this many cost evaluations per parameter (and one)


@dataclass
class Windows:
    """One experiment cut into windows: each window's first sample, its start state (by the
    base model's state names) and the measured outputs."""
    exp: object
    starts: np.ndarray          # sample index of each window's start
    length: int                 # samples per window (the end sample included: length + 1)
    x0: np.ndarray              # windows × base states
    states: list[str]
    outputs: list[str]
    scale: dict[str, float]     # each output's measured standard deviation


def windows_of(model: Model, exps: list, p: np.ndarray, outputs: list[str], window_s: float = WINDOW_S) -> list[Windows]:
    """Each experiment cut into back-to-back windows of ``window_s``, started on the hybrid
    trajectory of ``model`` at ``p`` (measured states low-passed at ``FC_START_HZ``)."""
    out = []
    for e in exps:
        h = hybrid_trajectory(model, e, p, FC_START_HZ)
        n = e.t_out.size
        step = max(2, int(round(window_s * h.fs)))
        starts = np.arange(0, n - step, step)
        outs = [o for o in outputs if o in e.measured]
        out.append(Windows(e, starts, step, h.X[starts].copy(), [s.name for s in model.states], outs,
                           {o: float(np.nanstd(e.measured[o])) or 1.0 for o in outs}))
    return out


def thinned(w: Windows) -> Windows:
    """Every other window: the fits' search runs on half the training windows, scored on all."""
    return Windows(w.exp, w.starts[::2], w.length, w.x0[::2], w.states, w.outputs, w.scale)


def _scaled(w: Windows, o: str, seg: slice, yhat: np.ndarray | None) -> np.ndarray:
    """(ŷ − y)/σ_y of output ``o`` over one window, 0 where the recording's mask sets a sample
    aside or a value is missing; ``FAILED`` throughout when the model could not be simulated."""
    y = w.exp.measured[o][seg]
    r = np.full(y.shape, FAILED) if yhat is None else (yhat - y) / w.scale[o]
    return np.where(np.isfinite(r) & used(w.exp, o)[seg], r, 0.0)


def window_residuals(model: Model, p: np.ndarray, ws: list[Windows]) -> tuple[np.ndarray, np.ndarray]:
    """(the scaled prediction residuals of every window, concatenated; each window's cost):
    r = (ŷ − y)/σ_y per output, over all windows together scaled by 1/√(samples)."""
    rs, costs = [], []
    col = {o: model.output_names.index(o) for w in ws for o in w.outputs}
    total = sum(w.starts.size * (w.length + 1) for w in ws)
    for w in ws:
        order = [w.states.index(s.name) for s in model.states]
        for k, s0 in enumerate(w.starts):
            seg = slice(s0, s0 + w.length + 1)
            tw = w.exp.t_out[seg]
            try:
                Y = simulate(model, w.exp.inputs, tw, p=p, x0=w.x0[k, order], opts=OPTS).Y
            except HydroError:
                Y = None
            r = np.concatenate([_scaled(w, o, seg, None if Y is None else Y[:, col[o]]) for o in w.outputs]) \
                / np.sqrt(total)
            rs.append(r)
            costs.append(float(r @ r))
    return np.concatenate(rs), np.array(costs)


def fit_bounded(fun, start: np.ndarray, lo: np.ndarray, hi: np.ndarray, logs: np.ndarray, max_fev: int) -> np.ndarray:
    """Σ fun² minimised over a box by Powell's derivative-free search, each parameter on its own
    scale (log where it is a log-scaled companion). A window's cost jumps where a slip moves by a
    sample: finite differences see those jumps rather than the slope (a Gauss–Newton search from
    the lift's breakaway stopped at once, its steps 1e-10), a line search does not."""
    start = np.clip(start, lo, hi)
    logs = logs & (start > 0) & (lo > 0)
    scale = np.where(np.abs(start) > 0, np.abs(start), np.maximum(np.abs(hi - lo) * 1e-3, 1e-12))

    def theta(z):
        return np.where(logs, start * np.exp(np.clip(z, -50, 50)), start + scale * z)

    with np.errstate(divide="ignore", invalid="ignore"):
        zlo = np.where(logs, np.log(np.where(logs, lo, 1.0) / np.where(logs, start, 1.0)), (lo - start) / scale)
        zhi = np.where(logs, np.log(np.where(logs, hi, 1.0) / np.where(logs, start, 1.0)), (hi - start) / scale)
    bounds = [(float(a) if np.isfinite(a) else None, float(b) if np.isfinite(b) else None) for a, b in zip(zlo, zhi)]

    def cost(z):
        r = fun(theta(z))
        return float(r @ r)
    sol = minimize(cost, np.zeros(start.size), method="Powell", bounds=bounds,
                   options={"maxfev": max_fev, "xtol": 1e-3, "ftol": 1e-4})
    return theta(sol.x)


def fit_one(job: dict) -> dict:
    """A worker: the model of ``job["text"]`` fitted on (every other of) the training windows
    over ``job["names"]``, Powell from the better of ``job["starts"]`` (a probe can be far
    worse than "off"); its costs on every window of both sets."""
    try:
        model = model_from_text(job["text"], job["file"])
        p = warm_vector(model, job["base_names"], job["base_values"])
        idx = [model.param_index(n) for n in job["names"]]
        if idx:
            fp = FreeParameters.from_model(model, job["names"])
            lo, hi = np.asarray(fp.lo, float), np.asarray(fp.hi, float)
            fitted = [thinned(w) for w in job["train"]]

            def fun(theta):
                q = p.copy()
                q[idx] = theta
                return window_residuals(model, q, fitted)[0]
            first = min((np.clip(np.asarray(s, float), lo, hi) for s in job["starts"]),
                        key=lambda s: float(np.sum(fun(s) ** 2)))
            p[idx] = fit_bounded(fun, first, lo, hi, np.asarray(job["logs"], bool), job["max_fev"])
        return {"key": job["key"], "names": job["names"], "values": p[idx].tolist(), "p": p, "error": None,
                "train": window_residuals(model, p, job["train"])[1],
                "validate": window_residuals(model, p, job["validate"])[1]}
    except Exception as exc:   # a candidate that cannot be built or simulated is reported, not fatal
        return {"key": job["key"], "error": f"{type(exc).__name__}: {exc}"}


def persistence_costs(ws: list[Windows]) -> np.ndarray:
    """Each window's cost when every output is held at its measured value at the window's start:
    the prediction that knows no physics. A model that does not beat it on the held-out windows
    has shown nothing on them (a base model far off — seed 76's vane against its bumper — and
    a law that stills the machine would pass against it)."""
    total = sum(w.starts.size * (w.length + 1) for w in ws)
    out = []
    for w in ws:
        for s0 in w.starts:
            seg = slice(s0, s0 + w.length + 1)
            r = np.concatenate([_scaled(w, o, seg, np.full(w.length + 1, w.exp.measured[o][s0]))
                                for o in w.outputs])
            out.append(float(r @ r) / total)
    return np.array(out)


def paired_gain(control: np.ndarray, cand: np.ndarray) -> tuple[float, float]:
    """(held-out gain 1 − Σcand/Σcontrol, one-sided p of the paired t-test that the candidate's
    windows cost less)."""
    d = control - cand
    gain = float(1.0 - cand.sum() / control.sum()) if control.sum() > 0 else 0.0
    if d.size < 3 or not np.any(d):
        return gain, 1.0
    sd = float(np.std(d, ddof=1))
    if sd == 0:
        return gain, 0.0 if d.mean() > 0 else 1.0
    t = float(d.mean()) / (sd / np.sqrt(d.size))
    return gain, float(sps.t.sf(t, d.size - 1))


def state_free(cands: list[Candidate], texts: dict[str, str], model: Model, machine: str) -> list[Candidate]:
    """The candidates whose models have exactly the base model's states, a sensor's lag
    excepted: a window starts the sensor on its own reading, so a slower sensor holds that
    reading longer and predicts a short window better the slower it is, whatever the machine
    does (held-out seed 76's vane with a bumper at its end of travel, P1 68 % off on the whole
    record: a pressure sensor's lag gained 91 % on the windows)."""
    names = {s.name for s in model.states}
    out = []
    for c in cands:
        if c.key in texts and c.effect not in measurement.EFFECTS:
            try:
                m = model_from_text(texts[c.key], machine)
            except Exception:      # reported by the round already
                continue
            if {s.name for s in m.states} == names:
                out.append(c)
    return out


def _attached(c: Candidate, free: list[str]) -> list[str]:
    """The base's free parameters of the element the candidate attaches to (a breakaway's
    Coulomb and viscous terms, a leak's cylinder volumes): refitted with it and in its control."""
    new = {q.name for q in c.params}
    return [n for n in free if n.startswith(f"{c.component}.") and n not in new]


def _starts(c: Candidate, base: list[float]) -> list[list[float]]:
    """The base's values with the effect off (every new parameter at its start), and with the
    new primaries at their probe (the companions at their start)."""
    return [base + [q.start for q in c.params], base + [q.probe if q.primary else q.start for q in c.params]]


def judge_windows(machine: str, model: Model, p: np.ndarray, free: list[str], base_text: str, train: list,
                  validate: list, outputs: list[str], cands: list[Candidate], texts: dict[str, str], pool=None,
                  progress=None, window_s: float = WINDOW_S) -> dict:
    """Every state-free candidate and its control fitted on the training windows and scored on
    the held-out ones: {"window_s", "windows", "rows": [...], "best": row or None} with rows
    {"key", "effect", "component", "names", "values", "gain_train", "gain_validation",
    "p_value", "passed"} sorted by held-out gain."""
    wtr = windows_of(model, train, p, outputs, window_s)
    wva = windows_of(model, validate, p, outputs, window_s)
    tested = state_free(cands, texts, model, machine)
    common = {"file": machine, "base_names": list(model.param_names), "base_values": p, "train": wtr, "validate": wva}
    jobs, controls = [], {}
    for c in tested:
        names = _attached(c, free)
        ctl = f"control: {', '.join(names) or 'nothing refitted'}"
        if ctl not in controls:
            controls[ctl] = names
            base = [float(p[model.param_index(n)]) for n in names]
            jobs.append(dict(common, key=ctl, text=base_text, names=names, starts=[base], logs=[False] * len(names),
                             max_fev=FEV * (len(names) + 1)))
        all_names = names + [q.name for q in c.params]
        jobs.append(dict(common, key=c.key, text=texts[c.key], names=all_names,
                         starts=_starts(c, [float(p[model.param_index(n)]) for n in names]),
                         logs=[False] * len(names) + [bool(q.log) for q in c.params], max_fev=FEV * (len(all_names) + 1),
                         control=ctl))
    if progress is not None:
        progress(f"  short-horizon test: {len(tested)} candidate(s) without states of their own, "
                 f"{sum(w.starts.size for w in wva)} held-out windows of {1e3 * window_s:.0f} ms…")
    fits = {f["key"]: f for f in run_all(fit_one, [{k: v for k, v in j.items() if k != "control"} for j in jobs], pool,
                                         progress=progress, what="short-horizon fits")}
    alpha = ALPHA / max(len(tested), 1)
    still = persistence_costs(wva)
    rows = []
    for j in jobs:
        if "control" not in j:
            continue
        c = next(x for x in tested if x.key == j["key"])
        f, ctl = fits[c.key], fits[j["control"]]
        if f.get("error") or ctl.get("error"):
            rows.append({"key": c.key, "effect": c.effect, "component": c.component, "passed": False,
                         "error": f.get("error") or ctl.get("error")})
            continue
        gain, pv = paired_gain(ctl["validate"], f["validate"])
        _, pv_still = paired_gain(still, f["validate"])
        gain_tr = float(1.0 - f["train"].sum() / ctl["train"].sum()) if ctl["train"].sum() > 0 else 0.0
        # BIC on the training windows, each window one independent sample: it restarts from the
        # measurement, while the samples within it are as correlated as the model's error
        dbic = stats.delta_bic(float(ctl["train"].sum()), float(f["train"].sum()), float(f["train"].size), len(c.params))
        rows.append({"key": c.key, "effect": c.effect, "component": c.component, "names": f["names"],
                     "values": f["values"], "p": f["p"], "gain_train": gain_tr, "gain_validation": gain, "p_value": pv,
                     "cost_validation_control": float(ctl["validate"].sum()),
                     "cost_validation": float(f["validate"].sum()),
                     "p_value_persistence": pv_still, "delta_bic": dbic,
                     "reasons": [why for failed, why in (
                         (gain < MIN_GAIN, f"gains {100 * gain:.1f} % < {100 * MIN_GAIN:.0f} % of the held-out windows' error"),
                         (dbic >= 0, f"ΔBIC of the training windows {dbic:+.0f}"),
                         (pv >= alpha, f"not better than its control (p = {pv:.2g})"),
                         (pv_still >= alpha, f"not better than holding the outputs at their first reading (p = {pv_still:.2g})"))
                         if failed]})
        rows[-1]["passed"] = not rows[-1]["reasons"]
    rows.sort(key=lambda r: -r.get("gain_validation", -np.inf))
    best = next((r for r in rows if r["passed"]), None)
    return {"window_s": window_s, "windows": int(sum(w.starts.size for w in wva)), "alpha": alpha, "rows": rows,
            "best": best, "cost_validation_persistence": float(still.sum())}


def wandered(esr_validation: dict[str, float], kinds: dict[str, str]) -> list[str]:
    """The position and angle outputs a model run over the whole held-out record no longer
    follows (validation ESR above ``TRAVEL_ESR``). A law that mends a limit cycle shifts when the
    rod slips, not where the machine goes: the seed 71, 72 and 76 lifts' breakaways kept x within
    0.0001–0.022 %. A law that wins on the windows while the whole record wanders off (held-out
    seed 76's counterbalanced lift with a delayed command: a valve overlap, x 29 → 190 %) mends
    a local symptom of something the windows cannot hold (a delay's own states)."""
    return [o for o, q in kinds.items() if q in locate.POSITIONS and o in esr_validation
            and esr_validation[o] > TRAVEL_ESR]


def needed(st: Settings, accepted: list[dict], esr_validation: dict, noise: dict, located: dict) -> bool:
    """Run the test? Only when nothing was named (no candidate, no base-fit finding) and the
    held-out error stays above the noise (the verdict would be an unexplained mismatch)."""
    return bool(st.short_horizon and not accepted and findings.unexplained(esr_validation, noise, located))


def round_(su: Setup, stage: Stage, located: dict, st: Settings, pool=None,
           progress=None) -> tuple[dict | None, Stage | None, dict]:
    """The short-horizon test from ``stage`` (see the module's docstring): (the accepted entry
    and its stage, or None and None; the test's record for diagnosis.json)."""
    cands, _ = catalogue(context(su, stage, located))
    cands = [c for c in cands if not st.only or c.effect in st.only]
    texts = {}
    for c in cands:
        try:
            texts[c.key] = augment.text_of(c.build(stage.net))
        except Exception:       # reported by the whole-record round already
            continue
    log(progress, "no candidate passes on the whole record and the held-out error stays above the noise: "
                  "testing the state-free laws on short windows that each start from the measured state…")
    try:
        res = judge_windows(su.machine, stage.model, stage.p, list(stage.free), augment.text_of(stage.net), su.train,
                            su.validate, su.outputs, cands, texts, pool, progress)
    except SolverError as e:
        # the windows start on the model's own run along each recording; a model that leaves its
        # valid range there (a stroke overrun on the held-out record) gives them no start
        why = f"not run: the model cannot simulate a recording ({e.problems[0].message})"
        log(progress, f"  short-horizon test {why}")
        return None, None, {"skipped": why}
    record = {"window_s": res["window_s"], "windows_validation": res["windows"], "alpha": res["alpha"],
              "min_gain": MIN_GAIN, "cost_validation_persistence": res["cost_validation_persistence"]}
    kinds = locate.output_quantities(stage.model)
    best = new = None
    for row in (r for r in res["rows"] if r["passed"]):
        model_c = model_from_text(texts[row["key"]], su.machine)
        p_c = np.asarray(row["p"], float)
        free_c = list(model_c.free_params)
        aug = augment.set_values(augment.reload(stage.net, texts[row["key"]]),
                                 {n: p_c[model_c.param_index(n)] for n in free_c})
        trial = make_stage(aug, model_c, p_c, residuals.objective(model_c, su.train).cost(p_c), free_c, su.train,
                           su.validate, su.outputs)
        lost = wandered(trial.esr_validation, kinds)
        row["travel_esr_validation"] = {o: trial.esr_validation[o] for o in lost} or None
        if not lost:
            best, new = row, trial
            break
        log(progress, f"  {row['effect']} gains {100 * row['gain_validation']:.0f} % on the held-out windows, but "
                      "its model, run over the whole record, leaves the recorded travel (" +
            ", ".join(f"{o} {trial.esr_validation[o]:.3g} %" for o in lost) + "): not named")
    record["rows"] = [{k: v for k, v in r.items() if k not in ("p", "key")} for r in res["rows"]]
    if best is None:
        top = res["rows"][0] if res["rows"] else None
        if top is not None and not top["passed"]:
            log(progress, f"  no law passes on the windows (best {top['effect']}: "
                          f"{'; '.join(top.get('reasons') or [top.get('error', '')])})")
        return None, None, record
    c = next(x for x in cands if x.key == best["key"])
    others = [r for r in res["rows"] if r.get("passed") and r["effect"] != c.effect]
    entry = {"key": c.key, "effect": c.effect, "component": c.component, "source": "short_horizon",
             "description": c.description,
             "parameters": parameter_rows(c.params, dict(zip(best["names"], best["values"])), {}, ()),
             "delta_bic": best["delta_bic"],
             "esr_train_before": stage.esr_train, "esr_train_after": new.esr_train,
             "esr_validation_before": stage.esr_validation, "esr_validation_after": new.esr_validation,
             "short_horizon": {"window_s": res["window_s"], "windows_validation": res["windows"],
                               "cost_validation_before": best["cost_validation_control"],
                               "cost_validation_after": best["cost_validation"],
                               "gain_validation": best["gain_validation"], "gain_train": best["gain_train"],
                               "p_value": best["p_value"], "delta_bic": best["delta_bic"]},
             "alternatives": [{"effect": r["effect"], "component": r["component"],
                               "gain_validation": r["gain_validation"]} for r in others]}
    log(progress, f"  {c.effect} on '{c.component}' predicts the held-out windows "
                  f"{100 * best['gain_validation']:.0f} % better (paired test p = {best['p_value']:.2g}); "
                  f"whole-record validation ESR {residuals.total(stage.esr_validation):.3g} → "
                  f"{residuals.total(new.esr_validation):.3g} %")
    return entry, new, record
