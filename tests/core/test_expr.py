"""The equation language: constant folding, C/NumPy printing, smooth helpers."""
import math

import numpy as np
import pytest

from hydrocli.model import expr as E


def test_constant_folding_and_identities():
    x = E.state("x")
    assert (x * 1.0) is x
    assert (x + 0.0) is x
    assert (x * 0.0).is_const and (x * 0.0).value == 0.0
    assert (E.const(2) * 3).value == 6.0


def test_no_truth_value():
    with pytest.raises(TypeError):
        bool(E.state("x") > 0)


def test_c_and_numpy_printing_agree():
    x, p = E.state("x"), E.param("k")
    e = E.where(x > 0, p * E.sqrt(x), -p * E.tanh(x)) + E.fmax(x, 0.5)
    names = {("state", "x"): "x[0]", ("param", "k"): "p[0]"}
    c = E.to_c(e, names)
    assert "sqrt" in c and "?" in c and "fmax" in c
    src = E.to_numpy(e, names)
    for xv in (-1.3, 0.7, 2.0):
        with np.errstate(invalid="ignore"):  # np.where evaluates both branches
            got = eval(src, {"np": np, "x": [xv], "p": [3.0]})
        want = (3.0 * math.sqrt(xv) if xv > 0 else -3.0 * math.tanh(xv)) + max(xv, 0.5)
        assert got == pytest.approx(want)


def test_signed_sqrt_is_turbulent_far_from_zero_and_linear_near_it():
    dp = E.state("dp")
    names = {("state", "dp"): "x[0]"}
    f = lambda v: eval(E.to_numpy(E.signed_sqrt(dp, 5e4), names), {"np": np, "x": [v]})  # noqa: E731
    assert f(1e7) == pytest.approx(math.sqrt(1e7), rel=1e-4)
    assert f(-1e7) == pytest.approx(-math.sqrt(1e7), rel=1e-4)
    assert f(10.0) == pytest.approx(10.0 / math.sqrt(5e4), rel=1e-6)


def test_symbols_are_collected():
    e = E.state("a") * E.param("b") + E.var("c") - E.input_("u")
    assert e.symbols() == {("state", "a"), ("param", "b"), ("var", "c"), ("input", "u")}
