"""Signal-path effects: a transport delay as a second-order Padé block, a delay behind a
filter (first order plus dead time), valve play (backlash) as a smooth play operator, and a
smooth Dahl hysteresis loop.

Padé (2,2): e^{−sT} ≈ (1 − sT/2 + (sT)²/12)/(1 + sT/2 + (sT)²/12) (Franklin, Powell &
Emami-Naeini, *Feedback Control*, §5.6.3), realised in controllable canonical form.
Play operator (Krasnosel'skii–Pokrovskii; Tao & Kokotović, *Adaptive Control of Systems with
Actuator and Sensor Nonlinearities*, ch. 2): the output stays while |u − y| ≤ b and
follows u at rate (|u − y| − b)/τ outside the band; smoothed so the stiff solver sees a
smooth right-hand side.
"""
from __future__ import annotations

from ..base import SIGNAL_IN, SIGNAL_OUT, Component, Param, StateSpec
from ..dynamics import dahl_rate, first_order, play_rate
from ..registry import register

_IN, _OUT = SIGNAL_IN, SIGNAL_OUT


@register
class PadeDelay(Component):
    """Transport delay e^{−sT} as a second-order Padé approximant (good to ω·T ≈ 2)."""

    type = "pade_delay"
    family = "effects"
    description = "Transport/input delay T, second-order Padé approximation"
    source = "Franklin, Powell & Emami-Naeini §5.6.3 (Padé approximant)"
    ports = (_IN, _OUT)
    parameters = (Param("T", "s", 2e-3, "delay", positive=True, bounds=(2e-4, 0.1)),)
    states = (StateSpec("z1", "1", "Padé state 1", nominal=1e-3), StateSpec("z2", "1", "Padé state 2", nominal=1.0))

    def equations(self, c):
        c.drive("out", _pade(c, c.signal("in"), c.p.T))


def _pade(c, u, T):
    """The Padé (2,2) block on signal ``u`` with delay ``T`` (states z1, z2); returns its output.
    H(s) = (s² − a1 s + a0)/(s² + a1 s + a0), a1 = 6/T, a0 = 12/T²
    = 1 − 2 a1 s/(s² + a1 s + a0): y = u − 2 a1 z2, z1' = z2, z2' = u − a0 z1 − a1 z2."""
    a1 = 6.0 / T
    a0 = 12.0 / (T * T)
    z1, z2 = c.state("z1"), c.state("z2")
    c.der("z1", z2)
    c.der("z2", u - a0 * z1 - a1 * z2)
    return u - 2.0 * a1 * z2


@register
class LaggedDelay(Component):
    """A delay behind a filter, first order plus dead time: e^{−sT}/(1 + τs), the dead time a
    second-order Padé block as in :class:`PadeDelay`. The command path of a valve amplifier
    with its input filter, a fieldbus that averages, a chain of small lags: Skogestad's half
    rule approximates any cascade of lags by exactly this form (S. Skogestad, "Simple analytic
    rules for model reduction and PID controller tuning", J. Process Control 13 (2003) 291,
    §3.1). Parametrised by the equivalent delay D = T + τ (the low-frequency group delay: what
    a pure delay fitted to the same data would come out as) and the lag's share s = τ/D; its
    bounds are the law's limits, s → 0 a pure delay, s → 1 a first-order lag."""

    type = "lagged_delay"
    family = "effects"
    description = "Delay behind a first-order filter: equivalent delay D = T + tau, lag share s = tau/D"
    source = "first order plus dead time; Skogestad 2003 §3.1 (half rule); Padé as pade_delay"
    ports = (_IN, _OUT)
    parameters = (Param("D", "s", 2e-3, "equivalent delay T + tau", positive=True, bounds=(2e-4, 0.1)),
                  Param("s", "1", 0.5, "the lag's share tau/D of the equivalent delay", bounds=(0.05, 0.95)))
    states = (StateSpec("z1", "1", "Padé state 1", nominal=1e-3), StateSpec("z2", "1", "Padé state 2", nominal=1.0),
              StateSpec("y", "1", "filtered output", nominal=1.0))

    def equations(self, c):
        D, share = c.p.D, c.p.s
        delayed = _pade(c, c.signal("in"), (1.0 - share) * D)
        y = c.state("y")
        c.der("y", first_order(y, delayed, share * D))
        c.drive("out", y)


@register
class Play(Component):
    """Smooth play (backlash) of half-width b: y' = [s⁺(u − y − b) − s⁺(y − u − b)]/τ,
    s⁺ the smooth positive part; b = 0 is a first-order lag τ (keep τ ≪ the dynamics)."""

    type = "play"
    family = "effects"
    description = "Backlash/play of half-width b (valve hysteresis, linkage play)"
    source = "play operator, Tao & Kokotović ch. 2"
    ports = (_IN, _OUT)
    parameters = (Param("b", "1", 0.0, "half-width of the play band (input units)", min=0.0, bounds=(0.0, 0.1)),
                  Param("tau", "s", 2e-4, "tracking lag outside the band", positive=True),
                  Param("eps", "1", 1e-4, "smoothing of the band edges", positive=True))
    states = (StateSpec("y", "1", "output", nominal=1e-2),)

    def equations(self, c):
        u, y, p = c.signal("in"), c.state("y"), c.p
        c.der("y", play_rate(u, y, p.b, p.eps, p.tau))
        c.drive("out", y)


@register
class DahlHysteresis(Component):
    """Smooth rate-independent hysteresis (Dahl's loop) of half-width h on a signal:
    y = u − z,  z' = σ·r·(1 − (z/h)·tanh(r/ε)),  r = (u − w)/τ_r,  w' = r
    (Dahl, *A solid friction model*, Aerospace Corp. TOR-158, 1968, eq. 5 with exponent 1; the
    magnetic hysteresis of a torque motor). After a reversal z swings from ∓h to ±h over an
    input travel of a few h/σ, so the output trails the input by h in the direction of motion:
    the offset a play of half-width h also leaves once its band is crossed, but reached
    within h/σ (σ ≫ 1: an abrupt switch) instead of 2h (a play holds still across its band).
    ``r`` is the input's rate through a first-order filter τ_r; only its sign (smoothed over ε)
    and its integral enter, so the loop does not depend on how fast it is run."""

    type = "dahl_hysteresis"
    family = "effects"
    description = "Dahl hysteresis loop of half-width h on a signal (magnetic hysteresis of a torque motor)"
    source = "Dahl 1968 (TOR-158) eq. 5, exponent 1"
    ports = (_IN, _OUT)
    parameters = (Param("h", "1", 1e-4, "half-width of the loop (input units)", positive=True, bounds=(1e-6, 0.1)),
                  Param("sigma", "1", 1.0, "shape of the loop: dz/du = 2σ just after a reversal (σ ≫ 1 switches abruptly)",
                        positive=True, bounds=(0.05, 100.0)),
                  Param("tau_r", "s", 2e-3, "filter of the input rate (direction sensing)", positive=True),
                  Param("eps", "1/s", 1e-3, "input rate below which the direction is smoothed", positive=True))
    states = (StateSpec("w", "1", "filtered input", nominal=1e-2), StateSpec("z", "1", "hysteretic offset", nominal=1e-3))

    def equations(self, c):
        u, w, z, p = c.signal("in"), c.state("w"), c.state("z"), c.p
        r = (u - w) / p.tau_r
        c.der("w", r)
        c.der("z", dahl_rate(z, r, p.h, p.sigma, p.eps))
        c.drive("out", u - z)
