"""Air-in-oil bulk modulus (components/hydraulic/fluid.py) against the closed forms of the
mixture: with the free-air fraction α' of the mixture at pressure p,
1/β_e = (1 − α')/β + α'/(n·p) (Merritt §2.2; Gholizadeh, Burton & Schoenau 2011)."""
import pytest

from hydrocli.components.hydraulic.fluid import effective_bulk_modulus

BETA = 1.5e9


def _value(*args):
    e = effective_bulk_modulus(*args)
    return e.value if hasattr(e, "value") else e


def _mixture(alpha0, p, n, dissolved=1.0):
    r = alpha0 * (1e5 / p) ** (1 / n) * dissolved      # free air at p, per unit oil volume
    a = r / (1 + r)
    return 1.0 / ((1 - a) / BETA + a / (n * p))


def test_no_air_is_the_oil():
    assert _value(BETA, 50e5, 0.0) == BETA


@pytest.mark.parametrize("p", [1e5, 10e5, 100e5])
@pytest.mark.parametrize("n", [1.0, 1.4])
def test_free_air_isothermal_and_isentropic(p, n):
    assert _value(BETA, p, 0.02, n) == pytest.approx(_mixture(0.02, p, n), rel=1e-9)


def test_at_one_bar_isothermal_air_is_softer_than_isentropic():
    """Same free air at p₀; the gas stiffness is n·p."""
    assert _value(BETA, 1e5, 0.02, 1.0) < _value(BETA, 1e5, 0.02, 1.4) < BETA


def test_henry_dissolution_is_linear_down_to_the_dissolution_pressure():
    p, p_d = 50e5, 150e5
    d = 1 - (p - 1e5) / (p_d - 1e5)
    assert _value(BETA, p, 0.05, 1.0, p_d) == pytest.approx(_mixture(0.05, p, 1.0, d), rel=1e-5)
    # above the dissolution pressure no free air is left: the oil's modulus (to the smoothing)
    assert _value(BETA, 200e5, 0.05, 1.0, p_d) == pytest.approx(BETA, rel=1e-4)
