"""Statistics of the diagnosis: whiteness, effective n, BIC, noise floor, score screening."""
import numpy as np
import pytest

from hydrocli.diagnose import stats


@pytest.fixture
def rng():
    return np.random.default_rng(4)


def test_ljung_box_separates_white_from_coloured(rng):
    white = rng.normal(size=4000)
    coloured = np.convolve(rng.normal(size=4100), np.ones(30) / 30, "valid")[:4000]
    assert stats.ljung_box(white)[1] > 0.01
    assert stats.ljung_box(coloured)[1] < 1e-6


def test_effective_n_shrinks_for_autocorrelated_residuals(rng):
    white = rng.normal(size=4000)
    ar = np.zeros(4000)
    e = rng.normal(size=4000)
    for i in range(1, 4000):
        ar[i] = 0.9 * ar[i - 1] + e[i]
    assert stats.effective_n(white) == pytest.approx(4000, rel=0.1)
    # AR(1) with ρ = 0.9: n(1 − ρ)/(1 + ρ) ≈ 210
    assert stats.effective_n(ar) == pytest.approx(4000 * 0.1 / 1.9, rel=0.25)


def test_delta_bic_closed_form():
    assert stats.delta_bic(1.0, 0.5, 100, 1) == pytest.approx(100 * np.log(0.5) + np.log(100))
    assert stats.delta_bic(1.0, 0.999, 100, 1) > 0          # tiny gain does not pay for a parameter
    assert stats.delta_bic(1.0, 0.8, 1000, 2) < 0


def test_noise_floor_from_second_differences(rng):
    t = np.linspace(0, 10, 10001)
    y = np.sin(2 * np.pi * 0.5 * t) + 0.01 * rng.normal(size=t.size)
    assert stats.noise_variance(y) == pytest.approx(1e-4, rel=0.15)
    assert stats.noise_esr(y) == pytest.approx(100 * 1e-4 / np.var(y), rel=0.2)


def test_cross_correlation_finds_lag(rng):
    u = rng.normal(size=3000)
    r = np.roll(u, 7) + 0.1 * rng.normal(size=3000)
    c, lag = stats.cross_correlation(r, u, 20)
    assert lag == 7 and c > 0.9


def test_screening_names_the_missing_term_of_an_equation_error(rng):
    """Force-balance equation error m·a − ΣF of a model without Coulomb friction:
    the sign(v) regressor explains it, a pressure regressor does not, after the base
    regressors (viscous v, acceleration) are projected out."""
    t = np.linspace(0, 6, 6000)
    v = 0.05 * np.sin(2 * np.pi * 0.7 * t) + 0.02 * np.sin(2 * np.pi * 2.3 * t)
    a = np.gradient(v, t)
    p = 5e6 + 1e6 * np.sin(2 * np.pi * 0.3 * t + 1)
    e = 800 * np.tanh(v / 1e-3) + 30 * v + 2 * a + 20 * rng.normal(size=t.size)
    base = np.column_stack([v, a])
    coulomb = stats.screen(e, np.tanh(v / 1e-3), base)
    pressure = stats.screen(e, p, base)
    assert coulomb["dr2"] > 0.95 and abs(coulomb["t"][0]) > 50
    assert pressure["dr2"] < 0.05


def test_noise_floor_does_not_lock_onto_a_quantised_sensor():
    """White Gaussian noise σ = 0.9–1.3 on a 0.1 lattice (the lifts' speed sensor: σ ≈ 1 mm/s,
    0.1 mm/s steps) on a smooth signal: the estimate stays within 4 % of the realised noise in
    every draw. A median-absolute-deviation scale locks onto the lattice here (at σ = 0.9 it
    reads 1.018 in every draw, and it strays by up to 7 %; session 71)."""
    rng = np.random.default_rng(11)
    t = np.arange(20000) * 1e-3
    smooth = 30.0 * np.sin(2 * np.pi * 0.3 * t)
    worst = 0.0
    for sigma in (0.9, 1.0, 1.1, 1.2, 1.3):
        for _ in range(6):
            e = sigma * rng.normal(size=t.size)
            y = np.round((smooth + e) / 0.1) * 0.1
            realised = np.var(y - smooth)
            worst = max(worst, abs(stats.noise_variance(y) / realised - 1.0))
    assert worst < 0.04


def test_noise_floor_ignores_steps_of_the_signal(rng):
    """A square wave's edges put a few second differences far out; they are dropped, so the
    estimate is the noise's (within 3 %), not the edges'."""
    t = np.arange(30000) * 1e-3
    square = 5.0 * np.sign(np.sin(2 * np.pi * 0.5 * t))
    e = 0.02 * rng.normal(size=t.size)
    assert stats.noise_variance(square + e) == pytest.approx(np.var(e), rel=0.03)
    assert np.var(np.diff(square + e, 2)) / 6 > 20 * np.var(e)     # the edges alone would swamp it
