"""The resonant pressure transducer (components/effects/sensors.py::ResonantPressureSensor):
y'' = (p − y − 2ζτ·y')/τ². For a pressure step of height P from rest the reading is the
second-order step response (Doebelin §6.2), underdamped:
    y = P·(1 − e^(−ζω t)·(cos ω_d t + ζ/√(1 − ζ²)·sin ω_d t)),  ω = 1/τ, ω_d = ω√(1 − ζ²),
with its first overshoot exp(−πζ/√(1 − ζ²)) at t = π/ω_d."""
import math

import numpy as np
import pytest

from simhelpers import col, run

TAU, P = 4e-3, 5e6          # 40 Hz transducer; a 50 bar step


def _sensed_step(zeta: float):
    text = f"""
name: ringing
inputs:
  ps: {{unit: Pa}}
components:
  src: {{type: pressure_source, ports: {{P: line, ref: ps}}}}
  gauge: {{type: pressure_sensor_2nd, ports: {{P: line}}, tau: {TAU}, zeta: {zeta}}}
"""
    m, tr, _ = run(text, 0.2, n=2001, inputs={"ps": P}, x0={"gauge.y": 0.0})
    return tr.t, col(m, tr, "gauge.y")


@pytest.mark.parametrize("zeta", [0.05, 0.2])
def test_a_step_rings_as_the_closed_form_second_order_response(zeta):
    t, y = _sensed_step(zeta)
    w = 1.0 / TAU
    wd = w * math.sqrt(1 - zeta ** 2)
    ref = P * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta ** 2) * np.sin(wd * t)))
    assert y == pytest.approx(ref, abs=2e-4 * P)
    over = (y.max() - P) / P
    assert over == pytest.approx(math.exp(-math.pi * zeta / math.sqrt(1 - zeta ** 2)), rel=0.02)
    assert t[np.argmax(y)] == pytest.approx(math.pi / wd, abs=2 * (t[1] - t[0]))


def test_the_resonant_sensor_is_a_drop_in_for_the_first_order_one():
    """Same port and time constant as ``pressure_sensor`` (the diagnosis swaps the type in
    place), one parameter more: the damping ratio."""
    from hydrocli.components import registry
    first, second = registry.get("pressure_sensor"), registry.get("pressure_sensor_2nd")
    assert [p.name for p in first.ports] == [p.name for p in second.ports]
    assert {p.name for p in first.parameters} < {p.name for p in second.parameters}
