"""The candidates' re-identification on the diagnosis's executor, one fit per pool task.

A candidate is fitted from one to four starts (:func:`workers._fit_starts`: effect off, its
best start with the effect present, each base, each basin), a switching effect from each on
sensitivities AND on finite differences; the lowest final cost wins. Run as one task per
candidate, the pool's workers idled behind the longest candidate: on the shared
``eha_valve_overlap`` recording (30 s) a rod–load link's four fits took 112 s on one worker
while the other finished the rest of the round in 85 s. So the work runs in three phases,
each a batch on the same executor:

1. :func:`plan` per candidate: its start vectors and the gradients each start is fitted
   with (the starts' costs are a few simulations), and the time of one simulation;
2. :func:`fit_start` per (candidate, start, gradient): one least-squares fit, submitted
   longest first by an estimate (simulation time × simulations per iteration), so the
   workers finish together — with more workers (``--scheduler``) a round takes about as
   long as its longest single fit;
3. :func:`finish` per candidate: the lowest cost wins (the first in start order among
   equal costs, as one sequential loop had it), idle stops are withdrawn, the winner is
   scored on training and held-out data.

The result of every candidate is the one a single sequential fit loop gives (each fit is
deterministic and independent of the others); only the wall time changes.
"""
from __future__ import annotations

import time

import numpy as np

from . import baseline, residuals
from .workers import _fit_starts, model_from_text, run_all, warm_vector, withdraw_idle_stops

FD = "finite-differences"


def plan(job: dict) -> dict:
    """Phase 1: the start vectors of a candidate's fit, the gradients each is fitted with
    ("both": sensitivities and finite differences, see ``engine.Settings.switching_gradient``)
    and the seconds one simulation of the candidate takes (for ordering the fits).

    The new parameters start from the best of: effect off, the probe value, and the
    Gauss–Newton step of the screening regression (so an effect far from zero is reached in
    few iterations) — from two of them when "off" costs least — each with the base parameters
    where the current fit has them and where the machine file (``job["drawing"]``) has them
    (:func:`workers._fit_starts`)."""
    try:
        model = model_from_text(job["text"], job["file"])
        p = warm_vector(model, job["names"], job["values"])
        names = set(model.param_names)
        drawn = model.param_vector({n: v for n, v in (job.get("drawing") or {}).items() if n in names}, base=p)
        obj = residuals.objective(model, job["train"])
        t0 = time.perf_counter()
        starts = _fit_starts(obj, p, model, job.get("starts") or [{}], drawn, job.get("each_base", False),
                             job.get("basins") or {}, job.get("transfers") or [], job.get("stops") or [])
        sim_s = (time.perf_counter() - t0) / max(obj.n_evals, 1)
        g = job.get("gradient", "auto")
        return {"key": job["key"], "error": None, "starts": starts, "n_free": len(model.free_params),
                "grads": ["auto", FD] if g == "both" else [g], "sim_s": sim_s}
    except Exception as exc:  # a candidate that cannot be built or simulated is reported, not fatal
        return {"key": job["key"], "error": f"{type(exc).__name__}: {exc}"}


def fit_start(task: dict) -> dict:
    """Phase 2: one fit of a candidate (``task["job"]``) from ``task["start"]`` with
    ``task["gradient"]``; the FitResult without its Jacobian (the pool sends results back)."""
    job = task["job"]
    try:
        model = model_from_text(job["text"], job["file"])
        res = baseline.identify(model, job["train"], p_start=task["start"], iterations=job["max_evals"],
                                gradient=task["gradient"])
        res.jacobian = None
        return {"error": None, "result": res}
    except Exception as exc:
        return {"error": f"{type(exc).__name__}: {exc}"}


def best(fits: list[dict]) -> tuple[object, str | None]:
    """(the lowest-cost result of ``fits``, None) — in start order, the first among equal
    costs — or (None, the first failed fit's error) when any failed (a sequential loop over
    the starts stopped there)."""
    failed = next((f["error"] for f in fits if f["error"] is not None), None)
    if failed is not None:
        return None, failed
    res = None
    for f in fits:
        if res is None or f["result"].cost < res.cost:
            res = f["result"]
    return res, None


def finish(job: dict) -> dict:
    """Phase 3: the best of the candidate's fits (``job["fits"]``, in start order), its idle
    stops withdrawn (:func:`workers.withdraw_idle_stops`), scored on training and held-out data."""
    res, failed = best(job["fits"])
    if failed is not None:
        return {"key": job["key"], "error": failed}
    try:
        model = model_from_text(job["text"], job["file"])
        obj = residuals.objective(model, job["train"])
        withdrawn = withdraw_idle_stops(obj, model, res, job.get("stops") or [])
        Ytr = residuals.simulate_outputs(model, job["train"], res.p)
        Yva = residuals.simulate_outputs(model, job["validate"], res.p)
        # standard errors inflated by THIS fit's residual autocorrelation: a candidate that
        # takes up the structured misfit leaves whiter residuals, and more independent samples,
        # than the model it starts from (ΔBIC keeps the current model's n_eff, so candidates
        # are ranked alike)
        n_own = residuals.effective_n(model, job["train"], Ytr, job["outputs"])
        return {"key": job["key"], "error": None, "names": res.names, "estimates": res.estimates.tolist(),
                "stderr": baseline.inflated_stderr(res, n_own).tolist(), "cost": res.cost, "n_eff": n_own,
                "correlation": None if res.correlation is None else np.asarray(res.correlation).tolist(),
                "p": res.p, "param_names": model.param_names, "seconds": res.seconds,
                "esr_train": residuals.esr_table(model, job["train"], Ytr, job["outputs"]),
                "esr_train_each": [residuals.total(residuals.esr_table(model, [e], [Y], job["outputs"]))
                                   for e, Y in zip(job["train"], Ytr)],
                "esr_validation": residuals.esr_table(model, job["validate"], Yva, job["outputs"]),
                "withdrawn": withdrawn}
    except Exception as exc:
        return {"key": job["key"], "error": f"{type(exc).__name__}: {exc}"}


def estimated_seconds(pl: dict, gradient: str, iterations: int) -> float:
    """A fit's expected time, for ordering only: simulations per optimiser iteration (finite
    differences: one per free parameter and the step; sensitivities: one run costing about
    six plain runs plus 0.3 per column, docs/identify.md, and the step) × one simulation's time."""
    n = pl["n_free"]
    per = n + 2 if gradient == FD else 8 + 0.3 * n
    return pl["sim_s"] * per * iterations


def fit_all(jobs: list[dict], pool=None, progress=None, what: str = "candidate") -> list[dict]:
    """Every candidate of ``jobs`` re-identified (the three phases above); results in the jobs'
    order, each as :func:`finish` returns it. ``progress`` is told "{what} starts k/n",
    "{what} fits done k/n" (one per start and Jacobian), "{what} fits scored k/n"."""
    plans = run_all(plan, jobs, pool, progress=progress, what=f"{what} starts")
    # listed candidate by candidate, each in start order (then Jacobian): the order finish() reads
    tasks = [{"cand": i, "job": job, "start": q, "gradient": g} for i, (job, pl) in enumerate(zip(jobs, plans))
             if pl["error"] is None for q in pl["starts"] for g in pl["grads"]]
    order = sorted(range(len(tasks)), key=lambda k: -estimated_seconds(plans[tasks[k]["cand"]], tasks[k]["gradient"],
                                                                       tasks[k]["job"]["max_evals"]))
    done = run_all(fit_start, [tasks[k] for k in order], pool, progress=progress, what=f"{what} fits done")
    fits: dict[int, list] = {}
    for k, f in sorted(zip(order, done), key=lambda kf: kf[0]):       # back in the listed order
        fits.setdefault(tasks[k]["cand"], []).append(f)
    ends = run_all(finish, [dict(job, fits=fits[i]) for i, job in enumerate(jobs) if plans[i]["error"] is None],
                   pool, progress=progress, what=f"{what} fits scored")
    ends = iter(ends)
    return [next(ends) if pl["error"] is None else pl for pl in plans]
