"""Shared test helpers and fixtures: the seed-004 EHA machine and recordings the tests simulate
themselves (imported by tests/identify/conftest.py and tests/experiments/conftest.py)."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
EHA = ROOT / "machines" / "eha_testbench.yaml"


@pytest.fixture(scope="session", autouse=True)
def _cache_dir(tmp_path_factory):
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("hydro_cache")))


@pytest.fixture(scope="session")
def eha():
    from hydrocli.runner import load_machine
    from hydrocli.solve.library import compiled
    net, model = load_machine(EHA)
    compiled(model)
    return net, model


def excitation(model, duration=4.0, rate=1000.0, u_amp=30.0, seed=0):
    """A designed input table: two sines on the valve, 100 bar supply, a sine load."""
    from hydrocli.solve.simulate import InputTable
    t = np.arange(int(duration * rate) + 1) / rate
    rng = np.random.default_rng(seed)
    ph = rng.uniform(0, 2 * np.pi, 2)
    u = 0.01 * (u_amp * np.sin(2 * np.pi * 0.5 * t + ph[0]) + 0.3 * u_amp * np.sin(2 * np.pi * 2.3 * t + ph[1]))
    cols = {"u": u, "Ps": np.full_like(t, 100e5), "Fext": 400.0 * np.sin(2 * np.pi * 1.1 * t)}
    return InputTable(t, np.column_stack([cols[n] for n in model.input_names]))


def synthetic(model, p, duration=4.0, seed=0, noise=True, name="synthetic", u_amp=30.0):
    """An Experiment whose measurements are the model's own outputs (+ sensor noise)."""
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.solve.simulate import SolverOptions, simulate
    inputs = excitation(model, duration, u_amp=u_amp, seed=seed)
    x0 = model.x0.copy()
    traj = simulate(model, inputs, inputs.t, p=p, x0=x0, opts=SolverOptions(rtol=1e-8))
    rng = np.random.default_rng(seed + 100)
    sigma = {"P1": 0.15e5, "P2": 0.15e5, "x": 5e-6, "v": 1e-3, "dp": 0.2e5}
    measured = {}
    for j, o in enumerate(model.output_names):
        y = traj.Y[:, j].copy()
        if noise:
            y += rng.normal(0.0, sigma.get(o, 0.0), y.size)
        measured[o] = y
    return Experiment(name=name, file="<synthetic>", inputs=inputs, t_out=inputs.t.copy(), measured=measured,
                      fit_outputs=["P1", "P2", "v"])


def write_csv(path, exp, model):
    cols = ["t[s]"] + [f"{n}[1]" for n in model.input_names] + [f"{o}[1]" for o in ("P1", "P2", "x", "v")]
    U = exp.inputs.U
    data = np.column_stack([exp.t_out, U] + [exp.measured[o] for o in ("P1", "P2", "x", "v")])
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="", fmt="%.9g")
    return path


# Two first-order lags in series, gain k of the first and time constant of the second free:
# the small machine of the fit, profile and model-error tests (closed-form step responses).
LAG = """
name: lag
inputs: {u: {unit: "1"}}
components:
  lag:
    type: first_order_lag
    ports: {in: u, out: y}
    tau: 0.05
    k: {value: 1.5, free: true, bounds: [0.1, 10]}
  lag2:
    type: first_order_lag
    ports: {in: y, out: z}
    tau: {value: 0.02, free: true, bounds: [0.001, 1]}
outputs: {z: lag2.y}
"""
