"""Motion sensors with a first-order lag (components/effects/sensors.py): an inertia J driven
by a constant torque T turns with ω = a·t, θ = a·t²/2 (a = T/J); through 1/(1 + τs) from rest
the sensor reads ω_m = a·(t − τ(1 − e^(−t/τ))) and θ_m = a·(t²/2 − τt + τ²(1 − e^(−t/τ)))
(the lag's response to a ramp and to a parabola, by convolution with e^(−t/τ)/τ)."""
import numpy as np
import pytest

from simhelpers import col, run

J, T, TAU = 0.5, 2.0, 0.05


def test_rotary_sensor_lags_angle_and_speed_by_its_time_constant():
    text = f"""
name: turned
components:
  J: {{type: inertia, ports: {{r: arm}}, J: {J}}}
  drive: {{type: torque_source, ports: {{a: arm}}, tau0: {T}}}
  enc: {{type: rotary_motion_sensor, ports: {{a: arm}}, tau: {TAU}}}
"""
    m, tr, _ = run(text, 0.5, n=501)
    t, a = tr.t, T / J
    decay = 1.0 - np.exp(-t / TAU)
    assert col(m, tr, "arm.w") == pytest.approx(a * t, abs=1e-9)
    assert col(m, tr, "enc.wm") == pytest.approx(a * (t - TAU * decay), abs=1e-6)
    assert col(m, tr, "enc.thm") == pytest.approx(a * (t ** 2 / 2 - TAU * t + TAU ** 2 * decay), abs=1e-6)


def test_linear_sensor_lags_position_and_velocity_alike():
    """The same closed forms for a mass m pushed by a constant force F (a = F/m)."""
    text = f"""
name: pushed
components:
  m: {{type: mass, ports: {{m: rod}}, m: {J}}}
  push: {{type: force_source, ports: {{a: rod}}, F0: {T}}}
  lvdt: {{type: motion_sensor, ports: {{a: rod}}, tau: {TAU}}}
"""
    m, tr, _ = run(text, 0.5, n=501)
    t, a = tr.t, T / J
    decay = 1.0 - np.exp(-t / TAU)
    assert col(m, tr, "lvdt.vm") == pytest.approx(a * (t - TAU * decay), abs=1e-6)
    assert col(m, tr, "lvdt.xm") == pytest.approx(a * (t ** 2 / 2 - TAU * t + TAU ** 2 * decay), abs=1e-6)
