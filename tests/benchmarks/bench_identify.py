"""Benchmark: seed 004's 15-parameter identification, Jacobian from sensitivities vs finite differences.

    python tests/benchmarks/bench_identify.py [--workers 2] [--rtol 1e-6] [--max-evals 2000]
        [--experiment experiments/quickstart/train.yaml]

Fits the fifteen free parameters of machines/eha_testbench.yaml to the training recording
(30 s at 1 kHz; P1, P2, v; least-squares, trust-region reflective) twice in one process:
once with the Jacobian from forward sensitivities integrated with the states (one simulation
per Jacobian), once with forward differences (one simulation per parameter, columns in
``--workers`` threads). Prints wall time, simulations and final cost of each, then the line

    identify speed-up (sensitivities vs finite differences): N.N×

and the held-out ESR with both results. Timings on a shared machine are noisy; the ratio is
measured in one process, back to back.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from hydrocli.experiments.experiment_file import load_experiment  # noqa: E402
from hydrocli.identify.fit import fit  # noqa: E402
from hydrocli.metrics import esr  # noqa: E402
from hydrocli.runner import load_machine, simulate_experiment  # noqa: E402
from hydrocli.solve.library import compiled  # noqa: E402
from hydrocli.solve.sensitivities import sensitivity_library  # noqa: E402
from hydrocli.solve.simulate import SolverOptions  # noqa: E402


def run(model, train, gradient: str, a) -> tuple:
    t0, c0 = time.perf_counter(), time.process_time()
    res = fit(model, [train], method="least-squares", max_evals=a.max_evals, opts=SolverOptions(rtol=a.rtol),
              workers=a.workers, gradient=gradient)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"{gradient:18s}: wall {wall:6.2f} s  CPU {cpu:6.2f} s  simulations {res.n_evals:4d}  "
          f"cost {res.cost_initial:.6g} → {res.cost:.6g}  ({res.message})")
    return res, wall


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--max-evals", type=int, default=2000)
    ap.add_argument("--experiment", default="experiments/quickstart/train.yaml")
    ap.add_argument("--validate", default="experiments/eha/none_validate.yaml")
    a = ap.parse_args()
    _, model = load_machine(ROOT / "machines" / "eha_testbench.yaml")
    train = load_experiment(ROOT / a.experiment, model)
    val = load_experiment(ROOT / a.validate, model)
    compiled(model)
    sensitivity_library(model)          # compile both libraries before timing
    print(f"identify {len(model.free_params)} parameters on {a.experiment} (30 s at 1 kHz), rtol {a.rtol:g}, "
          f"finite differences in {a.workers} thread(s)")
    sens, t_sens = run(model, train, "sensitivities", a)
    fd, t_fd = run(model, train, "finite-differences", a)
    same = "lower" if sens.cost < fd.cost * (1 - 1e-6) else ("same" if sens.cost <= fd.cost * (1 + 1e-3) else "HIGHER")
    print(f"identify speed-up (sensitivities vs finite differences): {t_fd / t_sens:.1f}×  "
          f"(final cost {sens.cost:.6g} vs {fd.cost:.6g}: {same})")
    for label, res in (("sensitivities", sens), ("finite-differences", fd)):
        r = simulate_experiment(model, val, p=res.p)
        dp_m = val.measured["P1"] - val.measured["P2"]
        print(f"  ESR validate ({label}): dp {esr(dp_m, r.outputs['dp']):.3f} %   "
              f"v {esr(val.measured['v'], r.outputs['v']):.3f} %")


if __name__ == "__main__":
    main()
