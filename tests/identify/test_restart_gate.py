"""The restart gate of the least-squares search: a Gauss–Newton step's predicted share of the cost.

A search that stops on its step size is restarted only when one Gauss–Newton step from its
end is predicted to remove at least RESTART_GAIN of the cost (fit.gauss_newton_gain). Checked
against closed forms of linear residuals r(z) = A z − b, whose Gauss–Newton step is exact.
"""
import numpy as np

from hydrocli.identify.fit import RESTART_GAIN, gauss_newton_gain


def test_the_gain_is_zero_at_a_linear_least_squares_optimum():
    rng = np.random.default_rng(3)
    A, b = rng.normal(size=(50, 3)), rng.normal(size=50)
    z = np.full(3, 0.5)                                          # inside the box
    # at the optimum the residual is orthogonal to the columns of A
    e = b - A @ np.linalg.lstsq(A, b, rcond=None)[0]
    assert gauss_newton_gain(A, e, z) < 1e-20


def test_the_gain_is_the_share_of_the_residual_one_step_removes():
    # one column e1, residual (3, 4): the step removes the first component, 9 of 25
    J, r, z = np.array([[1.0], [0.0]]), np.array([3.0, 4.0]), np.array([0.5])
    assert abs(gauss_newton_gain(J, r, z) - 9.0 / 25.0) < 1e-12
    # a nonlinear residual near a distant optimum: r(z) = (z − 0.9)², started at 0.1
    z = np.array([0.1])
    r, J = np.array([(z[0] - 0.9) ** 2, 0.0]), np.array([[2 * (z[0] - 0.9)], [0.0]])
    assert gauss_newton_gain(J, r, z) > RESTART_GAIN


def test_a_variable_pressed_against_its_bound_takes_no_step():
    J, r = np.array([[1.0], [0.0]]), np.array([3.0, 4.0])
    # gradient Jᵀr = 3 > 0: descent lowers z, which sits at 0: nothing to gain
    assert gauss_newton_gain(J, r, np.array([0.0])) == 0.0
    # the same variable at its upper bound may come down
    assert abs(gauss_newton_gain(J, r, np.array([1.0])) - 9.0 / 25.0) < 1e-12
    # and at 0 with the gradient pointing into the box it may rise
    assert abs(gauss_newton_gain(J, -r, np.array([0.0])) - 9.0 / 25.0) < 1e-12


def test_no_gain_is_claimed_from_a_non_finite_jacobian_or_a_zero_residual():
    assert gauss_newton_gain(np.array([[np.nan]]), np.array([1.0]), np.array([0.5])) == 0.0
    assert gauss_newton_gain(np.array([[1.0]]), np.array([0.0]), np.array([0.5])) == 0.0
