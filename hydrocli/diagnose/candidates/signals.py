"""Signal and measurement effects: a transport delay on each machine input (second-order
Padé block), alone or behind a first-order filter, and sensor lags beyond a typical
transducer (pressure sensors re-identified with wide bounds; position/velocity sensors with a
first-order lag; a speed sensor alone behind a second-order filter)."""
from __future__ import annotations

from .. import augment as A
from ..locate import POSITIONS, ROTARY, SPEEDS
from ..measurement import PRESSURE_TAU_BOUNDS, RESONANT_SENSOR_TYPE, sensor_components
from .base import Candidate, Context, Family, NewParam, Skipped


CLEARLY_SLOW = 5e-3  # s: a pressure-sensor lag reported as an effect must be well beyond a typical
                     # transducer (≤ 1–2 ms); smaller lags stay in the measurement model
MIN_DELAY = 2e-3   # s: shorter "delays" are sampling/interpolation artefacts of the recording
                   # (a command held between samples but interpolated linearly looks ~half a sample late)
LAG_SHARES = (0.5, 0.2, 0.8)   # the lag's share τ/D of a filtered delay the fit starts from


class InputDelayFamily(Family):
    """A command that reaches the machine late: a pure transport delay (``pade_delay``), or a
    delay behind a filter (``lagged_delay``, first order plus dead time: an amplifier's input
    filter, a fieldbus that averages, a chain of lags). They are laws of one effect: a pure
    delay passes every frequency at full amplitude, a filter attenuates the fast content it
    delays, and the fits say which law the command path follows (dev lift and counterbalanced
    lift, four lags of 3.7 ms on the command: the filtered law is accepted, and after it the
    held-out P1 error is 6–13 % lower than after the pure delay (the summed ESR 4–8 %); on the
    counterbalanced lift a rod–load link is still accepted after it, so what the link takes
    up there is not the chain's attenuation)."""

    effects = ("input_delay",)
    lags = frozenset({"input_delay"})
    laws = frozenset({"input_delay"})

    def candidates(self, ctx: Context):
        out = []
        for name in ctx.net.inputs:
            users = ctx.on_node(name)
            if not users:
                continue
            out += [_delayed_input(ctx, name, users, filtered) for filtered in (False, True)]
        return out or [Skipped("input_delay", "no machine input drives a component")]


def _delayed_input(ctx: Context, name: str, users: list, filtered: bool) -> Candidate:
    """Input ``name`` reaching its users late: through a Padé delay (its T), or through a delay
    behind a filter (its equivalent delay D; the lag's share s a companion whose bounds are the
    law's limits). The delay is the primary, from near nothing."""
    delay = A.unique_name(ctx.net, f"{name}_delay")
    node = A.unique_name(ctx.net, f"{name}_delayed")
    block, size = ("lagged_delay", "D") if filtered else ("pade_delay", "T")
    params = [NewParam(f"{delay}.{size}", 2.5e-4, (2e-4, 0.1), (MIN_DELAY, 0.1), 5e-3, True)]
    if filtered:
        params.append(NewParam(f"{delay}.s", LAG_SHARES[0], (0.05, 0.95), (0.05, 0.95), LAG_SHARES[0], False,
                               primary=False, shapes=LAG_SHARES[1:], basins=True, limits=True))

    def build(net, users=tuple(users), params=params):
        for comp, port in users:
            net = A.connect(net, comp, port, node)
        net = A.add(net, delay, block, {"in": name, "out": node})
        return A.free_new(net, params)
    text = "delay behind a first-order filter" if filtered else "transport delay"
    return Candidate("input_delay", users[0][0], params, build, "signal", f"{text} on input '{name}'",
                     variant="filtered" if filtered else "")


SLOW_SENSOR_MAX = 1.0   # s: a pressure read through a gauge snubber or a long thin sensing line
                        # (a damping orifice is fitted to calm a gauge) lags by up to about a second;
                        # so may a motion reading on a slow machine: a speed counted from encoder
                        # pulses over a gate time or a tachogenerator behind a heavy filter (dev
                        # winch, a drum speed read through a 0.82 Hz filter, τ = 0.19 s: the filter
                        # closed 95 % of the held-out gap, w 52.7 → 2.9 %, but ended at the old
                        # 0.1 s bound and was refused)


class SensorLagFamily(Family):
    """Pressure-sensor lags are always estimated as nuisance parameters (bounds up to a
    typical transducer's few ms, :mod:`..measurement`); this candidate lets them grow to
    ``SLOW_SENSOR_MAX``, and adds a lag to position/velocity (angle/speed) outputs."""

    effects = ("sensor_lag",)
    lags = frozenset({"sensor_lag"})
    # the slow readings are laws of one effect: a first-order lag of position and speed alike
    # (one transducer), a speed alone behind a second-order filter, slow pressure transducers.
    # A secant at one probe ranks them by how much each resembles the others there (dev lift,
    # a 5 Hz speed filter: the lag of both screened 9.1 %, the filter 6.7 % and was never
    # fitted), so every significant one is fitted once one is shortlisted
    laws = frozenset({"sensor_lag"})

    def candidates(self, ctx: Context):
        out = []
        sensors = sensor_components(ctx.net)
        if sensors:
            params = [NewParam(f"{s}.tau", min(ctx.value(f"{s}.tau"), PRESSURE_TAU_BOUNDS[1]),
                               (PRESSURE_TAU_BOUNDS[0], SLOW_SENSOR_MAX), (CLEARLY_SLOW, SLOW_SENSOR_MAX), 0.01, True)
                      for s in sensors]

            def widen(net, params=params):
                for p in params:
                    net = A.free(net, p.name, ctx.value(p.name), p.bounds, True)
                return net
            out.append(Candidate("sensor_lag", sensors[0], params, widen, "measurement",
                                 "pressure sensors slower than a typical transducer"))
            out.append(_ringing_pressure(ctx, sensors))
        for node, rotary in _sensed(ctx, POSITIONS + SPEEDS):
            sens = A.unique_name(ctx.net, f"{node}_sensor")
            tau = f"{sens}.tau"
            typ, (pos, vel) = ("rotary_motion_sensor", ("theta", "w")) if rotary else ("motion_sensor", ("x", "v"))

            def build(net, node=node, sens=sens, tau=tau, typ=typ, pos=pos, vel=vel):
                net = A.add(net, sens, typ, {"a": node})
                net = A.rewrite_outputs(net, {f"{node}.{pos}": f"{sens}.{pos}", f"{node}.{vel}": f"{sens}.{vel}"})
                return A.free(net, tau, 1e-4, (1e-5, SLOW_SENSOR_MAX), True)
            out.append(Candidate("sensor_lag", node, [NewParam(tau, 1e-4, (1e-5, SLOW_SENSOR_MAX),
                                                               (1e-3, SLOW_SENSOR_MAX), 5e-3, True)],
                                 build, "measurement", f"lag of the {'angle/speed' if rotary else 'position/velocity'} "
                                                       f"sensor on '{node}'"))
        out += [_speed_filter(ctx, node, rotary) for node, rotary in _sensed(ctx, SPEEDS)]
        return out or [Skipped("sensor_lag", "no sensed output")]


RINGING = 0.4          # damping ratio below which a transducer's step response overshoots by > 25 %: a ring
RING_ZETA_STARTS = (0.1, 0.03, 0.3)   # damping ratios the fit starts from (a sensing line rings lightly)


def _ringing_pressure(ctx: Context, sensors: list[str]) -> Candidate:
    """Pressure transducers that RING: each measured pressure read through a second-order
    response 1/(τ²s² + 2ζτs + 1) (library ``pressure_sensor_2nd``, a drop-in for the
    first-order ``pressure_sensor``): a transducer on a sensing line or a drilled port, the
    line's oil mass on the cavity's compliance (Doebelin §6.2). A first-order lag, however
    slow, cannot overshoot, and what rings in the pressure alone is otherwise fitted as a mode
    of the structure (a mount, a rod–load link) that must also move the position.

    What separates it from those modes is WHERE the ringing is: a sensor's resonance is in
    the pressure it reads and in nothing downstream of it, while a structural mode feeds back
    through the load into the motion and every chamber. τ (the resonance's, f_n = 1/(2πτ)) is
    the primary, plausible from f_n = 160 Hz (τ 1 ms: a typical transducer resonates in the
    kilohertz); ζ a companion started at light damping. A fit that neither rings (ζ ≥ RINGING)
    nor lags as much as a clearly slow transducer (equivalent lag 2ζτ < CLEARLY_SLOW) is only
    the nuisance lag again, and is refused (:attr:`Candidate.checks`)."""
    params = []
    for s in sensors:
        tau0 = max(min(ctx.value(f"{s}.tau"), PRESSURE_TAU_BOUNDS[1]) / 2.0, PRESSURE_TAU_BOUNDS[0])
        params.append(NewParam(f"{s}.tau", tau0, (PRESSURE_TAU_BOUNDS[0], SLOW_SENSOR_MAX),
                               (1e-3, SLOW_SENSOR_MAX), 4e-3, True))
        params.append(NewParam(f"{s}.zeta", RING_ZETA_STARTS[0], (0.01, 3.0), (0.01, 3.0), RING_ZETA_STARTS[0], True,
                               primary=False, ref=0.71, shapes=RING_ZETA_STARTS[1:], basins=True))

    def build(net, params=params):
        for s in sensors:
            net = A.set_type(net, s, RESONANT_SENSOR_TYPE)
        return A.free_new(net, params)

    def rings(est: dict[str, float], names=tuple(sensors)) -> str | None:
        found = [(est.get(f"{s}.tau"), est.get(f"{s}.zeta")) for s in names]
        if any(t is not None and z is not None and (z < RINGING or 2.0 * z * t >= CLEARLY_SLOW) for t, z in found):
            return None
        return (f"no transducer rings (ζ ≥ {RINGING}) or lags beyond a typical one "
                f"(2ζτ < {CLEARLY_SLOW * 1e3:g} ms): the nuisance lag, not a finding")
    return Candidate("sensor_lag", sensors[0], params, build, "measurement",
                     "pressure transducers with a resonance (a sensing line ringing): second-order response",
                     variant="resonant", checks=(rings,))


def _speed_filter(ctx: Context, node: str, rotary: bool) -> Candidate:
    """The speed read through its own second-order filter, the position read directly (a
    tachogenerator or a differentiated position behind a low-pass: ``speed_sensor``): a lag
    of both from one time constant delays a position the encoder reads at once. Measured on
    seed 67's velocity filters (f_c 5–15.6 Hz, ζ 0.7): the first-order lag of both
    left the position's held-out ESR 3–16× worse than before it (EHA 0.015 → 0.044 %, lift
    0.010 → 0.161 %, rotary 0.017 → 0.166 %); on the EHA case the speed filter fits
    τ = 9.8 ms, ζ = 0.68 (truth 10.2 ms, 0.70) and brings v to its noise (0.064 % against
    0.063 %; the first-order lag of both: 0.093 %)."""
    sens = A.unique_name(ctx.net, f"{node}_speed_sensor")
    tau, zeta = f"{sens}.tau", f"{sens}.zeta"
    typ, vel = ("rotary_speed_sensor", "w") if rotary else ("speed_sensor", "v")
    params = [NewParam(tau, 1e-4, (1e-5, SLOW_SENSOR_MAX), (1e-3, SLOW_SENSOR_MAX), 5e-3, True),
              NewParam(zeta, 0.71, (0.3, 3.0), (0.3, 3.0), 0.71, True, primary=False, ref=0.71)]

    def build(net):
        net = A.add(net, sens, typ, {"a": node})
        net = A.rewrite_outputs(net, {f"{node}.{vel}": f"{sens}.{vel}"})
        return A.free_new(net, params)
    return Candidate("sensor_lag", node, params, build, "measurement",
                     f"{'angular ' if rotary else ''}speed sensor on '{node}' behind a second-order filter",
                     variant="speed_filter")


def _sensed(ctx: Context, quantities: tuple[str, ...]) -> list[tuple[str, bool]]:
    """The nodes whose motion an output of these quantities reads, each with whether it is
    rotary, in name order."""
    return sorted({(n, q in ROTARY) for o, q in ctx.outputs.items() if q in quantities for n in _nodes_of(ctx, o)})


def _nodes_of(ctx: Context, output: str) -> set[str]:
    nodes = ctx.net.nodes()
    return {s.rsplit(".", 1)[0] for s in A.output_symbols(ctx.net, output) if s.rsplit(".", 1)[0] in nodes}
