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


def test_speed_sensor_filters_the_speed_alone_through_a_second_order_lag():
    """A speed sensor behind 1/(τ²s² + 2ζτs + 1): with ζ = 1 (two equal first-order lags) a
    ramp a·t read from rest gives a·(t − 2τ + (t + 2τ)·e^(−t/τ)); with a Butterworth ζ = 0.71
    the reading is scipy's lsim of the same transfer function (an independent integrator). The
    position is not read through it."""
    from scipy import signal
    for zeta in (1.0, 0.71):
        text = f"""
name: pushed
components:
  m: {{type: mass, ports: {{m: rod}}, m: {J}}}
  push: {{type: force_source, ports: {{a: rod}}, F0: {T}}}
  tacho: {{type: speed_sensor, ports: {{a: rod}}, tau: {TAU}, zeta: {zeta}}}
"""
        m, tr, _ = run(text, 0.5, n=501)
        t, a = tr.t, T / J
        vm = col(m, tr, "tacho.vm")
        if zeta == 1.0:
            assert vm == pytest.approx(a * (t - 2 * TAU + (t + 2 * TAU) * np.exp(-t / TAU)), abs=1e-6)
        _, ref, _ = signal.lsim(([1.0], [TAU ** 2, 2 * zeta * TAU, 1.0]), a * t, t)
        assert vm == pytest.approx(ref, abs=1e-4 * a * t[-1])
        assert vm[-1] == pytest.approx(a * (t[-1] - 2 * zeta * TAU), rel=1e-3)     # lags a ramp by 2ζτ
        assert [s for s in m.state_names if s.startswith("tacho.")] == ["tacho.vm", "tacho.am"]


def test_rotary_speed_sensor_reads_the_shafts_speed():
    text = f"""
name: turned
components:
  J: {{type: inertia, ports: {{r: arm}}, J: {J}}}
  drive: {{type: torque_source, ports: {{a: arm}}, tau0: {T}}}
  tacho: {{type: rotary_speed_sensor, ports: {{a: arm}}, tau: {TAU}, zeta: 1.0}}
"""
    m, tr, _ = run(text, 0.5, n=501)
    t, a = tr.t, T / J
    assert col(m, tr, "tacho.vm") == pytest.approx(a * (t - 2 * TAU + (t + 2 * TAU) * np.exp(-t / TAU)), abs=1e-6)
