"""Batch identification: fit every experiment separately, over an executor.

Each job ships the built :class:`Model` (it pickles; workers reload the compiled library
from the disk cache) and one :class:`Experiment` to :func:`fit_job`, which returns a small
dict. The executor is anything with ``submit(fn, *args) -> future`` and ``future.result()``:
``hydrocli.executor``: a process pool by default, or a Dask distributed client connected to
``--scheduler tcp://HOST:PORT`` — the same code path. The table has one row per
experiment and rows ``mean``, ``std`` (sample, ddof = 1), ``min``, ``max`` per parameter.
"""
from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import HydroError, IdentifyError, Problem
from ..executor import executor
from ..experiments.experiment import Experiment
from ..model.model import Model
from ..solve.simulate import SolverOptions
from ..solve.library import compiled


def fit_job(model: Model, exp: Experiment, free: list[str] | None, options: dict) -> dict:
    """Run in a worker: fit one experiment; errors come back as data, not exceptions."""
    from .fit import fit
    try:
        res = fit(model, [exp], free, **options)
    except HydroError as err:
        return {"experiment": exp.name, "error": err.render(with_source=False)}
    return {"experiment": exp.name, "names": list(res.names), "estimates": res.estimates.tolist(),
            "stderr": res.stderr.tolist(), "cost": res.cost, "n_evals": res.n_evals, "seconds": res.seconds,
            "warnings": list(res.warnings), "message": res.message}


@dataclass
class BatchResult:
    names: list[str]
    rows: list[dict]                     # one per experiment (fit_job output)

    @property
    def ok(self) -> list[dict]:
        return [r for r in self.rows if "error" not in r]

    def matrix(self) -> np.ndarray:
        return np.array([r["estimates"] for r in self.ok], dtype=float).reshape(len(self.ok), len(self.names))

    def summary(self) -> dict[str, np.ndarray]:
        M = self.matrix()
        if not M.size:
            nan = np.full(len(self.names), np.nan)
            return {"mean": nan, "std": nan, "min": nan, "max": nan}
        std = M.std(axis=0, ddof=1) if M.shape[0] > 1 else np.zeros(M.shape[1])
        return {"mean": M.mean(axis=0), "std": std, "min": M.min(axis=0), "max": M.max(axis=0)}

    def table_rows(self) -> list[list]:
        head = ["experiment", *self.names, "cost", "status"]
        rows = [head]
        for r in self.rows:
            if "error" in r:
                rows.append([r["experiment"], *[""] * len(self.names), "", "failed: " + r["error"].splitlines()[0]])
            else:
                rows.append([r["experiment"], *[f"{v:.6g}" for v in r["estimates"]], f"{r['cost']:.6g}",
                             "ok" if not r["warnings"] else "; ".join(r["warnings"])])
        for k, v in self.summary().items():
            rows.append([k, *[f"{x:.6g}" for x in v], "", ""])
        return rows

    def csv_text(self) -> str:
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(self.table_rows())
        return buf.getvalue()

    def write_csv(self, path: str | Path) -> None:
        from ..netlist.yamldoc import write_atomic
        write_atomic(path, self.csv_text())


def run_batch(model: Model, experiments: list[Experiment], free: list[str] | None = None, *,
              jobs: int = 2, scheduler: str | None = None, options: dict | None = None,
              on_done=None) -> BatchResult:
    """Fit each experiment separately; ``on_done(i, row)`` after each one (in order)."""
    from .transforms import FreeParameters
    names = FreeParameters.from_model(model, free, (options or {}).get("bounds")).names
    opts = dict(options or {})
    opts.setdefault("opts", SolverOptions(rtol=1e-6))
    compiled(model)                      # compile once in the parent; workers load the cached library
    rows = []
    with executor(jobs, scheduler) as ex:
        futures = [ex.submit(fit_job, model, e, free, opts) for e in experiments]
        for i, f in enumerate(futures):
            rows.append(f.result())
            if on_done:
                on_done(i, rows[-1])
    res = BatchResult(names, rows)
    if not res.ok:
        raise IdentifyError(Problem(f"every fit of the batch failed; first: {rows[0]['error']}",
                                    hint="check the experiments and the free parameters' bounds"))
    return res
