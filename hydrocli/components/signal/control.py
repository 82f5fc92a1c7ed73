"""Control blocks: joint PID (seed 002 Fig. 7) and the static inverse valve map used as
feed-forward (seed 002 §5, eqs. 10a–10b)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, Param, Port, S, StateSpec
from ..dynamics import first_order
from ..registry import register


@register
class PID(Component):
    """u = K_p·e + K_i·∫e dt + K_d·ė_f, e = ref − meas, with the derivative filtered by
    1/(1 + T_f s) and the output clamped to [u_min, u_max]; the integrator stops while the
    output is saturated in the direction of the error (conditional integration)."""

    type = "pid"
    family = "signal"
    description = "PID controller with filtered derivative, output limits and anti-windup"
    source = "seed 002 Fig. 7 (joint-level PID); seed 003 Fig. 10"
    ports = (Port("ref", S, "reference", direction="in"), Port("meas", S, "measurement", direction="in"),
             Port("out", S, "controller output", direction="out"))
    parameters = (
        Param("Kp", "1", 1.0, "proportional gain", bounds=(0.0, 1e4)),
        Param("Ki", "1/s", 0.0, "integral gain", bounds=(0.0, 1e4)),
        Param("Kd", "s", 0.0, "derivative gain", bounds=(0.0, 1e3)),
        Param("Tf", "s", 0.01, "derivative filter time constant", positive=True),
        Param("u_min", "1", -1e9, "lower output limit"),
        Param("u_max", "1", 1e9, "upper output limit"),
    )
    states = (StateSpec("i", "s", "integral of the error", nominal=1e-3),
              StateSpec("ef", "1", "filtered error (derivative filter state)", nominal=1e-3))

    def check(self, values):
        return ["u_min must be below u_max"] if values["u_min"] >= values["u_max"] else []

    def equations(self, c):
        p = c.p
        e = c.let("e", c.signal("ref") - c.signal("meas"))
        ef = c.state("ef")
        c.der("ef", first_order(ef, e, p.Tf))
        d = (e - ef) / p.Tf                                   # filtered derivative of e
        u_raw = c.let("u_raw", p.Kp * e + p.Ki * c.state("i") + p.Kd * d)
        u = c.let("u", E.clamp(u_raw, p.u_min, p.u_max))
        windup = E.where(u_raw * e > 0.0, E.where(u_raw > p.u_max, 0.0, E.where(u_raw < p.u_min, 0.0, 1.0)), 1.0)
        c.der("i", windup * e)
        c.drive("out", u)


@register
class InverseValveMap(Component):
    """Valve command for a desired flow (seed 002 §5): the orifice needs
    C_R^(−1/2) = Q/sqrt(ΔP) (eqs. 10a–10b), and the static valve characteristic (Fig. 5)
    C_R^(−1/2)(V) = k_max·(|V| − V_db)/(V_max − V_db) beyond the deadband V_db (assumed
    linear; the paper fitted a third-order polynomial it does not print) is inverted:

        V = V_db·tanh(Q/q_eps) + (V_max − V_db)·Q/(k_max·sqrt(ΔP)),  clamped to ±V_max.

    The tanh makes the jump across the deadband smooth at Q = 0. ΔP comes from the ``dp``
    port (e.g. P_pump − P_in from pressure transducers) or the constant ``dp_nom``."""

    type = "inverse_valve_map"
    family = "signal"
    description = "Static inverse valve characteristic C_R^(-1/2)(V) with deadband (feed-forward)"
    source = "seed 002 §5, eqs. 10a–10b, Fig. 5"
    ports = (Port("q", S, "desired flow [m^3/s]", direction="in"),
             Port("dp", S, "pressure drop across the metering orifice [Pa]", optional=True, direction="in"),
             Port("out", S, "valve command [V]", direction="out"))
    parameters = (
        Param("k_max", "m^3/s/Pa^0.5", 1e-6, "C_R^(−1/2) at V_max (fully open)", positive=True),
        Param("V_db", "V", 1.2, "deadband (seed 002 §3a: 0–1.2 V)", min=0.0),
        Param("V_max", "V", 10.0, "command at full opening", positive=True),
        Param("dp_nom", "Pa", 70e5, "pressure drop used when the dp port is not connected", positive=True),
        Param("dp_min", "Pa", 1e5, "lower bound on ΔP inside the square root", positive=True),
        Param("q_eps", "m^3/s", 1e-6, "flow over which the deadband jump is smoothed", positive=True),
    )

    def check(self, values):
        return ["V_db must be below V_max"] if values["V_db"] >= values["V_max"] else []

    def equations(self, c):
        p = c.p
        q = c.signal("q")
        dp = E.fmax(c.signal("dp") if c.connected("dp") else p.dp_nom, p.dp_min)
        k_req = c.let("k_req", q / E.sqrt(dp))
        v = p.V_db * E.tanh(q / p.q_eps) + (p.V_max - p.V_db) * k_req / p.k_max
        c.drive("out", c.let("V", E.clamp(v, -1.0 * p.V_max, p.V_max), "V"))
