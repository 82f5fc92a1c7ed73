"""Sensors with a lag: the measured value follows the physical one through 1/(1 + τs). A
pressure transducer's membrane and amplifier, or a position/velocity encoder's filter, behave
so (ISO 16028-style dynamic pressure calibration; Jelali & Kroll, *Hydraulic Servo-systems*,
§6.5, sensor dynamics). A speed read by a tachogenerator or differentiated from a position
goes through its own filter, commonly second order 1/(τ²s² + 2ζτs + 1) (a Butterworth
ζ = 0.71), while the position is read directly. Outputs then read ``<sensor>.<variable>``."""
from __future__ import annotations

from ..base import Component, H, Param, Port, R, StateSpec, T, VariableSpec
from ..dynamics import first_order, second_order
from ..registry import register

# up to a second: a gauge behind a snubber, a speed counted over a gate time on a slow machine
_TAU = Param("tau", "s", 1e-3, "sensor time constant", positive=True, bounds=(1e-5, 1.0))
_ZETA = Param("zeta", "1", 0.71, "speed filter damping ratio (0.71 Butterworth, 1 two equal first-order lags)",
              positive=True, bounds=(0.3, 3.0))


@register
class PressureSensor(Component):
    """Pressure transducer with lag: τ·dy/dt = p − y (draws no flow)."""

    type = "pressure_sensor"
    family = "effects"
    description = "Pressure transducer with a first-order lag (measured value y)"
    source = "first-order sensor model, Jelali & Kroll §6.5"
    ports = (Port("P", H, "sensed node"),)
    parameters = (_TAU,)
    states = (StateSpec("y", "Pa", "measured pressure", nominal=1e5),)
    variables = (VariableSpec("p", "Pa", "measured pressure (alias of the state)"),)

    def equations(self, c):
        y = c.state("y")
        c.der("y", first_order(y, c.across("P"), c.p.tau))
        c.at_rest("y", c.across("P"))
        c.let("p", y)


_RING_ZETA = Param("zeta", "1", 0.71, "damping ratio of the transducer's resonance (a sensing line and the "
                   "transducer's cavity ring lightly: 0.02–0.2; 0.71 a flat response)", positive=True,
                   bounds=(0.01, 3.0))


@register
class ResonantPressureSensor(Component):
    """Pressure transducer with a resonance: y'' = (p − y − 2ζτ·y')/τ², i.e.
    1/(τ²s² + 2ζτs + 1), natural frequency f_n = 1/(2πτ). A transducer on a sensing line or
    a drilled port is a Helmholtz resonator (the line's oil mass on the cavity's compliance)
    ringing at tens to hundreds of hertz, lightly damped (Doebelin, *Measurement Systems*
    §6.2 (second-order instruments); Jelali & Kroll §6.5). Same ports and time constant as
    ``pressure_sensor`` (a drop-in replacement), with the damping ratio added."""

    type = "pressure_sensor_2nd"
    family = "effects"
    description = "Pressure transducer with a second-order (resonant) response (measured value y)"
    source = "second-order instrument, Doebelin §6.2; Jelali & Kroll §6.5"
    ports = (Port("P", H, "sensed node"),)
    parameters = (_TAU, _RING_ZETA)
    states = (StateSpec("y", "Pa", "measured pressure", nominal=1e5),
              StateSpec("yd", "Pa/s", "rate of the measured pressure", nominal=1e7))
    variables = (VariableSpec("p", "Pa", "measured pressure (alias of the state)"),)

    def equations(self, c):
        _second_order_reading(c, c.across("P"), ("y", "yd"), "p")


@register
class MotionSensor(Component):
    """Position and velocity sensor with lag on a translational node: measured x_m, v_m
    follow the node's position and velocity through 1/(1 + τs)."""

    type = "motion_sensor"
    family = "effects"
    description = "Position/velocity sensor with a first-order lag (measured x, v)"
    source = "first-order sensor model, Jelali & Kroll §6.5"
    ports = (Port("a", T, "sensed node"),)
    parameters = (_TAU,)
    states = (StateSpec("xm", "m", "measured position", nominal=1e-3),
              StateSpec("vm", "m/s", "measured velocity", nominal=1e-2))
    variables = (VariableSpec("x", "m", "measured position"), VariableSpec("v", "m/s", "measured velocity"))

    def equations(self, c):
        _lagged_motion(c, ("xm", "x"), ("vm", "v"))


@register
class RotaryMotionSensor(Component):
    """Angle and angular-velocity sensor with lag on a rotational node (an encoder or
    tachometer with its filter): measured θ_m, ω_m follow the node's angle and speed through
    1/(1 + τs)."""

    type = "rotary_motion_sensor"
    family = "effects"
    description = "Angle/angular-velocity sensor with a first-order lag (measured theta, w)"
    source = "first-order sensor model, Jelali & Kroll §6.5"
    ports = (Port("a", R, "sensed node"),)
    parameters = (_TAU,)
    states = (StateSpec("thm", "rad", "measured angle", nominal=1e-3),
              StateSpec("wm", "rad/s", "measured angular velocity", nominal=1e-2))
    variables = (VariableSpec("theta", "rad", "measured angle"), VariableSpec("w", "rad/s", "measured angular velocity"))

    def equations(self, c):
        _lagged_motion(c, ("thm", "theta"), ("wm", "w"))


def _lagged_motion(c, position: tuple[str, str], speed: tuple[str, str]) -> None:
    """τ·dy/dt = u − y for the node's position and its speed; (state, variable) names."""
    for (state, var), value in ((position, c.position("a")), (speed, c.across("a"))):
        y = c.state(state)
        c.der(state, first_order(y, value, c.p.tau))
        c.at_rest(state, value)
        c.let(var, y)


@register
class SpeedSensor(Component):
    """Velocity sensor with a second-order filter on a translational node (a tachogenerator,
    or a differentiated position, behind a low-pass): v_m follows v through
    1/(τ²s² + 2ζτs + 1), the position is not read here."""

    type = "speed_sensor"
    family = "effects"
    description = "Velocity sensor behind a second-order low-pass (measured v)"
    source = "second-order sensor filter, Jelali & Kroll §6.5"
    ports = (Port("a", T, "sensed node"),)
    parameters = (_TAU, _ZETA)
    states = (StateSpec("vm", "m/s", "measured velocity", nominal=1e-2),
              StateSpec("am", "m/s^2", "rate of the measured velocity", nominal=1.0))
    variables = (VariableSpec("v", "m/s", "measured velocity"),)

    def equations(self, c):
        _filtered_speed(c, "v")


@register
class RotarySpeedSensor(Component):
    """Angular-velocity sensor with a second-order filter on a rotational node: ω_m follows ω
    through 1/(τ²s² + 2ζτs + 1), the angle is not read here."""

    type = "rotary_speed_sensor"
    family = "effects"
    description = "Angular-velocity sensor behind a second-order low-pass (measured w)"
    source = "second-order sensor filter, Jelali & Kroll §6.5"
    ports = (Port("a", R, "sensed node"),)
    parameters = (_TAU, _ZETA)
    states = (StateSpec("vm", "rad/s", "measured angular velocity", nominal=1e-2),
              StateSpec("am", "rad/s^2", "rate of the measured angular velocity", nominal=1.0))
    variables = (VariableSpec("w", "rad/s", "measured angular velocity"),)

    def equations(self, c):
        _filtered_speed(c, "w")


def _filtered_speed(c, var: str) -> None:
    """v_m'' = (v − v_m − 2ζτ·v_m')/τ² (:func:`second_order`) for the node's speed."""
    _second_order_reading(c, c.across("a"), ("vm", "am"), var)


def _second_order_reading(c, value, states: tuple[str, str], var: str) -> None:
    """y'' = (u − y − 2ζτ·y')/τ² for the sensed ``value`` u: the reading's state and its rate
    (``states``), the reading named ``var``, at rest equal to what it senses."""
    y, yd = (c.state(s) for s in states)
    c.der(states[0], yd)
    c.der(states[1], second_order(y, yd, value, c.p.tau, c.p.zeta))
    c.at_rest(states[0], value)
    c.let(var, y)
