"""Tests of the compiled Rodas4 integrator (hydrocli/solve/csrc/hy_integrator.c) and its
ctypes driver (hydrocli/solve/compiled.py).

The C models below are hand-written stand-ins for generated code; they follow the
model contract exactly (HY_* macros, HY_JAC_ROW/COL in CSR order, hy_rhs, hy_out).
"""
from __future__ import annotations

import os
import pickle
import subprocess
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from hydrocli.solve import compiled
from hydrocli.solve.compiled import CompiledModel, CompileError, SimResult, build_library


# ----------------------------------------------------------------------------- helpers
def model_source(nx, np_, nu, ny, pattern, rhs_body, out_body="", prelude=""):
    """C source of a model following the generated-code contract."""
    pattern = sorted(set(pattern) | {(i, i) for i in range(nx)})
    rows = ",".join(str(r) for r, _ in pattern)
    cols = ",".join(str(c) for _, c in pattern)
    return f"""{prelude}
#include <math.h>
#define HY_NX {nx}
#define HY_NP {np_}
#define HY_NU {nu}
#define HY_NY {ny}
#define HY_NNZ {len(pattern)}
static const int HY_JAC_ROW[HY_NNZ] = {{{rows}}};
static const int HY_JAC_COL[HY_NNZ] = {{{cols}}};
static int hy_rhs(double t, const double *x, const double *p, const double *u, double *dx)
{{
    (void)t; (void)x; (void)p; (void)u;
{rhs_body}
    return 0;
}}
static int hy_out(double t, const double *x, const double *p, const double *u, double *y)
{{
    (void)t; (void)x; (void)p; (void)u; (void)y;
{out_body}
    return 0;
}}
"""


def dense_pattern(n):
    return [(i, j) for i in range(n) for j in range(n)]


@pytest.fixture()
def cache(tmp_path):
    return tmp_path / "cache"


def make(cache, nx, np_, nu, ny, pattern, rhs, out="", prelude=""):
    so = build_library(model_source(nx, np_, nu, ny, pattern, rhs, out, prelude), cache_dir=cache)
    return CompiledModel(so, nx, np_, nu, ny)


# ------------------------------------------------------------------ 1. linear stiff
LINEAR_RHS = """
    dx[0] = -p[0]*x[0] + (p[0] - 1.0)*x[1];
    dx[1] = -x[1];
    dx[2] = -p[1]*(x[2] - sin(t));
"""


def linear_exact(t, x0, k, lam):
    x1 = x0[1] * np.exp(-t)
    x0_ = x0[1] * np.exp(-t) + (x0[0] - x0[1]) * np.exp(-k * t)
    A, B = lam**2 / (lam**2 + 1), -lam / (lam**2 + 1)
    x2 = A * np.sin(t) + B * np.cos(t) + (x0[2] - B) * np.exp(-lam * t)
    return np.column_stack([x0_, x1, x2])


def test_linear_stiff_matches_exact(cache):
    m = make(cache, 3, 2, 0, 1, [(0, 1)], LINEAR_RHS, "y[0] = x[0] + x[1];")
    t = np.linspace(0.0, 5.0, 501)
    x0 = [2.0, 1.0, 0.5]
    k, lam = 1000.0, 1.0e4
    r = m.simulate([k, lam], None, None, None, 0.0, x0, t, rtol=1e-8, atol=1e-12)
    assert isinstance(r, SimResult) and r.status == 0 and r.message == "ok"
    ex = linear_exact(t, x0, k, lam)
    assert np.max(np.abs(r.X - ex)) < 2e-7
    np.testing.assert_allclose(r.Y[:, 0], r.X[:, 0] + r.X[:, 1], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(r.X[0], x0)
    st = r.stats
    assert st["steps_accepted"] > 0 and st["jacobian_evals"] == st["steps_accepted"]
    assert st["lu_decompositions"] == st["steps_accepted"] + st["steps_rejected"]
    assert st["time_reached"] == 5.0 and st["worst_state"] == -1


def test_convergence_order(cache):
    """Errors must fall roughly like rtol (tolerance proportionality)."""
    m = make(cache, 3, 2, 0, 0, [(0, 1)], LINEAR_RHS)
    t = np.linspace(0.0, 2.0, 201)
    x0 = [2.0, 1.0, 0.5]
    ex = linear_exact(t, x0, 50.0, 30.0)
    errs = []
    for rtol in (1e-4, 1e-6, 1e-8):
        r = m.simulate([50.0, 30.0], None, None, None, 0.0, x0, t, rtol=rtol, atol=rtol)
        errs.append(np.max(np.abs(r.X - ex)))
        if rtol == 1e-4:  # dense output: steps are much longer than the output spacing
            assert r.stats["steps_accepted"] < len(t) / 4
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-7


# ------------------------------------------------------------------ 2. Robertson
ROBER_RHS = """
    dx[0] = -p[0]*x[0] + p[2]*x[1]*x[2];
    dx[1] =  p[0]*x[0] - p[2]*x[1]*x[2] - p[1]*x[1]*x[1];
    dx[2] =  p[1]*x[1]*x[1];
"""


def test_robertson_vs_radau(cache):
    m = make(cache, 3, 3, 0, 0, dense_pattern(3), ROBER_RHS)
    k = (0.04, 3e7, 1e4)

    def f(t, y):
        return [-k[0] * y[0] + k[2] * y[1] * y[2],
                k[0] * y[0] - k[2] * y[1] * y[2] - k[1] * y[1] ** 2,
                k[1] * y[1] ** 2]

    t = np.concatenate([[0.0], np.logspace(-5, 3, 60)])
    atol = np.array([1e-10, 1e-14, 1e-10])
    ref = solve_ivp(f, (0, t[-1]), [1, 0, 0], method="Radau", rtol=1e-10, atol=atol * 1e-2,
                    t_eval=t)
    r = m.simulate(k, None, None, None, 0.0, [1, 0, 0], t, rtol=1e-8, atol=atol)
    assert r.status == 0
    rel = np.abs(r.X - ref.y.T) / np.maximum(np.abs(ref.y.T), atol * 100)
    assert rel.max() < 1e-5
    np.testing.assert_allclose(r.X.sum(axis=1), 1.0, atol=1e-9)


def test_van_der_pol_stiff_vs_radau(cache):
    """Van der Pol with mu=1000 in Hairer-Wanner's scaled form (eps = 1/mu^2 = 1e-6)."""
    m = make(cache, 2, 1, 0, 0, dense_pattern(2),
             "dx[0] = x[1]; dx[1] = ((1.0 - x[0]*x[0])*x[1] - x[0]) / p[0];")
    eps = 1e-6
    t = np.linspace(0.0, 2.0, 41)
    x0 = [2.0, -0.66]
    ref = solve_ivp(lambda t, y: [y[1], ((1 - y[0] ** 2) * y[1] - y[0]) / eps], (0, t[-1]),
                    x0, method="Radau", rtol=1e-10, atol=1e-12, t_eval=t)
    r = m.simulate([eps], None, None, None, 0.0, x0, t, rtol=1e-9, atol=1e-11)
    assert r.status == 0
    scale = np.max(np.abs(ref.y), axis=1)
    assert np.max(np.abs(r.X - ref.y.T) / scale) < 1e-5


# ------------------------------------------------------------------ 3. input tables
MSD_RHS = """
    dx[0] = x[1];
    dx[1] = (u[0] - p[1]*x[1] - p[2]*x[0]) / p[0];
"""


def msd_exact(p, t_in, F, hold, t_out, x0):
    """Exact response of m x'' + c x' + k x = F(t) for a piecewise-linear (hold=0) or
    piecewise-constant (hold=1) force, by matrix exponentials per table segment."""
    m_, c, k = p
    A = np.zeros((4, 4))
    A[0, 1] = 1.0
    A[1, 0], A[1, 1], A[1, 2] = -k / m_, -c / m_, 1.0 / m_
    A[2, 3] = 1.0
    out = np.empty((len(t_out), 2))
    z = np.array([x0[0], x0[1], F[0], 0.0])
    tcur = t_out[0]
    knots = list(t_in[(t_in > t_out[0]) & (t_in < t_out[-1])])
    events = sorted(set(knots) | set(t_out))
    j = 0
    for te in events:
        if te > tcur:
            z = expm(A * (te - tcur)) @ z
            tcur = te
        # re-establish the input at te (continuous value / slope to the right)
        kseg = np.searchsorted(t_in, te, side="right") - 1
        if kseg < 0:
            z[2], z[3] = F[0], 0.0
        elif kseg >= len(t_in) - 1:
            z[2], z[3] = F[-1], 0.0
        elif hold:
            z[2], z[3] = F[kseg], 0.0
        else:
            slope = (F[kseg + 1] - F[kseg]) / (t_in[kseg + 1] - t_in[kseg])
            z[2], z[3] = F[kseg] + slope * (te - t_in[kseg]), slope
        while j < len(t_out) and t_out[j] == te:
            out[j] = z[:2]
            j += 1
    return out


@pytest.mark.parametrize("hold", [0, 1])
def test_mass_spring_damper_input_table(cache, hold):
    m = make(cache, 2, 3, 1, 1, [(0, 1), (1, 0)], MSD_RHS, "y[0] = u[0];")
    p = (2.0, 0.8, 50.0)
    # ramp 1 s -> 2 s then constant, then a steeper ramp down, then a step (ZOH style)
    t_in = np.array([0.0, 1.0, 2.0, 3.0, 3.5, 4.0, 4.7, 6.0])
    F = np.array([0.0, 0.0, 10.0, 10.0, -5.0, -5.0, 3.0, 3.0])
    t_out = np.linspace(0.0, 8.0, 161)
    r = m.simulate(p, t_in, F.reshape(-1, 1), [hold], 0.0, [0.1, 0.0], t_out,
                   rtol=1e-9, atol=1e-12)
    assert r.status == 0, r.message
    ex = msd_exact(p, t_in, F, hold, t_out, [0.1, 0.0])
    assert np.max(np.abs(r.X - ex)) < 1e-7
    # outputs see the interpolated input at t_out
    if hold:
        idx = np.clip(np.searchsorted(t_in, t_out, side="right") - 1, 0, len(F) - 1)
        np.testing.assert_array_equal(r.Y[:, 0], F[idx])
    else:
        np.testing.assert_allclose(r.Y[:, 0], np.interp(t_out, t_in, F), atol=1e-12)


def test_zoh_input_fast_table(cache):
    """Dense random ZOH table: steps stop at the sample times, so the integrator is
    exact to tolerance although the input is discontinuous at every sample."""
    m = make(cache, 2, 3, 1, 0, [(0, 1), (1, 0)], MSD_RHS)
    p = (1.0, 2.0, 400.0)
    rng = np.random.default_rng(4)
    t_in = np.linspace(0.0, 1.0, 101)
    F = rng.normal(size=101) * 10
    t_out = np.linspace(0.0, 1.2, 61)
    r = m.simulate(p, t_in, F, 1, 0.0, [0.0, 0.0], t_out, rtol=1e-9, atol=1e-12)
    assert r.status == 0
    ex = msd_exact(p, t_in, F, 1, t_out, [0.0, 0.0])
    assert np.max(np.abs(r.X - ex)) < 1e-8
    # at most a few rejections per input jump (the step never straddles a jump)
    assert r.stats["steps_rejected"] < 3 * len(t_in)


def test_mixed_inputs_and_extrapolation(cache):
    """Two inputs, one linear and one ZOH; inputs constant outside the table; t0 > 0."""
    m = make(cache, 2, 0, 2, 2, [], "dx[0] = u[0]; dx[1] = u[1];", "y[0] = u[0]; y[1] = u[1];")
    t_in = np.array([1.0, 2.0, 4.0])
    U = np.array([[1.0, 1.0], [3.0, 2.0], [-1.0, 5.0]])
    t_out = np.array([0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0])
    r = m.simulate([], t_in, U, [0, 1], 0.5, [0.0, 0.0], t_out, rtol=1e-10, atol=1e-12)
    assert r.status == 0
    # integral of the piecewise-linear u0 (trapezoids) and piecewise-constant u1
    x0 = [0.0, 0.5, 0.5 + 0.75, 0.5 + 2.0, 0.5 + 2.0 + 2.0, 0.5 + 2.0 + 2.0, 2.5 + 2.0 - 2.0]
    x1 = [0.0, 0.5, 1.0, 1.5, 1.5 + 2.0, 1.5 + 4.0, 5.5 + 10.0]
    np.testing.assert_allclose(r.X[:, 0], x0, atol=1e-8)
    np.testing.assert_allclose(r.X[:, 1], x1, atol=1e-8)
    np.testing.assert_allclose(r.Y[:, 0], np.interp(t_out, t_in, U[:, 0]), atol=1e-14)
    np.testing.assert_array_equal(r.Y[:, 1], [1, 1, 1, 2, 2, 5, 5])


# ------------------------------------------------------------------ 4. failures
def test_model_status_propagates(cache):
    m = make(cache, 1, 1, 0, 1, [], "dx[0] = 1.0 + 0.0*t; if (x[0] > p[0]) return 7;",
             "y[0] = 2.0*x[0];")
    t_out = np.linspace(0.0, 2.0, 21)
    r = m.simulate([0.5], None, None, None, 0.0, [0.0], t_out, rtol=1e-6, atol=1e-9)
    assert r.status == 107
    assert "status 7" in r.message
    assert abs(r.stats["time_reached"] - 0.5) < 1e-6
    ok = t_out < 0.5 - 1e-9
    np.testing.assert_allclose(r.X[ok, 0], t_out[ok], atol=1e-9)
    assert np.all(np.isnan(r.X[~ok])) and np.all(np.isnan(r.Y[~ok]))


def test_model_status_at_start(cache):
    m = make(cache, 1, 0, 0, 0, [], "dx[0] = 1.0; if (x[0] < 0) return 3;")
    r = m.simulate([], None, None, None, 0.0, [-1.0], [0.0, 1.0])
    assert r.status == 103 and r.stats["time_reached"] == 0.0


def test_nan_detection(cache):
    m = make(cache, 2, 0, 0, 0, [(1, 0)], "dx[0] = -1.0; dx[1] = sqrt(x[0]);")
    r = m.simulate([], None, None, None, 0.0, [1.0, 0.0], np.linspace(0, 3, 31))
    assert r.status == 3
    assert r.stats["worst_state"] == 1
    assert abs(r.stats["time_reached"] - 1.0) < 1e-6
    assert "non-finite" in r.message and "index 1" in r.message


def test_nan_initial_state(cache):
    m = make(cache, 2, 0, 0, 0, [], "dx[0] = -x[0]; dx[1] = -x[1];")
    r = m.simulate([], None, None, None, 0.0, [1.0, np.nan], [0.0, 1.0])
    assert r.status == 3 and r.stats["worst_state"] == 1


def test_step_underflow_and_max_steps(cache):
    # finite-time blow-up: x' = x^2, x(0)=1 -> singular at t=1
    m = make(cache, 1, 0, 0, 0, [], "dx[0] = x[0]*x[0];")
    r = m.simulate([], None, None, None, 0.0, [1.0], [0.0, 2.0], rtol=1e-6, atol=1e-6)
    assert r.status in (1, 3)
    assert 0.99 < r.stats["time_reached"] < 1.001
    assert "t=" in r.message
    r = m.simulate([], None, None, None, 0.0, [1.0], [0.0, 0.9], max_steps=5)
    assert r.status == 2 and "maximum number of steps" in r.message


def test_hmax_and_h0(cache):
    m = make(cache, 1, 0, 0, 0, [], "dx[0] = -x[0];")
    r = m.simulate([], None, None, None, 0.0, [1.0], [0.0, 1.0], hmax=0.01, h0=1e-3)
    assert r.status == 0 and r.stats["steps_accepted"] >= 100
    assert abs(r.X[-1, 0] - np.exp(-1)) < 1e-6


def test_bad_arguments_raise(cache):
    m = make(cache, 2, 3, 1, 1, [(0, 1), (1, 0)], MSD_RHS, "y[0] = u[0];")
    p = (1.0, 1.0, 1.0)
    tin, U = np.array([0.0, 1.0]), np.zeros((2, 1))
    with pytest.raises(ValueError):
        m.simulate(p[:2], tin, U, [0], 0.0, [0, 0], [0, 1])
    with pytest.raises(ValueError):
        m.simulate(p, tin, U, [0], 0.0, [0, 0, 0], [0, 1])
    with pytest.raises(ValueError):
        m.simulate(p, tin, np.zeros((3, 1)), [0], 0.0, [0, 0], [0, 1])
    with pytest.raises(ValueError):
        m.simulate(p, np.array([0.0, 0.0]), U, [0], 0.0, [0, 0], [0, 1])
    with pytest.raises(ValueError):
        m.simulate(p, tin, U, [0], 0.0, [0, 0], [1, 0.5])
    with pytest.raises(ValueError):
        m.simulate(p, tin, U, [0], 2.0, [0, 0], [1, 3])
    with pytest.raises(ValueError):
        m.simulate(p, None, None, None, 0.0, [0, 0], [0, 1])
    with pytest.raises(ValueError):
        m.simulate(p, tin, U, [0], 0.0, [0, 0], [0, 1], atol=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        CompiledModel(m.so_path, 3, 3, 1, 1)  # sizes disagree with the library
    r = m.simulate(p, tin, U, [0], 0.0, [0, 0], [])
    assert r.status == 0 and r.X.shape == (0, 2)


# ------------------------------------------------------------------ 5. sparse path
def chain_model(n):
    """Nonlinear reaction-diffusion chain with a time-dependent boundary input."""
    pat = [(i, i - 1) for i in range(1, n)] + [(i, i + 1) for i in range(n - 1)]
    rhs = f"""
    int i;
    for (i = 0; i < {n}; ++i) {{
        double l = i > 0 ? x[i-1] : u[0], r = i < {n}-1 ? x[i+1] : 0.0;
        dx[i] = p[0]*(l - 2.0*x[i] + r) - p[1]*x[i]*x[i]*x[i];
    }}"""
    return n, pat, rhs


def arrow_model(n):
    """n-1 leaves coupled to one hub (last state), like cylinders on a supply node."""
    hub = n - 1
    pat = [(i, hub) for i in range(hub)] + [(hub, i) for i in range(hub)]
    rhs = f"""
    int i; double s = 0.0;
    for (i = 0; i < {hub}; ++i) {{
        dx[i] = -(1.0 + 0.01*i)*p[0]*(x[i] - x[{hub}]) - x[i]*x[i]*x[i];
        s += (x[i] - x[{hub}]);
    }}
    dx[{hub}] = p[1]*s/{hub} - x[{hub}] + u[0];"""
    return n, pat, rhs


def block_model(nb, bs=6):
    """nb independent dense blocks (decoupled cylinders)."""
    n = nb * bs
    pat = [(b * bs + i, b * bs + j) for b in range(nb) for i in range(bs) for j in range(bs)]
    rhs = f"""
    int b, i, j;
    for (b = 0; b < {nb}; ++b) {{
        const double *xb = x + {bs}*b; double *db = dx + {bs}*b;
        for (i = 0; i < {bs}; ++i) {{
            double s = -p[0]*(1.0 + 0.1*i + 0.01*b)*xb[i] + u[0];
            for (j = 0; j < {bs}; ++j) if (j != i) s += 0.3*sin(xb[j] - xb[i]);
            db[i] = s;
        }}
    }}"""
    return n, pat, rhs


@pytest.mark.parametrize("builder,size", [(chain_model, 240), (arrow_model, 201),
                                          (block_model, 40)])
def test_sparse_matches_dense(cache, builder, size):
    n, pat, rhs = builder(size)
    t_in = np.linspace(0.0, 2.0, 41)
    U = np.sin(3 * t_in).reshape(-1, 1) + 1.0
    x0 = np.cos(np.arange(n) * 0.37)
    t_out = np.linspace(0.0, 2.0, 21)
    p = (200.0, 50.0)
    res = {}
    for name, prelude in (("auto", ""), ("dense", "#define HY_FORCE_DENSE"),
                          ("sparse", "#define HY_FORCE_SPARSE"),
                          ("fallback", "#define HY_FORCE_SPARSE\n#define HY_PIVTOL 1e300")):
        m = make(cache, n, 2, 1, 0, pat, rhs, prelude=prelude)
        r = m.simulate(p, t_in, U, [0], 0.0, x0, t_out, rtol=1e-8, atol=1e-10)
        assert r.status == 0, (name, r.message)
        res[name] = r
    ref = res["dense"].X
    for name in ("auto", "sparse", "fallback"):
        np.testing.assert_allclose(res[name].X, ref, rtol=1e-6, atol=1e-8, err_msg=name)
    # the step sequence is essentially the same (only rounding differs)
    na, nd = res["auto"].stats["steps_accepted"], res["dense"].stats["steps_accepted"]
    assert abs(na - nd) <= 0.02 * nd + 2


def test_sparse_vs_scipy_reference(cache):
    n, pat, rhs = arrow_model(60)
    m = make(cache, n, 2, 1, 0, pat, rhs)
    p = (200.0, 50.0)
    x0 = np.cos(np.arange(n) * 0.37)
    t_out = np.linspace(0.0, 1.0, 11)

    def f(t, x):
        hub = n - 1
        k = (1.0 + 0.01 * np.arange(hub)) * p[0]
        dx = np.empty(n)
        dx[:hub] = -k * (x[:hub] - x[hub]) - x[:hub] ** 3
        dx[hub] = p[1] * np.sum(x[:hub] - x[hub]) / hub - x[hub] + 1.5
        return dx

    ref = solve_ivp(f, (0, 1), x0, method="Radau", rtol=1e-10, atol=1e-12, t_eval=t_out)
    r = m.simulate(p, [0.0], [[1.5]], [0], 0.0, x0, t_out, rtol=1e-9, atol=1e-11)
    assert r.status == 0
    assert np.max(np.abs(r.X - ref.y.T)) < 1e-7


# ------------------------------------------------------------------ 6. caching
def test_cache_reuse_without_compiler(cache, monkeypatch):
    src = model_source(1, 1, 0, 0, [], "dx[0] = -p[0]*x[0];")
    so1 = build_library(src, cache_dir=cache)
    mtime = so1.stat().st_mtime_ns

    def boom(*a, **k):
        raise AssertionError("compiler invoked for a cached model")

    monkeypatch.setattr(compiled.subprocess, "run", boom)
    so2 = build_library(src, cache_dir=cache)
    assert so2 == so1 and so2.stat().st_mtime_ns == mtime
    # new parameters: same library, no compilation, different results
    m = CompiledModel(so2, 1, 1, 0, 0)
    r1 = m.simulate([1.0], None, None, None, 0.0, [1.0], [0.0, 1.0], rtol=1e-9, atol=1e-12)
    r2 = m.simulate([2.0], None, None, None, 0.0, [1.0], [0.0, 1.0], rtol=1e-9, atol=1e-12)
    assert abs(r1.X[-1, 0] - np.exp(-1)) < 1e-8 and abs(r2.X[-1, 0] - np.exp(-2)) < 1e-8
    assert sorted(p.name for p in cache.glob("*.so")) == [so1.name]


def test_integrator_headers_are_inlined():
    """The cached translation unit is self-contained: no include of the integrator's headers."""
    text = compiled.integrator_source()
    assert '#include "hy_' not in text and "R_GAM" in text and "hy_lu_dense" in text


def test_cache_key_and_env_dir(tmp_path, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "envcache"))
    a = build_library(model_source(1, 0, 0, 0, [], "dx[0] = -x[0];"))
    b = build_library(model_source(1, 0, 0, 0, [], "dx[0] = -2.0*x[0];"))
    assert a.parent == tmp_path / "envcache" and a != b
    # the integrator text is part of the key
    original = compiled.integrator_source()
    monkeypatch.setattr(compiled, "integrator_source", lambda: original + "\n/* changed */\n")
    c = build_library(model_source(1, 0, 0, 0, [], "dx[0] = -x[0];"))
    assert c != a
    assert not list((tmp_path / "envcache").glob(".hy_*"))  # no temporaries left


def test_compile_error(cache):
    with pytest.raises(CompileError) as ei:
        build_library(model_source(1, 0, 0, 0, [], "dx[0] = undefined_symbol;"), cache_dir=cache)
    assert "undefined_symbol" in str(ei.value)
    assert not list(cache.glob("*.so"))


def test_missing_compiler(cache, monkeypatch):
    monkeypatch.setenv("CC", "definitely-not-a-compiler-xyz")
    with pytest.raises(CompileError, match="not found"):
        build_library(model_source(1, 0, 0, 0, [], "dx[0] = -x[0];"), cache_dir=cache)


# ------------------------------------------------------------------ 7. pickling / processes
def _worker(model, p, t_out):
    r = model.simulate(p, np.array([0.0, 1.0]), np.array([[0.0], [1.0]]), [0], 0.0,
                       [0.0, 0.0], t_out, rtol=1e-8, atol=1e-10)
    return r.X, r.status, os.getpid()


def test_pickle_process_pool(cache):
    m = make(cache, 2, 3, 1, 1, [(0, 1), (1, 0)], MSD_RHS, "y[0] = u[0];")
    m2 = pickle.loads(pickle.dumps(m))
    assert m2.so_path == m.so_path and (m2.nx, m2.np_, m2.nu, m2.ny) == (2, 3, 1, 1)
    t_out = np.linspace(0.0, 3.0, 31)
    params = [(1.0, 0.5, 10.0 + i) for i in range(4)]
    local = [_worker(m, p, t_out) for p in params]
    with ProcessPoolExecutor(max_workers=2) as ex:
        remote = list(ex.map(_worker, [m] * 4, params, [t_out] * 4))
    for (xl, sl, _), (xr, sr, pid) in zip(local, remote):
        assert sl == sr == 0
        np.testing.assert_array_equal(xl, xr)
    assert all(pid != os.getpid() for *_, pid in remote)


def test_concurrent_builds_are_atomic(tmp_path):
    """Several processes building the same source at once all get a loadable library."""
    src = model_source(1, 0, 0, 0, [], "dx[0] = -3.0*x[0];")
    with ProcessPoolExecutor(max_workers=2) as ex:
        paths = list(ex.map(_build_and_run, [src] * 4, [str(tmp_path)] * 4))
    assert len({p for p, _ in paths}) == 1
    assert all(abs(v - np.exp(-3)) < 1e-7 for _, v in paths)


def _build_and_run(src, cache_dir):
    so = build_library(src, cache_dir=cache_dir)
    m = CompiledModel(so, 1, 0, 0, 0)
    r = m.simulate([], None, None, None, 0.0, [1.0], [0.0, 1.0], rtol=1e-9, atol=1e-12)
    return str(so), float(r.X[-1, 0])


def test_analytic_jacobian_hook(cache):
    """Optional HY_HAS_JAC: the generator may emit hy_jac (values in CSR order)."""
    prelude = """
#define HY_HAS_JAC
static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv);
"""
    src = model_source(2, 1, 0, 0, dense_pattern(2),
                       "dx[0] = x[1]; dx[1] = p[0]*((1.0 - x[0]*x[0])*x[1] - x[0]);",
                       prelude=prelude)
    src += """
static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv)
{
    (void)t; (void)u;
    jv[0] = 0.0; jv[1] = 1.0;
    jv[2] = p[0]*(-2.0*x[0]*x[1] - 1.0); jv[3] = p[0]*(1.0 - x[0]*x[0]);
    return 0;
}
"""
    m = CompiledModel(build_library(src, cache_dir=cache), 2, 1, 0, 0)
    fd = make(cache, 2, 1, 0, 0, dense_pattern(2),
              "dx[0] = x[1]; dx[1] = p[0]*((1.0 - x[0]*x[0])*x[1] - x[0]);")
    t = np.linspace(0, 20, 41)
    ra = m.simulate([10.0], None, None, None, 0.0, [2.0, 0.0], t, rtol=1e-9, atol=1e-11)
    rf = fd.simulate([10.0], None, None, None, 0.0, [2.0, 0.0], t, rtol=1e-9, atol=1e-11)
    assert ra.status == rf.status == 0
    np.testing.assert_allclose(ra.X, rf.X, atol=1e-6)
    assert ra.stats["rhs_evals"] < rf.stats["rhs_evals"]


# ------------------------------------------------------------------ 8. method coefficients
# HY_METHOD selects the RODAS coefficient set: 1 Rodas4, 2 Rodas4P, 3 Rodas5P (default).
# The tables are verified here by their convergence orders at FIXED steps (h0 = hmax,
# error test disabled by a huge rtol with atol/rtol tiny so FD scaling stays sane) with an
# analytic Jacobian (HY_HAS_JAC), so that only the coefficients are tested.
METHODS = {1: "rodas4", 2: "rodas4p", 3: "rodas5p"}
_JAC_PRELUDE = """
#define HY_HAS_JAC
static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv);
"""
# smooth, nonlinear, non-autonomous, exact solution e(t) = (1/(1+t) + sin t, cos 2t e^{-t/3})
SMOOTH_RHS = """
    double e0 = 1.0/(1.0+t) + sin(t), e1 = cos(2.0*t)*exp(-t/3.0);
    double r0 = -1.0/((1.0+t)*(1.0+t)) + cos(t), r1 = (-2.0*sin(2.0*t) - cos(2.0*t)/3.0)*exp(-t/3.0);
    dx[0] = -x[0]*x[0] + x[0]*x[1] - (-e0*e0 + e0*e1) + r0;
    dx[1] = -x[1]*x[1]*x[1] + sin(x[0]) - (-e1*e1*e1 + sin(e0)) + r1;
"""
SMOOTH_JAC = """
static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv)
{
    (void)t; (void)p; (void)u;
    jv[0] = -2.0*x[0] + x[1]; jv[1] = x[0]; jv[2] = cos(x[0]); jv[3] = -3.0*x[1]*x[1];
    return 0;
}
"""


def smooth_exact(t):
    return np.array([1 / (1 + t) + np.sin(t), np.cos(2 * t) * np.exp(-t / 3)])


# Prothero-Robinson y' = lam (y - g(t)) + g'(t), g = sin 2t + cos t, lam = -1e6, written
# autonomously (x0 = t) so that f_t is exact (a forward difference of lam*g(t) in t would
# lose ~8 digits by cancellation at lam = -1e6 and mask the method error).
PR_RHS = """
    dx[0] = 1.0;
    dx[1] = p[0]*(x[1] - (sin(2.0*x[0]) + cos(x[0]))) + 2.0*cos(2.0*x[0]) - sin(x[0]);
"""
PR_JAC = """
static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv)
{
    (void)t; (void)u;
    jv[0] = 0.0; jv[1] = 0.0;
    jv[2] = -p[0]*(2.0*cos(2.0*x[0]) - sin(x[0])) - 4.0*sin(2.0*x[0]) - cos(x[0]);
    jv[3] = p[0];
    return 0;
}
"""


def pr_exact(t):
    return np.array([t, np.sin(2 * t) + np.cos(t)])


def _method_model(cache, method, rhs, jac):
    prelude = f"#define HY_METHOD {method}\n" + _JAC_PRELUDE
    src = model_source(2, 1, 0, 0, dense_pattern(2), rhs, prelude=prelude) + jac
    return CompiledModel(build_library(src, cache_dir=cache), 2, 1, 0, 0)


def _fixed_step_errors(m, p, exact, T=2.0, Ns=(10, 20, 40, 80, 160), theta=0.37):
    """End-point and dense-output (inside the last step) errors at N fixed steps."""
    end, dense = [], []
    for N in Ns:
        h = T / N
        t_out = np.array([0.0, T - (1 - theta) * h, T])
        r = m.simulate(p, None, None, None, 0.0, exact(0.0), t_out, rtol=1e6, atol=1e-6,
                       h0=h, hmax=h)
        assert r.status == 0
        assert r.stats["steps_accepted"] == N and r.stats["steps_rejected"] == 0
        end.append(np.max(np.abs(r.X[-1] - exact(T))))
        dense.append(np.max(np.abs(r.X[1] - exact(t_out[1]))))
    return np.array(end), np.array(dense)


def _orders(e):
    return np.log2(e[:-1] / e[1:])


@pytest.mark.parametrize("method,order", [(1, 4), (2, 4), (3, 5)])
def test_method_order_smooth(cache, method, order):
    """Nominal order on a smooth nonlinear non-autonomous problem (halving h)."""
    m = _method_model(cache, method, SMOOTH_RHS, SMOOTH_JAC)
    end, dense = _fixed_step_errors(m, [0.0], smooth_exact)
    o = _orders(end)
    # asymptotic order: the last two halvings; Rodas4 shows ~4.8 on this problem
    assert np.all(o[-2:] > order - 0.3), (METHODS[method], o)
    if order == 5:
        assert np.all(o[-2:] > 4.6)  # really fifth order, not a fourth-order method
    # dense output inside a step: local error O(h^(q+1)), q = 3 (Rodas4/4P), 4 (Rodas5P)
    od = _orders(dense)
    assert np.all(od[-2:] > (order - 1) + 1 - 0.35), (METHODS[method], od)


def test_method_order_prothero_robinson(cache):
    """lam = -1e6: Rodas4 loses order (~1), Rodas4P/Rodas5P keep order ~3 and are far
    more accurate, both at the step ends and in the dense output."""
    res = {}
    for method in METHODS:
        m = _method_model(cache, method, PR_RHS, PR_JAC)
        res[method] = _fixed_step_errors(m, [-1e6], pr_exact, Ns=(10, 20, 40, 80))
    o4 = _orders(res[1][0])
    assert np.all(o4 < 2.0), o4  # the known order reduction of Rodas4
    for method in (2, 3):
        end, dense = res[method]
        o = _orders(end)
        assert np.all(o > 2.7), (METHODS[method], o)
        assert np.all(end < res[1][0] / 30), (METHODS[method], end, res[1][0])
        od = _orders(dense)
        assert np.all(od[-2:] > 3.6), (METHODS[method], od)
        assert np.all(dense < res[1][1] / 10)


def test_default_method_is_rodas5p(cache):
    """Without HY_METHOD the integrator is Rodas5P (bit-identical results)."""
    t = np.linspace(0.0, 2.0, 21)
    src = model_source(2, 1, 0, 0, dense_pattern(2), SMOOTH_RHS, prelude=_JAC_PRELUDE) + SMOOTH_JAC
    m_def = CompiledModel(build_library(src, cache_dir=cache), 2, 1, 0, 0)
    m_5p = _method_model(cache, 3, SMOOTH_RHS, SMOOTH_JAC)
    r1 = m_def.simulate([0.0], None, None, None, 0.0, smooth_exact(0.0), t, rtol=1e-6, atol=1e-9)
    r2 = m_5p.simulate([0.0], None, None, None, 0.0, smooth_exact(0.0), t, rtol=1e-6, atol=1e-9)
    np.testing.assert_array_equal(r1.X, r2.X)
    assert r1.stats == r2.stats


@pytest.mark.parametrize("method", [1, 2, 3])
def test_method_tolerance_proportionality(cache, method):
    """Adaptive runs of every method: error falls with rtol and stays near it."""
    m = _method_model(cache, method, SMOOTH_RHS, SMOOTH_JAC)
    t = np.linspace(0.0, 5.0, 101)
    ex = np.array([smooth_exact(s) for s in t])
    errs = []
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
        r = m.simulate([0.0], None, None, None, 0.0, smooth_exact(0.0), t, rtol=rtol, atol=rtol)
        assert r.status == 0
        errs.append(np.max(np.abs(r.X - ex)))
    errs = np.array(errs)
    assert np.all(errs[1:] < errs[:-1] / 10), errs
    assert np.all(errs < 100 * np.array([1e-4, 1e-6, 1e-8, 1e-10])), errs
