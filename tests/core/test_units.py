"""Units are converted once at load time (pint); wrong dimensions are errors."""
import math

import pytest

from hydrocli.errors import UnitError
from hydrocli.units import from_si, to_si


def test_bar_to_pascal():
    assert to_si("210 bar", "Pa") == pytest.approx(2.1e7)


def test_flow_gain_litres_per_minute_per_sqrt_bar():
    # 37.8 L/min/bar^0.5 = 37.8e-3/60 m^3/s / sqrt(1e5 Pa)
    assert to_si("37.8 L/min/bar^0.5", "m^3/s/Pa^0.5") == pytest.approx(37.8e-3 / 60 / math.sqrt(1e5))


@pytest.mark.parametrize("text, unit, si", [("4 ms", "s", 4e-3), ("63 mm", "m", 0.063),
                                            ("2000 %/s", "1/s", 20.0), ("1.73 GPa", "Pa", 1.73e9),
                                            ("0.2 L", "m^3", 2e-4), ("50 %", "1", 0.5)])
def test_common_units(text, unit, si):
    assert to_si(text, unit) == pytest.approx(si)


def test_bare_number_uses_default_unit():
    assert to_si(50, "Pa", default_unit="bar") == pytest.approx(5e6)
    assert to_si(50, "Pa") == 50.0


def test_wrong_dimension_is_an_error_naming_both():
    with pytest.raises(UnitError) as exc:
        to_si("3 bar", "m")
    assert "bar" in str(exc.value) and "m" in str(exc.value)


def test_unknown_unit_is_an_error():
    with pytest.raises(UnitError):
        to_si("3 blorps", "m")


def test_from_si_round_trip():
    assert from_si(to_si("12.5 bar", "Pa"), "bar") == pytest.approx(12.5)
