"""Effect components: Padé delay reproduces a delayed ramp, play holds inside its band,
pressure sensor lags by τ."""
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


def test_play_holds_inside_the_band_and_follows_outside():
    t = np.linspace(0, 4, 4001)
    u = 0.05 * np.sin(2 * np.pi * 0.5 * t)
    y = _run("play", ", b: 0.01", t, u)
    # after the peak the output stays until the input has come back by 2b
    k = np.argmin(np.abs(t - 0.5))
    assert y[k] == pytest.approx(0.04, abs=2e-3)
    assert np.max(y) == pytest.approx(0.04, abs=2e-3)
    assert np.min(y[t > 1]) == pytest.approx(-0.04, abs=2e-3)
