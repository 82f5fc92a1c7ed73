"""The fit's exact Jacobian, its simulation budget and progress, and the estimates'
sensitivity to a fixed parameter checked against re-fits."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.experiments.experiment import Experiment
from hydrocli.identify.fit import fit
from hydrocli.runner import load_machine
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

from synth import LAG  # noqa: E402  (two first-order lags in series, k and tau free)


@pytest.fixture(scope="module")
def lag(tmp_path_factory):
    f = tmp_path_factory.mktemp("lag") / "lag.yaml"
    f.write_text(LAG)
    model = load_machine(f)[1]
    t = np.arange(0, 4.0, 1e-3)
    u = np.sign(np.sin(2 * np.pi * 1.3 * t)) + 0.5 * np.sin(2 * np.pi * 4.1 * t)
    inputs = InputTable(t, u[:, None])
    p = model.p0.copy()
    p[model.param_index("lag.k")] = 2.0
    y = simulate(model, inputs, t, p=p, opts=SolverOptions(rtol=1e-9)).Y[:, 0]
    y = y + np.random.default_rng(1).normal(0, 0.01, y.size)
    return model, Experiment(name="lag", file="<synthetic>", inputs=inputs, t_out=t, measured={"z": y})


def test_sensitivity_and_difference_jacobians_reach_the_same_optimum(lag):
    """Both searches land on one optimum. The standard errors from the sensitivity Jacobian
    are the exact ones: σ̂²(GᵀG)⁻¹ with G = ∂ŷ/∂(k, τ₂) from scipy.signal.lsim (exact for
    linearly interpolated inputs) to 1 %. The difference Jacobian's columns carry the
    integrator's error on the steps that cross the input's kinks (τ₂'s column is ~10 % off
    at the default rtol, by an amount that depends on rounding), so its standard errors are
    only held to 30 %: a scaling slip (unit box vs parameters) would be a factor off."""
    from scipy import signal
    model, exp = lag
    a = fit(model, [exp], gradient="sensitivities", polish=False)     # the searches themselves
    b = fit(model, [exp], gradient="finite-differences", polish=False)
    assert a.gradient == "sensitivities" and b.gradient == "finite-differences"
    assert a.estimates == pytest.approx(b.estimates, rel=1e-3)
    assert a.cost <= b.cost * (1 + 1e-6)
    t, u, y = exp.t_out, exp.inputs.U[:, 0], exp.measured["z"]

    def out(k, tau2):
        return signal.lsim(signal.lti([k], [0.05 * tau2, 0.05 + tau2, 1.0]), u, t)[1]
    k, tau2 = a.estimates
    h = 1e-5
    G = np.column_stack([(out(k * (1 + h), tau2) - out(k * (1 - h), tau2)) / (2 * h * k),
                         (out(k, tau2 * (1 + h)) - out(k, tau2 * (1 - h))) / (2 * h * tau2)])
    r = y - out(k, tau2)
    exact = np.sqrt(np.diag(r @ r / (r.size - 2) * np.linalg.inv(G.T @ G)))
    assert a.stderr_white == pytest.approx(exact, rel=0.01)
    assert b.stderr_white == pytest.approx(exact, rel=0.3)


def test_fixed_parameter_effect_matches_refits(lag):
    """dθ̂/dφ = −(JᵀJ)⁻¹JᵀJφ against central differences of two re-fits with φ = lag.tau moved ±1 %."""
    model, exp = lag
    res = fit(model, [exp], assess=True)
    u = res.uncertainty
    j = u.fixed_names.index("lag.tau")
    k = model.param_index("lag.tau")
    tau = model.p0[k]
    refits = []
    for f in (1.01, 0.99):
        p = model.p0.copy()
        p[k] = tau * f
        refits.append(fit(model, [exp], p_start=p).estimates)
    fd = (refits[0] - refits[1]) / (0.02 * tau)
    assert u.dtheta_dphi[:, j] == pytest.approx(fd, rel=0.03)
    assert any(e.name == "lag.tau" for e in u.fixed_effects)        # it moves the estimates by many σ


@pytest.mark.parametrize("gradient", ["sensitivities", "finite-differences"])
def test_max_evals_caps_every_simulation_and_the_progress_counts_them(lag, gradient):
    model, exp = lag
    seen = []
    res = fit(model, [exp], max_evals=7, gradient=gradient, p_start=model.param_vector({"lag.k": 5.0}),
              progress=lambda n, c, b: seen.append(n))
    assert res.n_evals <= 7 and max(seen) <= 7
    assert seen == sorted(seen) and seen[-1] == res.n_evals


def test_progress_prints_a_line_without_a_terminal(capsys):
    from hydrocli.cli.identify_output import progress_bar
    with progress_bar(10, every=0.0) as prog:
        prog.update(3, 0.5, 0.4)
    err = capsys.readouterr().err
    assert "simulation 3/10" in err and "best 0.4" in err


def test_intervals_bracket_the_truth_on_a_clean_synthetic_fit(lag):
    model, exp = lag
    res = fit(model, [exp], assess=True)
    u = res.uncertainty
    truth = {"lag.k": 2.0, "lag2.tau": 0.02}
    for i, n in enumerate(res.names):
        assert u.ci_lower[i] <= truth[n] <= u.ci_upper[i]
        # a white-noise fit: the bootstrap interval agrees with ±1.96 standard errors within 25 %
        assert (u.ci_upper[i] - u.ci_lower[i]) == pytest.approx(2 * 1.96 * res.stderr_white[i], rel=0.25)


def test_residual_jacobian_carries_the_settling_runs_sensitivity(lag):
    """An experiment that settles first starts from x0(p): ∂r/∂p includes ∂x0/∂p (central
    differences of the residuals, which re-run the settling, as the reference)."""
    from dataclasses import replace

    from hydrocli.identify.cost import Objective, make_targets
    model, exp = lag
    exp = replace(exp, inputs=InputTable(exp.inputs.t, exp.inputs.U + 1.0))    # settles at y = k·1, not 0
    settled = replace(exp, settle=1.0)
    obj = Objective(model, make_targets(model, [settled]), SolverOptions(rtol=1e-10, atol_factor=1.0))
    names = ["lag.k", "lag2.tau", "lag.tau"]
    p = model.p0
    _, J = obj.residuals_jacobian(p, names)
    for c, n in enumerate(names):
        k = model.param_index(n)
        h = 1e-4 * p[k]
        up, dn = p.copy(), p.copy()
        up[k] += h
        dn[k] -= h
        fd = (obj.residuals(up) - obj.residuals(dn)) / (2 * h)
        # (the settling run itself integrates at rtol 1e-6, which bounds the agreement)
        assert J[:, c] == pytest.approx(fd, rel=1e-3, abs=1e-3 * np.max(np.abs(fd))), n
    # and ∂x0/∂k matters: without it the k column would be far off
    _, J0 = Objective(model, make_targets(model, [exp]), obj.opts).residuals_jacobian(p, ["lag.k"])
    assert np.max(np.abs(J0[:, 0] - J[:, 0])) > 0.1 * np.max(np.abs(J[:, 0]))


def test_a_model_too_large_for_sensitivity_code_falls_back_to_differences(lag, monkeypatch):
    from hydrocli.errors import IdentifyError
    from hydrocli.solve import sensitivities
    model, exp = lag
    monkeypatch.setattr(sensitivities, "MAX_JACOBIAN_CHARS", 0)
    model.__dict__.pop("_sens_compiled", None)
    assert fit(model, [exp], max_evals=20).gradient == "finite-differences"
    with pytest.raises(IdentifyError, match="sensitivities are not available"):
        fit(model, [exp], gradient="sensitivities")


@pytest.mark.parametrize("gradient", ["sensitivities", "finite-differences"])
def test_a_run_that_blows_up_without_failing_does_not_overflow_the_search(lag, gradient, monkeypatch):
    """Trial runs far from the optimum (lag.k > 3) return a finite but absurd tail (1e200, as a
    diverged integration can): those samples count as a failed run's, with no slope, so the
    optimiser's sums and the covariance's SVD see no overflow and the fit still finds k = 2."""
    import warnings

    from hydrocli.identify import cost
    from hydrocli.solve import sensitivities
    model, exp = lag
    k = model.param_index("lag.k")
    plain, sens = cost.simulate, sensitivities.output_sensitivities

    def blow(res, p):
        if p[k] > 3.0:
            res.Y[-20:] *= 1e200
            if getattr(res, "dY", None) is not None:
                res.dY[-20:] *= 1e200
        return res

    monkeypatch.setattr(cost, "simulate", lambda m, *a, p, **kw: blow(plain(m, *a, p=p, **kw), p))
    monkeypatch.setattr(sensitivities, "output_sensitivities", lambda m, *a, p, **kw: blow(sens(m, *a, p=p, **kw), p))
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # an overflow in the search or in LAPACK fails the test
        res = fit(model, [exp], gradient=gradient, p_start=model.param_vector({"lag.k": 5.0}))
    assert res.estimates[res.names.index("lag.k")] == pytest.approx(2.0, rel=0.01)
    assert np.all(np.isfinite(res.stderr)) and np.isfinite(res.cost)
