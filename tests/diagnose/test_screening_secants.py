"""Screening secants taken at several sizes of one parameter share the other columns."""
from __future__ import annotations

import numpy as np

from hydrocli.diagnose import residuals


class _Counted:
    """r(p) = (sin p₀ + p₁², p₀·p₂, exp(p₂)) with a count of evaluations."""

    def __init__(self):
        self.calls = 0

    def residuals(self, p):
        self.calls += 1
        return np.array([np.sin(p[0]) + p[1] ** 2, p[0] * p[2], np.exp(p[2])])


def test_a_shared_memo_gives_the_same_columns_with_fewer_simulations():
    p = np.array([0.3, -1.2, 0.5])
    plain, shared = _Counted(), _Counted()
    r0 = plain.residuals(p)
    shared.calls = plain.calls = 0
    memo: dict = {}
    for h0 in (1e-3, 1e-1, 1.0):          # three sizes of the primary p₀, the others' steps fixed
        a = residuals.sensitivities(plain, p, [0, 1, 2], [h0, 1e-2, 2e-2], r0)
        b = residuals.sensitivities(shared, p, [0, 1, 2], [h0, 1e-2, 2e-2], r0, memo=memo)
        assert np.array_equal(a, b)
        # the secant of p₁ is (r(p + h e₁) − r(p))/h, to rounding
        assert np.allclose(a[:, 1], [((p[1] + 1e-2) ** 2 - p[1] ** 2) / 1e-2, 0.0, 0.0])
    assert plain.calls == 9
    assert shared.calls == 5               # p₀ at three sizes, p₁ and p₂ once
