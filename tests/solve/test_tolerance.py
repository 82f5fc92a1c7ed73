"""The achieved error tracks the requested tolerance under ``error_control="scaled"``.

Over rtol 1e-3 … 1e-8 the maximum error against an independent, tighter reference must
be within a small factor of rtol × the signal's scale and must fall with rtol:
1. a stiff closed-form problem driven by a 1 kHz piecewise-linear table (exact solution
   segment by segment), through the compiled integrator with the kink landing on;
2. seed 004's EHA under the quick-start recording's inputs (slow);
3. the Festo TP511 machine under voltage steps (slow).
For the machines the reference is the compiled integrator at rtol 1e-11 (``scaled``);
the hand-written EHA under scipy Radau checks that reference in ``hydro bench``.
"""
from __future__ import annotations

from hydrocli.experiments.initial import initial_state

from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_experiment
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.compiled import CompiledModel, build_library
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate, state_scales

ROOT = Path(__file__).resolve().parents[2]
RTOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)

PR_SOURCE = """
#include <math.h>
#define HY_NX 2
#define HY_NP 2
#define HY_NU 1
#define HY_NY 0
#define HY_NNZ 2
static const int HY_JAC_ROW[2] = {0, 1};
static const int HY_JAC_COL[2] = {0, 1};
static int hy_rhs(double t, const double *x, const double *p, const double *u, double *dx)
{ (void)t; dx[0] = -p[0] * (x[0] - u[0]); dx[1] = -p[1] * (x[1] - u[0]); return 0; }
static int hy_out(double t, const double *x, const double *p, const double *u, double *y)
{ (void)t; (void)x; (void)p; (void)u; (void)y; return 0; }
"""


def pl_exact(t, u, lam, x0):
    """x' = -lam (x - u(t)) with u linear on each [t_k, t_k+1]: on a segment with slope b,
    x = u - b/lam + (x_k - u_k + b/lam) e^(-lam (t - t_k)) (exact at the samples)."""
    x = np.empty_like(u)
    x[0] = x0
    for k in range(len(t) - 1):
        dt = t[k + 1] - t[k]
        b = (u[k + 1] - u[k]) / dt
        x[k + 1] = u[k + 1] - b / lam + (x[k] - u[k] + b / lam) * np.exp(-lam * dt)
    return x


def assert_tracks(errs: list[float], scale: float, factor: float, what: str, loose: float | None = None) -> None:
    """error ≤ factor · rtol · scale for rtol ≤ 1e-5 (≤ loose · … at 1e-3, 1e-4), falling with rtol."""
    ratios = [e / (r * scale) for e, r in zip(errs, RTOLS)]
    msg = f"{what}: errors {['%.2e' % e for e in errs]}, error/(rtol·scale) {['%.1f' % q for q in ratios]}"
    assert max(ratios[2:]) < factor, msg
    assert max(ratios[:2]) < (loose or factor), msg
    assert all(b < a for a, b in zip(errs, errs[1:])), "not monotone in rtol: " + msg


def test_stiff_closed_form_tracks_rtol(tmp_path):
    """Stiff (lam 1e4) and non-stiff (lam 3) states driven by a 1 kHz table with a 5 Hz sine
    and a step command ramped over one sample: error within 30 × rtol of the unit scale
    (measured ratios 13, 10, 29, 1.2, 0.6, 1e-4: the stiff state between steps that cross
    small kinks is the loose end)."""
    lib = CompiledModel(build_library(PR_SOURCE, cache_dir=tmp_path), 2, 2, 1, 0)
    t = np.arange(0.0, 2.0 + 5e-4, 1e-3)
    u = 0.5 * np.sin(2 * np.pi * 5 * t) + 0.5 * (np.sin(2 * np.pi * 0.7 * t) > 0)
    lam = (1e4, 3.0)
    exact = np.column_stack([pl_exact(t, u, lam[0], 0.0), pl_exact(t, u, lam[1], 0.0)])
    errs = []
    for rtol in RTOLS:
        r = lib.simulate(lam, t, u, [2], 0.0, [0.0, 0.0], t, rtol=rtol, atol=rtol * np.ones(2))
        assert r.status == 0, r.message
        errs.append(float(np.max(np.abs(r.X - exact))))
    assert_tracks(errs, 1.0, 30.0, "stiff closed form")


def test_kink_landing_cuts_rejections(tmp_path):
    """Steps of about one sample interval that cross kinks are rejected again and again;
    ending them on the kinks (u_hold = 2) removes most rejections at the same accuracy."""
    lib = CompiledModel(build_library(PR_SOURCE, cache_dir=tmp_path), 2, 2, 1, 0)
    t = np.arange(0.0, 2.0 + 5e-4, 1e-3)
    u = 0.5 * np.sin(2 * np.pi * 5 * t) + 0.01 * np.sin(2 * np.pi * 170 * t)
    exact = pl_exact(t, u, 1e4, 0.0)
    runs = {hold: lib.simulate((1e4, 3.0), t, u, [hold], 0.0, [0.0, 0.0], t, rtol=1e-8, atol=1e-8)
            for hold in (0, 2)}
    e0, e2 = (np.max(np.abs(runs[h].X[:, 0] - exact)) for h in (0, 2))
    assert runs[2].stats["steps_rejected"] < 0.5 * runs[0].stats["steps_rejected"]
    assert e2 < 5e-8 and e2 < 3 * e0


def _machine_errors(model, inputs, t, x0, cols):
    ref = simulate(model, inputs, t, x0=x0, opts=SolverOptions(rtol=1e-11, error_control="scaled")).X[:, cols]
    errs = []
    for rtol in RTOLS:
        X = simulate(model, inputs, t, x0=x0, opts=SolverOptions(rtol=rtol, error_control="scaled")).X[:, cols]
        errs.append(float(np.max(np.abs(X - ref))))
    return errs, ref


@pytest.mark.slow
def test_eha_quickstart_tracks_rtol():
    model = build_model(load_netlist(ROOT / "machines" / "eha_testbench.yaml"))
    exp = load_experiment(ROOT / "experiments" / "quickstart" / "train.yaml", model)
    keep = exp.inputs.t <= 10.0
    inputs = InputTable(exp.inputs.t[keep], exp.inputs.U[keep])
    p_cols = [model.state_index("chamber_1.p"), model.state_index("chamber_2.p")]
    errs, ref = _machine_errors(model, inputs, inputs.t, initial_state(model, exp), p_cols)
    # measured: 44, 83 (loose: stick-slip events of the friction), then 2.1, 3.2, 2.8, 3.3
    assert_tracks(errs, float(state_scales(model)[p_cols[0]]), 6.0, "EHA quick-start pressures", loose=150.0)


@pytest.mark.slow
def test_festo_steps_track_rtol():
    # the machine the bounds were measured on (no end cushions: their needle flows at the
    # stroke ends give ratios up to ~23 at rtol 1e-5; docs/solver.md)
    model = build_model(load_netlist(Path(__file__).parent / "data" / "festo_tp511_no_cushion.yaml"))
    t = np.arange(0.0, 3.0 + 1e-4, 2e-3)
    u = np.interp(t, [0, 0.1, 0.102, 1.4, 1.402, 1.5, 1.502, 3.0], [0, 0, 4, 4, 0, 0, -4, -4])
    inputs = InputTable(t, u[:, None])
    p_cols = [i for i, s in enumerate(model.states) if s.unit == "Pa"]
    errs, ref = _machine_errors(model, inputs, t, model.x0, p_cols)
    # measured: 8.1, 1.1, 1.7, 2.7, 1.3, 1.4
    assert_tracks(errs, float(state_scales(model)[p_cols[0]]), 6.0, "Festo pressures", loose=15.0)

