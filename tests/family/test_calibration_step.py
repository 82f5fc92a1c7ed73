"""The family generator's size calibration (experiments/family/generate.py: next_scale)."""
import math

import pytest

from experiments.family.generate import SLOPE_RANGE, next_scale

# seed 164's lift Dahl loop: the effect shrank as its size factor grew
DAHL_S164 = [(1.0, 6.300829618042728), (1.1388556255878024, 5.510597383063028),
             (4.23568181620373, 4.423780672802724)]


def test_a_probe_near_the_target_is_taken():
    assert next_scale([(1.0, 2.0), (2.0, 7.5)], 8.0) == (2.0, True)


def test_a_power_law_is_followed_by_the_log_log_secant():
    # ESR = 2·s²: from s = 1 the default slope 2 lands on the target
    s, done = next_scale([(1.0, 2.0)], 8.0)
    assert (s, done) == (pytest.approx(2.0), False)
    # two probes of ESR = 3·s^1.5 bracketing the target: the secant through them is exact
    probes = [(1.0, 3.0), (4.0, 24.0)]
    s, done = next_scale(probes, 12.0, last=True)
    assert done and 3.0 * s ** 1.5 == pytest.approx(12.0)


def test_the_last_step_does_not_extrapolate_a_response_that_does_not_grow():
    # the old calibration returned the unprobed ×32.8 (134 % against 8.2 %)
    s, done = next_scale(DAHL_S164, 8.17, last=True)
    assert done and s == 1.0                # the probe nearest the target (6.3 %)
    # before the last step the secant still proposes a probe (slope held at its floor)
    s, done = next_scale(DAHL_S164, 8.17)
    assert not done and s == pytest.approx(4.2357 * (8.17 / 4.4238) ** (1 / SLOPE_RANGE[0]), rel=1e-3)


def test_the_last_step_extrapolates_when_the_probes_slope_is_trusted():
    probes = [(1.0, 1.0), (2.0, 2.0 ** 0.8)]          # slope 0.8, target beyond both
    s, done = next_scale(probes, 4.0, last=True)
    assert done and s == pytest.approx(2.0 * (4.0 / 2.0 ** 0.8) ** (1 / 0.8))
    assert math.isfinite(s)
