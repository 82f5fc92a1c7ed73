"""Staged identification (seed 000 §5): a stages file lists fits run one after another,
each starting from the parameters the previous stages identified.

Stages file (YAML; paths relative to the stages file)::

    stages:
      - name: static friction and valve gain       # seed 000 §5.1–5.2: steady first
        mode: steady                               # plateau averages (identify/steady.py)
        free: [valve.Kv, friction.kv_p, friction.kv_m]   # or {valve.Kv: [1e-7, 2e-6]}
        experiments: [../experiments/eha/none_train.yaml]
        outputs: [v, dp]
        settle: 0.3 s                              # steady only; also min_duration, plateau_tol
      - name: dynamics
        free: [cylinder.beta, load.m]
        experiments: [../experiments/eha/none_train.yaml]
        method: least-squares                      # also cost, outputs, max_evals
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DataError, Location, Problem
from ..model.model import Model
from ..netlist import yamldoc as Y
from ..units import to_si
from .fit import FitResult

STAGE_KEYS = ("name", "mode", "free", "experiments", "method", "cost", "outputs", "max_evals", "settle",
              "min_duration", "plateau_tol", "steady_signals")


@dataclass
class Stage:
    name: str
    free: list[str]
    bounds: dict[str, tuple[float, float]]
    experiments: list[str]
    mode: str = "dynamic"
    method: str = "least-squares"
    cost: str = "esr"
    outputs: list[str] | None = None
    max_evals: int = 400
    steady: dict = field(default_factory=dict)


def load_stages(path: str | Path, model: Model) -> list[Stage]:
    path = Path(path)
    try:
        doc, _ = Y.load_file(path)
    except Exception as exc:
        if hasattr(exc, "problems"):
            raise DataError(exc.problems) from None
        raise
    file = str(path)
    items = doc.get("stages")
    if not Y.is_seq(items) or not items:
        raise DataError(Problem("a stages file needs 'stages:' with a list of stages", Location(file, 1, 1),
                                "see 'hydro identify --help' and docs/experiments.md"))
    out = []
    for i, st in enumerate(items):
        loc = Y.item_loc(items, i, file, f"stages[{i}]")
        if not Y.is_map(st):
            raise DataError(Problem("each stage must be a mapping", loc))
        for k in st:
            if k not in STAGE_KEYS:
                raise DataError(Problem(f"unknown stage key '{k}'", Y.key_loc(st, k, file), f"keys: {', '.join(STAGE_KEYS)}"))
        free, bounds = [], {}
        raw = st.get("free") or []
        for name in raw:
            model.param_index(str(name))           # unknown names: NetlistError with a suggestion
            free.append(str(name))
            if Y.is_map(raw) and raw[name] is not None:
                unit = model.params[model.param_index(str(name))].unit
                lo, hi = (to_si(v, unit, location=Y.value_loc(raw, name, file), what=f"{name} bounds") for v in raw[name])
                bounds[str(name)] = (lo, hi)
        exps = [str((path.parent / str(e)) if not Path(str(e)).is_absolute() else e) for e in (st.get("experiments") or [])]
        if not free or not exps:
            raise DataError(Problem("a stage needs 'free:' parameters and 'experiments:'", loc))
        mode = str(st.get("mode", "dynamic"))
        if mode not in ("dynamic", "steady"):
            raise DataError(Problem(f"stage mode '{mode}'", Y.value_loc(st, "mode", file), "use dynamic or steady"))
        outs = st.get("outputs")
        steady = {}
        for k, conv in (("settle", "s"), ("min_duration", "s")):
            if k in st:
                steady[k] = to_si(st[k], conv, location=Y.value_loc(st, k, file), what=k)
        if "plateau_tol" in st:
            steady["tol"] = float(st["plateau_tol"])
        if "steady_signals" in st:
            steady["steady_signals"] = [str(x) for x in st["steady_signals"]]
        out.append(Stage(name=str(st.get("name") or f"stage {i + 1}"), free=free, bounds=bounds, experiments=exps,
                         mode=mode, method=str(st.get("method", "least-squares")), cost=str(st.get("cost", "esr")),
                         outputs=[str(o) for o in outs] if outs else None, max_evals=int(st.get("max_evals", 400)),
                         steady=steady))
    return out


def run_stages(model: Model, stages: list[Stage], load, p_start: np.ndarray | None = None, *,
               opts=None, progress=None, workers: int = 1, on_stage=None) -> tuple[np.ndarray, list[FitResult]]:
    """Run the stages in order; ``load(path) -> list[Experiment]``; returns the final parameter
    vector and each stage's FitResult. ``on_stage(i, stage)`` is called before each."""
    from .fit import fit
    from .steady import fit_steady
    p = model.p0 if p_start is None else np.asarray(p_start, float)
    results = []
    for i, st in enumerate(stages):
        if on_stage:
            on_stage(i, st)
        exps = [e for path in st.experiments for e in load(path)]
        kw = dict(method=st.method, max_evals=st.max_evals, p_start=p, opts=opts, progress=progress,
                  bounds=st.bounds, workers=workers)
        if st.mode == "steady":
            res, _ = fit_steady(model, exps, st.free, outputs=st.outputs, **st.steady, **kw)
        else:
            res = fit(model, exps, st.free, cost=st.cost, outputs=st.outputs, **kw)
        results.append(res)
        p = res.p
        if res.interrupted:
            break
    return p, results


def combine(results: list[FitResult], stages: list[Stage]) -> dict:
    """The /identify tree of a staged run: the last estimate of every parameter at the top,
    each stage's full record under ``stages/<k>_<name>``."""
    last: dict[str, int] = {}
    for k, r in enumerate(results):
        for n in r.names:
            last[n] = k
    names = list(last)
    pick = lambda attr: np.array([getattr(results[last[n]], attr)[results[last[n]].names.index(n)] for n in names])
    tree = {"names": np.array(names, dtype=object), "estimates": pick("estimates"), "stderr": pick("stderr"),
            "initial": pick("initial"),
            "lower": pick("lower"), "upper": pick("upper"),
            "cost_history": np.concatenate([r.cost_history for r in results]),
            "cost": results[-1].cost, "cost_initial": results[0].cost_initial, "method": "staged",
            "message": "; ".join(f"{s.name}: {r.message}" for s, r in zip(stages, results)),
            "n_evals": int(sum(r.n_evals for r in results)), "seconds": float(sum(r.seconds for r in results)),
            "interrupted": int(any(r.interrupted for r in results)),
            "warnings": np.array([w for r in results for w in r.warnings] or [""], dtype=object),
            "stages": {f"{k + 1}_{s.name.replace('/', '_')}": r.as_dict() for k, (s, r) in enumerate(zip(stages, results))}}
    return tree
