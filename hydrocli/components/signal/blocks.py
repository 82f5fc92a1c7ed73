"""Signal blocks: constant, gain, sum, saturation, rate limiter, first/second-order lags."""
from __future__ import annotations

from ...model import expr as E
from ..base import SIGNAL_IN, SIGNAL_OUT, Component, Param, Port, S, StateSpec
from ..dynamics import first_order, rate_limited, second_order
from ..registry import register

_IN, _OUT = SIGNAL_IN, SIGNAL_OUT


@register
class Constant(Component):
    type = "constant"
    family = "signal"
    description = "Constant signal"
    source = "-"
    ports = (_OUT,)
    parameters = (Param("value", "1", 0.0, "output value (SI)"),)

    def equations(self, c):
        c.drive("out", c.p.value)


@register
class Gain(Component):
    """y = k·u + offset."""

    type = "gain"
    family = "signal"
    description = "Static gain with offset (e.g. a sensor or command scaling)"
    source = "-"
    ports = (_IN, _OUT)
    parameters = (Param("k", "1", 1.0, "gain"), Param("offset", "1", 0.0, "offset added to the output"))

    def equations(self, c):
        c.drive("out", c.p.k * c.signal("in") + c.p.offset)


@register
class Sum(Component):
    """y = k_a·a + k_b·b (use k_b = −1 for a difference)."""

    type = "sum"
    family = "signal"
    description = "Weighted sum of two signals"
    source = "-"
    ports = (Port("a", S, "first input", direction="in"), Port("b", S, "second input", direction="in"), _OUT)
    parameters = (Param("k_a", "1", 1.0, "weight of a"), Param("k_b", "1", 1.0, "weight of b"))

    def equations(self, c):
        c.drive("out", c.p.k_a * c.signal("a") + c.p.k_b * c.signal("b"))


@register
class Saturation(Component):
    """y = min(max(u, lo), hi)."""

    type = "saturation"
    family = "signal"
    description = "Saturation between lo and hi"
    source = "-"
    ports = (_IN, _OUT)
    parameters = (Param("lo", "1", -1.0, "lower limit"), Param("hi", "1", 1.0, "upper limit"))

    def check(self, values):
        return ["lo must be below hi"] if values["lo"] >= values["hi"] else []

    def equations(self, c):
        c.drive("out", E.clamp(c.signal("in"), c.p.lo, c.p.hi))


@register
class RateLimiter(Component):
    """Smooth rate limiter (seed 004 eq. 1): y' = s·tanh((u − y)/(τ·s)) with s = s_max rising
    and s = s_min falling (s_min = 0: symmetric, s_max both ways)."""

    type = "rate_limiter"
    family = "signal"
    description = "Rate limiter with a short tracking lag"
    source = "seed 004 eq. 1"
    ports = (_IN, _OUT)
    parameters = (Param("s_max", "1/s", 20.0, "maximum rising rate", positive=True),
                  Param("s_min", "1/s", 0.0, "maximum falling rate (magnitude); 0 = s_max", min=0.0),
                  Param("tau", "s", 1e-4, "tracking lag below the rate limit", positive=True))
    states = (StateSpec("y", "1", "output", nominal=0.01),)

    def equations(self, c):
        y = c.state("y")
        c.der("y", rate_limited(c.signal("in"), y, c.p.s_max, c.p.tau, c.p.s_min if c.active("s_min") else None))
        c.drive("out", y)


@register
class FirstOrderLag(Component):
    """y' = (k·u − y)/τ: sensor lag, filters."""

    type = "first_order_lag"
    family = "signal"
    description = "First-order lag k/(1 + τs), e.g. a pressure sensor's lag"
    source = "-"
    ports = (_IN, _OUT)
    parameters = (Param("tau", "s", 1e-3, "time constant", positive=True, bounds=(1e-5, 1.0)),
                  Param("k", "1", 1.0, "static gain"))
    states = (StateSpec("y", "1", "output", nominal=1.0),)

    def equations(self, c):
        y = c.state("y")
        c.der("y", first_order(y, c.p.k * c.signal("in"), c.p.tau))
        c.drive("out", y)


@register
class SecondOrder(Component):
    """k·ω²/(s² + 2ζωs + ω²): y'' = ω²(k·u − y) − 2ζω·y'."""

    type = "transfer_function_2"
    family = "signal"
    description = "Second-order transfer function (natural frequency, damping ratio, gain)"
    source = "seed 000 eq. 9 (spool dynamics); seed 004 eq. 2"
    ports = (_IN, _OUT)
    parameters = (Param("omega", "rad/s", 100.0, "natural frequency ω", positive=True),
                  Param("zeta", "1", 0.7, "damping ratio ζ", positive=True),
                  Param("k", "1", 1.0, "static gain"))
    states = (StateSpec("y", "1", "output", nominal=1.0), StateSpec("yd", "1/s", "output rate", nominal=1.0))

    def equations(self, c):
        y, yd = c.state("y"), c.state("yd")
        tau = 1.0 / c.p.omega
        c.der("y", yd)
        c.der("yd", second_order(y, yd, c.p.k * c.signal("in"), tau, c.p.zeta))
        c.drive("out", y)
