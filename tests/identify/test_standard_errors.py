"""Standard errors that allow for correlated residuals: the effective sample size of an
AR(1) residual is n(1 − ρ)/(1 + ρ) (Bayley & Hammersley 1946), and the reported standard
errors are the white-noise Gauss–Newton ones × √(n/n_eff)."""
import numpy as np
import pytest

from hydrocli.metrics import effective_samples


def _ar1(rho, n, seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n)
    r = np.empty(n)
    r[0] = e[0]
    for i in range(1, n):
        r[i] = rho * r[i - 1] + np.sqrt(1 - rho ** 2) * e[i]
    return r


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.9, 0.99])
def test_effective_samples_of_an_ar1_residual(rho):
    n = 200_000
    expected = n * (1 - rho) / (1 + rho)
    assert effective_samples(_ar1(rho, n, 3)) == pytest.approx(expected, rel=0.05)


def test_identify_reports_inflated_and_white_standard_errors(eha):
    """On data with white noise the inflation is near 1; it is exactly √(n/n_eff)."""
    from hydrocli.identify.fit import fit
    from synth import synthetic
    _, model = eha
    exp = synthetic(model, model.p0, duration=1.5, seed=2)
    start = model.p0.copy()
    start[model.param_index("valve.Kv")] *= 1.2
    res = fit(model, [exp], ["valve.Kv", "load.m"], p_start=start, max_evals=40)
    factor = np.sqrt(res.n_residuals / res.n_effective)
    assert np.allclose(res.stderr, res.stderr_white * factor)
    assert 1.0 <= factor < 3.0
    d = res.as_dict()
    assert np.allclose(d["stderr_white"], res.stderr_white) and d["n_effective"] == res.n_effective
