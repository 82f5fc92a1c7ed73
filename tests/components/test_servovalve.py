"""Jiles–Atherton hysteresis of the SARCOS servovalve (seed 001 eqs. 1–2, Fig. 2)."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from simhelpers import col, run

JA = dict(i_s=0.5, mu0=8.0, alpha=0.05, k=0.2, Lambda=1.0)
TEXT = """
name: ja
inputs: {i: {unit: A}}
components:
  sv: {type: servovalve_jet, ports: {P: ps, T: pt, A: na, B: nb, cmd: i}, tau_c: 1e-3}
  s1: {type: pressure_source, ports: {P: ps}, p: 200e5}
  s2: {type: tank, ports: {T: pt}}
  s3: {type: pressure_source, ports: {P: na}, p: 100e5}
  s4: {type: pressure_source, ports: {P: nb}, p: 100e5}
"""


def paper_eq1(i, ih, di):
    """Seed 001 eq. 1 written out directly (independent of the component's expression code)."""
    x = JA["mu0"] * (i + JA["alpha"] * ih)
    lang = x / 3 if abs(x) < 1e-3 else 1 / np.tanh(x) - 1 / x
    diff = JA["i_s"] * lang - ih
    d = 1.0 if di >= 0 else -1.0
    if diff * d <= 0:
        return 0.0
    return JA["Lambda"] * JA["mu0"] * diff / (JA["k"] * d - JA["mu0"] * JA["alpha"] * diff)


def _simulate(current, t_end, n):
    m, tr, _ = run(TEXT, t_end, n=n, inputs=lambda t: {"i": current(t)}, rtol=1e-8)
    return tr.t, col(m, tr, "sv.i_c"), col(m, tr, "sv.i_hys")


def _remanence(t, i, ih):
    """i_hys where the input crosses zero, and the crossing direction (+1 rising)."""
    k = np.where(np.sign(i[:-1]) != np.sign(i[1:]))[0]
    k = k[(i[k] != 0)]
    w = -i[k] / (i[k + 1] - i[k])
    return ih[k] + w * (ih[k + 1] - ih[k]), np.sign(i[k + 1] - i[k]), t[k]


def test_matches_direct_integration_of_eq1():
    cur = lambda t: 0.4 * np.sin(t)
    t, i, ih = _simulate(cur, 8.0, 801)
    tau = 1e-3

    def rhs(tt, y):
        ic, h = y
        di = (cur(tt) - ic) / tau
        return [di, paper_eq1(ic, h, di) * di]
    ref = solve_ivp(rhs, (0, 8), [0.0, 0.0], t_eval=t, method="LSODA", rtol=1e-9, atol=1e-12, max_step=1e-3)
    assert np.max(np.abs(ih - ref.y[1])) < 2e-3


def test_major_loop_saturates_and_closes():
    """Large periodic input: i_hys saturates below i_s; consecutive cycles retrace the loop."""
    t, i, ih = _simulate(lambda t: 3.0 * np.sin(t), 6 * np.pi, 6001)
    assert 0.85 * JA["i_s"] < ih.max() < JA["i_s"]
    one = int(np.searchsorted(t, 2 * np.pi))
    two = int(np.searchsorted(t, 4 * np.pi))
    k = np.arange(one, two)
    assert np.max(np.abs(ih[k + (two - one)] - ih[k])) < 0.01 * JA["i_s"]
    rem, direction, _ = _remanence(t, i, ih)
    assert np.all(rem[direction > 0] < -0.02) and np.all(rem[direction < 0] > 0.02)   # a real loop


def test_decreasing_amplitude_minor_loops_shrink():
    """Fig. 2: a decaying sinusoid traces nested loops whose width (remanence) shrinks, and the
    memory fades (the paper's pre-experiment demagnetising current)."""
    t, i, ih = _simulate(lambda t: 0.6 * np.exp(-t / 15) * np.sin(t), 60.0, 12001)
    rem, direction, tc = _remanence(t, i, ih)
    widths = np.abs(rem[1:])
    assert np.all(np.diff(widths[::2]) < 0) and np.all(np.diff(widths[1::2]) < 0)
    assert widths[-1] < 0.2 * widths[0]
    assert abs(ih[-1]) < 0.02
