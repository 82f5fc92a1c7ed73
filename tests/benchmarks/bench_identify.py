"""Benchmark: seed 004's 15-parameter identification on 30 s of 1 kHz data (plain script).

    cd /work/main && python tests/benchmarks/bench_identify.py [--workers 2] [--rtol 1e-6] [--max-evals 400]

Fits the fifteen free parameters of machines/eha_testbench.yaml to ../shared/recordings/
eha_none/train.csv (P1, P2, v; least-squares, 2-point Jacobian, columns in ``--workers``
threads), then simulates the held-out validate.csv with the identified parameters and prints
ESR of dp and v (noise floor ≈ 0.15 % for dp, 0.04 % for v). Prints wall and CPU seconds,
simulations, seconds per simulation and the target (< 30 s wall on 2 cores).
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
from hydrocli.solve.simulate import SolverOptions  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--max-evals", type=int, default=400)
    a = ap.parse_args()
    _, model = load_machine(ROOT / "machines" / "eha_testbench.yaml")
    train = load_experiment(ROOT / "experiments" / "eha" / "none_train.yaml", model)
    val = load_experiment(ROOT / "experiments" / "eha" / "none_validate.yaml", model)
    compiled(model)
    t0, c0 = time.perf_counter(), time.process_time()
    res = fit(model, [train], method="least-squares", max_evals=a.max_evals, opts=SolverOptions(rtol=a.rtol),
              workers=a.workers)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"identify 15 parameters, eha_none train (30 s at 1 kHz, {res.n_residuals} residuals), "
          f"rtol {a.rtol:g}, {a.workers} Jacobian thread(s)")
    print(f"  wall {wall:.1f} s (target < 30 s on 2 cores)  CPU {cpu:.1f} s  simulations {res.n_evals}  "
          f"wall/simulation {1000 * wall / res.n_evals:.0f} ms  cost {res.cost_initial:.5g} → {res.cost:.5g}")
    print(f"  {res.message}")
    hist = res.cost_history
    for frac in (0.01, 0.001):       # evaluations needed to come within frac of the final cost
        n = next(i + 1 for i, c in enumerate(hist) if c <= res.cost * (1 + frac))
        print(f"  best cost within {100 * frac:g} % of the final after {n} of {len(hist)} evaluations")
    for name, data in (("train", train), ("validate", val)):
        for label, p in (("nominal", model.p0), ("identified", res.p)):
            r = simulate_experiment(model, data, p=p)
            dp_m = data.measured["P1"] - data.measured["P2"]
            print(f"  ESR {name:8s} {label:10s}: dp {esr(dp_m, r.outputs['dp']):.3f} %   "
                  f"v {esr(data.measured['v'], r.outputs['v']):.3f} %")
    for w in res.warnings:
        print(f"  warning: {w}")


if __name__ == "__main__":
    main()
