"""The analytic Jacobian (symbolic differentiation through named variables) agrees with
central finite differences of the generated right-hand side."""
import math

import numpy as np
import pytest

from hydrocli.model import expr as E
from hydrocli.model.builder import build_model
from hydrocli.model.codegen import _Names, generate_c
from hydrocli.model.equations import jacobian_pattern
from hydrocli.model.jacobian import input_jacobian_numpy_source, jacobian_numpy_source
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


@pytest.mark.parametrize("machine", ["eha_testbench", "sarcos_elbow", "harvester"])
def test_input_jacobian_matches_finite_differences(machine):
    """∂f/∂u (``hy_jac_u``'s second output, from which the Rodas4P library forms ∂f/∂t =
    ∂f/∂u · du/dt) agrees with central differences of the generated right-hand side in u."""
    m = build_model(load_netlist(f"machines/{machine}.yaml"))
    eqs = m.equations
    ns = {}
    exec(input_jacobian_numpy_source(eqs, _Names(eqs)), ns)
    rhs = m.numpy_evaluate()
    rng = np.random.default_rng(5)
    x = m.x0 * (1 + 0.01 * rng.standard_normal(m.x0.size)) + 1e-3 * rng.standard_normal(m.x0.size)
    # inputs at typical magnitudes: a supply pressure of 100 bar, small commands/forces
    typical = {"Pa": 1e7, "N": 500.0}
    u = np.array([typical.get(str(m.input_units.get(n, "")).replace(" ", ""), 0.01) for n in m.input_names])
    u = u * (1 + 0.1 * rng.standard_normal(u.size))
    fu = np.array(ns["input_jacobian"](0.1, x, m.p0, u), dtype=float)
    assert len(fu) >= 1
    checked = 0
    for k, (i, j) in enumerate(zip(ns["rows"], ns["cols"])):
        h = 1e-5 * max(abs(u[j]), 1e-2)
        fd = []
        for step in (h, h / 10):
            up, um = u.copy(), u.copy()
            up[j] += step
            um[j] -= step
            fd.append((rhs(0.1, x, m.p0, up)[0][i] - rhs(0.1, x, m.p0, um)[0][i]) / (2 * step))
        if abs(fd[0] - fd[1]) > 1e-4 * max(abs(fd[1]), 1e-12):
            continue  # a kink of a branch
        assert fu[k] == pytest.approx(fd[1], rel=1e-4, abs=1e-9 * max(abs(fd[1]), 1.0)), (m.state_names[i], m.input_names[j])
        checked += 1
    assert checked >= 0.8 * len(fu)


def test_rodas4p_library_forms_df_dt_from_df_du(tmp_path, monkeypatch):
    """The Rodas4P library (HY_FT_ANALYTIC, HY_FAST_TANH) and the same method with a forward
    difference in t and the C library's tanh: the EHA at a tight tolerance gives the same
    trajectory, and one right-hand side per accepted step less."""
    from hydrocli.bench import eha_inputs
    from hydrocli.solve.compiled import CompiledModel, build_library
    from hydrocli.solve.library import method_source
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path))
    m = build_model(load_netlist("machines/eha_testbench.yaml"))
    assert "#define HY_HAS_JAC_U" in m.c_source
    t, U = eha_inputs(2.0)
    scale = np.array([max(s.nominal, 1e-3) for s in m.states]) * 1e3
    out = []
    for src in (method_source(m, "rodas4p"), "#define HY_METHOD 2\n" + m.c_source):
        lib = CompiledModel(build_library(src), len(m.state_names), len(m.param_names), 3, len(m.output_names))
        res = lib.simulate(m.p0, t, U, np.full(3, 2, np.int32), 0.0, m.x0, t, rtol=1e-8, atol=scale * 1e-8)
        assert res.status == 0, res.message
        out.append(res)
    fast, fd = out
    assert fast.stats["rhs_evals"] + fast.stats["steps_accepted"] <= fd.stats["rhs_evals"] + 0.02 * fd.stats["rhs_evals"]
    assert abs(fast.stats["steps_accepted"] - fd.stats["steps_accepted"]) <= 0.02 * fd.stats["steps_accepted"]
    np.testing.assert_allclose(fast.X[:, 3], fd.X[:, 3], atol=20.0)  # Pa, at pressures ~ 1e7
