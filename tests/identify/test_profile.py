"""Profile-likelihood intervals against references computed without the profile's search:
the cost on a dense grid (one free parameter) and a grid of refits (two), and the linearised
±1.96 σ interval where the cost is nearly quadratic."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.experiments.experiment import Experiment
from hydrocli.identify.cost import Objective, make_targets
from hydrocli.identify.fit import POLISH_RTOL, fit
from hydrocli.identify.profile import profile_intervals, threshold
from hydrocli.runner import load_machine
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

from synth import LAG  # noqa: E402  (two first-order lags in series, k and tau free)


@pytest.fixture(scope="module")
def lag(tmp_path_factory):
    f = tmp_path_factory.mktemp("lagpl") / "lag.yaml"
    f.write_text(LAG)
    model = load_machine(f)[1]
    t = np.arange(0, 2.0, 1e-3)
    u = np.sign(np.sin(2 * np.pi * 1.3 * t)) + 0.5 * np.sin(2 * np.pi * 4.1 * t)
    p = model.p0.copy()
    p[model.param_index("lag.k")] = 2.0
    y = simulate(model, InputTable(t, u[:, None]), t, p=p, opts=SolverOptions(rtol=1e-10)).Y[:, 0]
    # large noise: the fast lag's time constant is poorly determined, its cost curve lopsided
    y = y + np.random.default_rng(3).normal(0, 0.2, y.size)
    return model, Experiment(name="lag", file="<synthetic>", inputs=InputTable(t, u[:, None]), t_out=t,
                             measured={"z": y})


def _crossings(values, rises, delta, at):
    """Where the sampled curve rise(value) crosses delta on either side of ``at`` (linear
    interpolation between grid points)."""
    v, c = np.asarray(values), np.asarray(rises)
    left, right = v < at, v > at
    lo = np.interp(delta, c[left][::-1], v[left][::-1])
    hi = np.interp(delta, c[right], v[right])
    return lo, hi


def test_one_parameter_profile_is_the_cost_curve(lag):
    model, exp = lag
    res = fit(model, [exp], ["lag2.tau"])
    (pi,) = profile_intervals(model, [exp], res)
    delta = threshold(res)
    obj = Objective(model, make_targets(model, [exp]), SolverOptions(rtol=1e-6 * POLISH_RTOL))
    c_hat = obj.cost(res.p)
    tau = res.estimates[0]
    grid = np.linspace(0.5 * tau, 1.6 * tau, 221)
    k = model.param_index("lag2.tau")
    rises = []
    for v in grid:
        p = res.p.copy()
        p[k] = v
        rises.append(obj.cost(p) - c_hat)
    lo, hi = _crossings(grid, rises, delta, tau)
    assert pi.lower == pytest.approx(lo, rel=0.01)
    assert pi.upper == pytest.approx(hi, rel=0.01)
    assert pi.refits <= 8 and pi.reliable


def test_two_parameter_profile_matches_a_grid_of_refits_and_the_linear_interval(lag):
    model, exp = lag
    res = fit(model, [exp])
    delta = threshold(res)
    out = {p.name: p for p in profile_intervals(model, [exp], res)}
    # k enters the output linearly: its profile is nearly the linearised interval
    i = res.names.index("lag.k")
    lin = 1.96 * res.stderr[i]
    assert out["lag.k"].upper - res.estimates[i] == pytest.approx(lin, rel=0.1)
    assert res.estimates[i] - out["lag.k"].lower == pytest.approx(lin, rel=0.1)
    # lag2.tau: against refits of k on a grid of fixed tau
    j = res.names.index("lag2.tau")
    tau = res.estimates[j]
    kt = model.param_index("lag2.tau")
    c_hat = min(fit(model, [exp], ["lag.k"], p_start=res.p).cost, res.cost)
    grid = np.linspace(tau - 3 * res.stderr[j], tau + 3 * res.stderr[j], 25)
    rises = []
    for v in grid:
        p = res.p.copy()
        p[kt] = v
        rises.append(fit(model, [exp], ["lag.k"], p_start=p).cost - c_hat)
    lo, hi = _crossings(grid, rises, delta, tau)
    width = hi - lo
    assert out["lag2.tau"].lower == pytest.approx(lo, abs=0.03 * width)
    assert out["lag2.tau"].upper == pytest.approx(hi, abs=0.03 * width)
    assert all(p.reliable for p in out.values())
