"""Effect components: Padé delay reproduces a delayed ramp, a delay behind a filter is first
order plus dead time, play holds inside its band, pressure sensor lags by τ."""
import numpy as np
import pytest

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate


def _run(block: str, params: str, t, u):
    text = f"""
name: t
inputs: {{u: {{unit: "1"}}}}
components:
  blk: {{type: {block}, ports: {{in: u, out: y}}{params}}}
outputs: {{y: y}}
"""
    model = build_model(load_netlist_text(text, "t.yaml"))
    return simulate(model, InputTable(t, u[:, None]), t, opts=SolverOptions(rtol=1e-8, backend="python")).Y[:, 0]


def test_pade_delay_delays_a_smooth_signal():
    t = np.linspace(0, 2, 2001)
    u = np.sin(2 * np.pi * 1.0 * t) * (t > 0.2) * np.minimum((t - 0.2) / 0.2, 1)
    y = _run("pade_delay", ", T: 0.01", t, u)
    ref = np.interp(t - 0.01, t, u)
    assert np.max(np.abs(y - ref)[t > 0.5]) < 0.01


def test_lagged_delay_is_first_order_plus_dead_time():
    """A sine through e^{−sT}/(1 + τs), T = (1 − s)·D and τ = s·D: gain 1/√(1 + (ωτ)²), phase
    −ωT − atan(ωτ) (the closed form of the transfer function); a ramp trails by D = T + τ."""
    t = np.linspace(0, 3, 30001)
    D, share, f = 0.02, 0.4, 3.0
    T, tau, w = (1 - share) * D, share * D, 2 * np.pi * f
    u = np.sin(w * t)
    y = _run("lagged_delay", f", D: {D}, s: {share}", t, u)
    ref = np.sin(w * t - w * T - np.arctan(w * tau)) / np.sqrt(1 + (w * tau) ** 2)
    late = t > 1.0
    assert np.max(np.abs(y - ref)[late]) < 2e-3
    assert np.max(np.abs(y - u)[late]) > 0.3           # it does delay (3 Hz, 20 ms: 0.37 rad)
    ramp = _run("lagged_delay", f", D: {D}, s: {share}", t, 0.5 * t)
    assert np.max(np.abs(ramp - 0.5 * (t - D))[late]) < 1e-6


def test_play_holds_inside_the_band_and_follows_outside():
    t = np.linspace(0, 4, 4001)
    u = 0.05 * np.sin(2 * np.pi * 0.5 * t)
    y = _run("play", ", b: 0.01", t, u)
    # after the peak the output stays until the input has come back by 2b
    k = np.argmin(np.abs(t - 0.5))
    assert y[k] == pytest.approx(0.04, abs=2e-3)
    assert np.max(y) == pytest.approx(0.04, abs=2e-3)
    assert np.min(y[t > 1]) == pytest.approx(-0.04, abs=2e-3)


def test_dahl_loop_follows_its_closed_form_branches():
    """On a monotone input the Dahl state solves dz/dw = σ(1 − z/h): from z0 at w0,
    z = h + (z0 − h)·exp(−σ(w − w0)/h) (going up), mirrored going down; w is the input through
    the rate filter τ_r (a ramp's w trails it by τ_r). Up from 0, then down from the peak."""
    t = np.linspace(0, 2, 4001)
    rate, h, sigma, tau_r = 0.05, 0.01, 2.0, 2e-3
    u = rate * np.where(t < 1.0, t, 2.0 - t)
    y = _run("dahl_hysteresis", f", h: {h}, sigma: {sigma}, tau_r: {tau_r}", t, u)
    z = u - y
    w = rate * np.where(t < 1.0, t - tau_r * (1 - np.exp(-t / tau_r)), 0.0)
    up = (t > 0.05) & (t < 0.99)
    ref_up = h * (1 - np.exp(-sigma * w[up] / h))
    assert np.max(np.abs(z[up] - ref_up)) < 1e-6 * h
    # going down, from a point past the reversal (the filter's transient over): w trails u by
    # the same τ_r·rate all along the branch, so the travel in w is the travel in u
    k = np.argmin(np.abs(t - 1.05))
    down = (t > 1.05) & (t < 1.99)
    ref_down = -h + (z[k] + h) * np.exp(-sigma * (u[k] - u[down]) / h)
    assert np.max(np.abs(z[down] - ref_down)) < 1e-6 * h
    # the output trails the input by h in the direction of motion, the loop's width is 2h
    assert z[np.argmin(np.abs(t - 0.9))] == pytest.approx(h, rel=1e-3)
    assert z[np.argmin(np.abs(t - 1.9))] == pytest.approx(-h, rel=1e-3)
