"""The analytic Jacobian (symbolic differentiation through named variables) agrees with
central finite differences of the generated right-hand side."""
import math

import numpy as np
import pytest

from hydrocli.model import expr as E
from hydrocli.model.builder import build_model
from hydrocli.model.codegen import _Names, generate_c
from hydrocli.model.equations import jacobian_pattern
from hydrocli.model.jacobian import jacobian_numpy_source
from hydrocli.netlist.loader import load_netlist


@pytest.mark.parametrize("fn, x0, want", [
    (lambda x: E.tanh(3.0 * x), 0.4, lambda x: 3.0 * (1 - math.tanh(3 * x) ** 2)),
    (lambda x: E.sqrt(x * x + 1.0), 0.7, lambda x: x / math.sqrt(x * x + 1)),
    (lambda x: E.power(x, 3.0), 1.3, lambda x: 3 * x * x),
    (lambda x: E.fmax(x, 0.5) * E.exp(-x), 0.9, lambda x: math.exp(-x) - x * math.exp(-x)),
    (lambda x: E.atan2(x, 2.0), 0.3, lambda x: 2.0 / (4.0 + x * x)),
    (lambda x: E.where(x > 0, x * x, -x), -0.2, lambda x: -1.0),
])
def test_partial_derivatives(fn, x0, want):
    x = E.state("x")
    d = E.partial(fn(x), ("state", "x"))
    got = eval(E.to_numpy(d, {("state", "x"): "s"}), {"np": np, "s": x0})
    assert got == pytest.approx(want(x0), rel=1e-12)


@pytest.mark.parametrize("machine", ["eha_testbench", "sarcos_elbow", "harvester"])
def test_analytic_jacobian_matches_finite_differences(machine):
    m = build_model(load_netlist(f"machines/{machine}.yaml"))
    eqs = m.equations
    rows, cols = jacobian_pattern(eqs)
    ns = {}
    exec(jacobian_numpy_source(eqs, _Names(eqs), rows, cols), ns)
    rhs = m.numpy_evaluate()
    rng = np.random.default_rng(3)
    x = m.x0 * (1 + 0.01 * rng.standard_normal(m.x0.size)) + 1e-3 * rng.standard_normal(m.x0.size)
    u = np.full(len(m.input_names), 0.3)
    jac = np.array(ns["jacobian"](0.1, x, m.p0, u), dtype=float)
    checked = 0
    for k, (i, j) in enumerate(zip(rows, cols)):
        h = 1e-6 * max(abs(x[j]), 1e-4)
        fd = []
        for step in (h, h / 10):
            xp, xm = x.copy(), x.copy()
            xp[j] += step
            xm[j] -= step
            fd.append((rhs(0.1, xp, m.p0, u)[0][i] - rhs(0.1, xm, m.p0, u)[0][i]) / (2 * step))
        if abs(fd[0] - fd[1]) > 1e-4 * max(abs(fd[1]), 1e-12):
            continue  # a kink of a branch: finite differences are not a reference there
        row_scale = np.max(np.abs(jac[np.asarray(rows) == i]))
        assert jac[k] == pytest.approx(fd[1], rel=1e-4, abs=1e-7 * row_scale), (m.state_names[i], m.state_names[j])
        checked += 1
    assert checked >= 0.8 * len(rows)


def test_compiled_model_uses_the_analytic_jacobian_and_agrees_with_finite_differences(tmp_path, monkeypatch):
    from hydrocli.solve.compiled import CompiledModel, build_library
    from hydrocli.bench import eha_inputs
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path))
    m = build_model(load_netlist("machines/eha_testbench.yaml"))
    t, U = eha_inputs(2.0)
    out = []
    for analytic in (True, False):
        src = generate_c(m.equations, m.name, analytic_jacobian=analytic)
        assert ("hy_jac" in src) == analytic
        lib = CompiledModel(build_library(src), len(m.state_names), len(m.param_names), 3, len(m.output_names))
        res = lib.simulate(m.p0, t, U, np.zeros(3, np.int32), 0.0, m.x0, t, rtol=1e-8,
                           atol=np.array([s.nominal for s in m.states]) * 1e-5)
        assert res.status == 0
        out.append(res)
    assert out[0].stats["rhs_evals"] < out[1].stats["rhs_evals"]
    np.testing.assert_allclose(out[0].X[:, 3], out[1].X[:, 3], atol=50.0)  # Pa
