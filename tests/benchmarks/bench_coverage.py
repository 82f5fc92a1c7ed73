"""Coverage of the 95 % intervals on recordings the project's own model makes (plain script).

    python tests/benchmarks/bench_coverage.py [--n 30] [--duration 2] [--rho 0.9] [--seed 0]

For each of ``--n`` recordings: the EHA (machines/eha_testbench.yaml) with four parameters
(valve.Kv, cylinder.beta, load.m, friction.kv_p) drawn ±15 % around the nominal values,
excited by two sines on the valve and a sine load for ``--duration`` s at 1 kHz, measured with
coloured noise (AR(1) with coefficient ``--rho``; standard deviations of seed 004's sensors).
The four parameters are identified from the nominal values (least squares, Jacobian from
sensitivities, ``assess=True``) and the script counts how often each kind of 95 % interval
contains the true value:

* bootstrap: the moving-block bootstrap interval ``hydro identify`` prints;
* n_eff: ±1.96 standard errors allowing for correlated residuals (AR(1) n_eff);
* white: ±1.96 Gauss–Newton standard errors that assume white residuals;
* window: θ̂ ± t₉ × the cluster-robust standard error of 10 time windows (the model-error
  check's interval).

It also counts the model-error check's flags (false alarms here: these recordings contain no
model error; nominal rate 1 % per parameter). ``--no-polish`` skips the fit's final
Gauss–Newton steps at rtol/100 (to show what the search's integration error does to long
recordings, ``--duration 30``).

Target for the bootstrap interval: 90–99 %. Prints one line per recording and a summary.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from hydrocli.experiments.experiment import Experiment  # noqa: E402
from hydrocli.identify.fit import fit  # noqa: E402
from hydrocli.runner import load_machine  # noqa: E402
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate  # noqa: E402

FREE = ["valve.Kv", "cylinder.beta", "load.m", "friction.kv_p"]
SIGMA = {"P1": 0.15e5, "P2": 0.15e5, "v": 1e-3}


def ar1(rng, n: int, sigma: float, rho: float) -> np.ndarray:
    e = rng.normal(0.0, sigma * np.sqrt(1 - rho ** 2), n)
    out = np.empty(n)
    out[0] = rng.normal(0.0, sigma)
    for i in range(1, n):
        out[i] = rho * out[i - 1] + e[i]
    return out


def recording(model, p, duration: float, rho: float, rng) -> Experiment:
    t = np.arange(int(duration * 1000) + 1) / 1000.0
    ph = rng.uniform(0, 2 * np.pi, 3)
    u = 0.3 * np.sin(2 * np.pi * 0.7 * t + ph[0]) + 0.1 * np.sin(2 * np.pi * 3.1 * t + ph[1])
    cols = {"u": u, "Ps": np.full_like(t, 100e5), "Fext": 400.0 * np.sin(2 * np.pi * 1.3 * t + ph[2])}
    inputs = InputTable(t, np.column_stack([cols[n] for n in model.input_names]))
    Y = simulate(model, inputs, t, p=p, opts=SolverOptions(rtol=1e-9)).Y
    measured = {o: Y[:, model.output_names.index(o)] + ar1(rng, t.size, s, rho) for o, s in SIGMA.items()}
    return Experiment(name="coverage", file="<synthetic>", inputs=inputs, t_out=t, measured=measured,
                      fit_outputs=list(SIGMA))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=30)
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--rho", type=float, default=0.9)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-polish", action="store_true")
    a = ap.parse_args()
    _, model = load_machine(ROOT / "machines" / "eha_testbench.yaml")
    rng = np.random.default_rng(a.seed)
    idx = [model.param_index(n) for n in FREE]
    hits = {"bootstrap": 0, "n_eff": 0, "white": 0, "window": 0}
    flags = 0
    total, t0 = 0, time.perf_counter()
    for k in range(a.n):
        p = model.p0.copy()
        p[idx] *= rng.uniform(0.85, 1.15, len(idx))
        exp = recording(model, p, a.duration, a.rho, rng)
        res = fit(model, [exp], FREE, assess=True, seed=k, polish=not a.no_polish)
        truth = p[idx]
        u = res.uncertainty
        inside = {"bootstrap": (u.ci_lower <= truth) & (truth <= u.ci_upper),
                  "n_eff": np.abs(res.estimates - truth) <= 1.96 * res.stderr,
                  "white": np.abs(res.estimates - truth) <= 1.96 * res.stderr_white,
                  "window": (u.window_lower <= truth) & (truth <= u.window_upper)}
        flags += len(u.window_messages)
        for key, v in inside.items():
            hits[key] += int(v.sum())
        total += len(idx)
        print(f"recording {k + 1:2d}: cost {res.cost:.4g}, {res.n_evals} simulations; inside (bootstrap/n_eff/white): "
              + " ".join(f"{int(inside['bootstrap'][i])}{int(inside['n_eff'][i])}{int(inside['white'][i])}"
                         for i in range(len(idx))), flush=True)
    print(f"\n{a.n} recordings × {len(idx)} parameters = {total} intervals, AR(1) noise ρ = {a.rho}, "
          f"{a.duration:g} s each, {time.perf_counter() - t0:.0f} s")
    for key, h in hits.items():
        print(f"coverage of the 95 % intervals ({key}): {100 * h / total:.1f} % ({h}/{total})")
    print(f"model-error check: {flags} of {total} parameters flagged ({100 * flags / total:.1f} %; none is wrong here)")


if __name__ == "__main__":
    main()
