"""The joint with clearance (``clearance``, ``rotary_clearance``): a body launched from the middle
of the clearance against the closed forms of a free flight and a Kelvin–Voigt contact — it
crosses half the clearance at its launch speed, touches for half a period of the contact's
damped mode π/ω_d, and leaves at the restitution e = exp(−ζπ/√(1 − ζ²)) times its speed
(ζ = c/(2√(k·m))); without contact damping it keeps its energy. And b = 0 is the plain
spring–damper."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hydrocli.components.mechanical.clearance import SMOOTHING
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

M, K, V0, GAP = 2.0, 2.0e4, 0.05, 2e-3        # kg, N/m, m/s, m: 20 ms of free flight, a 31 ms contact
# pressed 0.5 mm, 12 times the rounding of its corners (clearance.SMOOTHING · GAP)

TRANSLATIONAL = """
name: clearance_{kind}
inputs: {{u: {{unit: "1"}}}}
components:
  body: {{type: mass, ports: {{m: n}}, m: {m}}}
  joint: {{type: clearance, ports: {{a: n, b: ground}}, k: {k}, c: {c}, b: {b}, eps: 1.0e-7}}
outputs: {{x: n.x, v: n.v, F: joint.F}}
initial: {{n.v: {v0}}}
"""

ROTARY = """
name: clearance_{kind}
inputs: {{u: {{unit: "1"}}}}
components:
  body: {{type: inertia, ports: {{r: n}}, J: {m}}}
  joint: {{type: rotary_clearance, ports: {{a: n, b: ground}}, k: {k}, c: {c}, b: {b}, eps: 1.0e-7}}
outputs: {{x: n.theta, v: n.w, F: joint.tau}}
initial: {{n.w: {v0}}}
"""


def _run(template: str, c: float, b: float, t_end: float = 0.15):
    model = build_model(load_netlist_text(template.format(kind="t", m=M, k=K, c=c, b=b, v0=V0)))
    t = np.linspace(0.0, t_end, 60001)
    res = simulate(model, InputTable(np.array([0.0]), np.array([[0.0]])), t,
                   opts=SolverOptions(rtol=1e-10, atol_factor=1e-4))
    return t, {o: res.Y[:, i] for i, o in enumerate(model.output_names)}


def _contact(t, y):
    """(in, out): when the body first reaches half the clearance, and when it is back there."""
    i = int(np.argmax(y["x"] >= 0.5 * GAP))
    j = i + int(np.argmax(y["x"][i:] < 0.5 * GAP))
    return t[i], t[j]


def _dead_zone(d):
    """The element's D(d) in numpy: softplus corners over SMOOTHING·GAP (+ its ε floor)."""
    w = SMOOTHING * GAP + 1e-7
    sp = lambda x: np.maximum(x, 0.0) + w * np.log1p(np.exp(-np.abs(x) / w))   # noqa: E731
    return sp(d - 0.5 * GAP) - sp(-d - 0.5 * GAP)


@pytest.mark.parametrize("template", [TRANSLATIONAL, ROTARY], ids=["clearance", "rotary_clearance"])
def test_free_flight_then_an_elastic_contact_keeps_the_energy(template):
    t, y = _run(template, c=0.0, b=GAP)
    flight = 0.5 * GAP / V0
    t_in, t_out = _contact(t, y)
    # free flight across half the clearance at the launch speed (nothing acts inside it)
    assert abs(t_in - flight) < 0.01 * flight
    assert np.allclose(y["v"][t < 0.8 * flight], V0, rtol=1e-3)
    # half a period of the contact's mode beyond it, π/ω (its rounded corners shorten it a little)
    w = math.sqrt(K / M)
    assert abs((t_out - t_in) - math.pi / w) < 0.03 * math.pi / w
    # pressed v0/ω beyond the half clearance; back at −v0 once free again
    assert abs(np.max(y["x"]) - (0.5 * GAP + V0 / w)) < 0.03 * V0 / w
    after = (t > t_out + 0.3 * flight) & (t < t_out + 1.5 * flight)
    assert np.allclose(y["v"][after], -V0, rtol=1e-3)
    # energy: ½m·v² + ∫k·D(s)ds, the contact's potential over the dead zone
    grid = np.linspace(-GAP, GAP, 40001)
    potential = np.concatenate([[0.0], np.cumsum(0.5 * (_dead_zone(grid[1:]) + _dead_zone(grid[:-1])) * np.diff(grid))])
    potential -= np.interp(0.0, grid, potential)
    energy = 0.5 * M * y["v"] ** 2 + K * np.interp(y["x"], grid, potential)
    assert np.max(np.abs(energy - 0.5 * M * V0 ** 2)) < 1e-4 * 0.5 * M * V0 ** 2


@pytest.mark.parametrize("template", [TRANSLATIONAL, ROTARY], ids=["clearance", "rotary_clearance"])
def test_damped_contact_rebounds_at_the_kelvin_voigt_restitution(template):
    zeta = 0.1
    c = 2 * zeta * math.sqrt(K * M)
    t, y = _run(template, c=c, b=GAP)
    _, t_out = _contact(t, y)
    flight = 0.5 * GAP / V0
    after = (t > t_out + 0.3 * flight) & (t < t_out + 1.5 * flight)
    e = math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2))
    assert np.allclose(y["v"][after], -e * V0, rtol=0.03)
    # the damping acts in contact only: the free flight before it keeps the launch speed
    assert np.allclose(y["v"][t < 0.8 * flight], V0, rtol=1e-3)


def test_no_clearance_is_the_spring_damper():
    """b = 0: the mass on k and c oscillates at the damped frequency with the damped decay."""
    zeta = 0.05
    c = 2 * zeta * math.sqrt(K * M)
    t, y = _run(TRANSLATIONAL, c=c, b=0.0, t_end=0.2)
    w = math.sqrt(K / M)
    wd = w * math.sqrt(1 - zeta ** 2)
    exact = V0 / wd * np.exp(-zeta * w * t) * np.sin(wd * t)
    assert np.max(np.abs(y["x"] - exact)) < 1e-5 * V0 / w
