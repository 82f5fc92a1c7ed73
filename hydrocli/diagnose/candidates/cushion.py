"""End-position cushioning (an ``end_stop`` form): over the last millimetres of stroke a
spear closes the chamber's outlet and the oil leaves through a needle orifice, so the piston
is braked hydraulically before it reaches the metal stop (Festo DSNU/DNC data sheets;
Murrenhoff, *Grundlagen der Fluidtechnik I* §8; library ``end_cushion``; a vane's swing alike,
``end_cushion_rotary``, angles in rad).

What tells a cushion from a stiff or soft stop is WHERE the force comes from: a stop pushes
on the rod (force balance) at the end itself, a cushion throttles the outflow of the chamber
being emptied (continuity) over a length before it — the emptied chamber's pressure rises
while the piston decelerates, and a reversal leaves the end freely (the check valve)."""
from __future__ import annotations

from ...components import roles as R
from ...components.base import Domain
from .. import augment as A
from ..measurement import SENSOR_TYPES
from .base import Candidate, Context, Family, NewParam, Part, Skipped
from .circuit import valve_kv
from .leakage import stop_damping, stop_stiffness

SPAN_MIN = 1e-3       # m (rad): the travel below which no end is judged
ENTRY = 0.005         # share of the travel seen over which the spear closes the outlet
LINE_VOLUME = 1e-3    # share of the chamber's dead volume between the cushion and the line: a port fitting small
                      # enough to leave the chamber's compliance as it was (0.1 %) while the cushion is off
OPEN = 100.0          # × the valve's flow coefficient: the open outlet and the check valve, no drop worth naming


class CushionFamily(Family):
    effects = ("end_stop",)
    switching = frozenset({"end_stop"})
    # a stop and a cushion at either end are laws of one effect (where the force comes from):
    # once the effect is shortlisted every significant one is fitted, and one that fails leaves
    # the others to the next wave (shortlist.after_wave; the Festo rig without its stops: a
    # cushion at the wrong end screened above the stops, failed, and hid them)
    laws = frozenset({"end_stop"})

    def candidates(self, ctx: Context):
        out = []
        for act in ctx.parts(R.ACTUATOR):
            if act.param("stop_min") is None:
                continue                       # a motor turns on: no end to cushion
            for end in ("max", "min"):
                c = _cushion(ctx, act, end)
                if c is not None:
                    out.append(c)
        return out or [Skipped("end_stop", "no actuator with a stroke and a cushion type on its motion")]


def _cushion(ctx: Context, act: Part, end: str) -> Candidate | Skipped | None:
    """A cushion at one END of the travel seen: on the chamber that end empties (``chamber_b``
    at the upper end, ``chamber_a`` at the lower), between that chamber and everything that
    fed it (valve, hoses, load-holding valve): a new line-side node with the port fitting's
    volume. The chamber keeps its sensors and state. Its position is judged as a stop's
    (started beyond the travel, off; plausible within half the travel of the recorded end),
    the needle and the cushion's length are companions."""
    found = ctx.on_travel(act, R.END_CUSHION)
    if found is None:
        return None
    node, ref, (lo, hi), typ, role = found
    vtyp, vrole = ctx.element(R.VOLUME, Domain.HYDRAULIC)
    slot = "chamber_b" if end == "max" else "chamber_a"
    chamber = act.node(slot)
    if ctx.parts_on(chamber, R.END_CUSHION):
        return Skipped("end_stop", f"'{chamber}' is cushioned in the machine already")
    vols = act.params("dead_volumes")
    try:
        v_dead = ctx.value(vols[1 if end == "max" else 0]) if len(vols) == 2 else 1e-5
    except (KeyError, TypeError, ValueError):
        v_dead = 1e-5
    span = max(hi - lo, SPAN_MIN)
    sign = 1.0 if end == "max" else -1.0
    edge = hi if end == "max" else lo
    kv = valve_kv(ctx, ctx.parts(R.METERING_VALVE)[0].name) if ctx.parts(R.METERING_VALVE) else 5e-7
    name = A.unique_name(ctx.net, f"{act.name}_cushion_{end}")
    line = A.unique_name(ctx.net, f"{chamber}_line")
    fit = A.unique_name(ctx.net, f"{chamber}_port")
    x_end, length, needle = (f"{name}.{role.param(s)}" for s in ("end", "length", "needle"))
    off = edge + sign * 0.2 * span
    out_lo, out_hi = ctx.recorded_range.get(node, (lo, hi))
    inside = 0.1 * span
    if end == "max":
        bounds, plaus = (hi - inside, max(hi + 0.5 * span, out_hi + 0.1 * span)), (hi - inside, hi + 0.5 * span)
    else:
        bounds, plaus = (min(lo - 0.5 * span, out_lo - 0.1 * span), lo + inside), (lo - 0.5 * span, lo + inside)
    params = [NewParam(x_end, off, bounds, plaus, edge + sign * 0.005 * span, scale=span,
                       reach=(lo - 0.1 * span, hi + 0.1 * span)),
              NewParam(length, 0.03 * span, (0.003 * span, 0.3 * span), (0.003 * span, 0.3 * span), 0.03 * span, True,
                       primary=False, shapes=(0.01 * span, 0.1 * span)),
              NewParam(needle, 0.1 * kv, (1e-4 * kv, 3 * kv), (1e-4 * kv, 3 * kv), 0.1 * kv, True, primary=False,
                       shapes=(0.01 * kv, 0.3 * kv))]
    stop, fixed = _metal_stop(ctx, act, end, lo, hi, span, params[0])
    params += stop
    keep = {act.name}
    values = {role.param("open_flow"): OPEN * kv, role.param("check"): OPEN * kv, role.param("direction"): sign,
              role.param("entry"): ENTRY * span, role.param("end"): off, role.param("length"): 0.03 * span,
              role.param("needle"): 0.1 * kv}

    def build(net):
        for comp, port in list(net.nodes().get(chamber, [])):
            c = net.components[comp]
            if comp in keep or c.type in SENSOR_TYPES or c.type == vtyp:
                continue                       # the chamber keeps its actuator, sensors and volumes
            net = A.connect(net, comp, port, line)
        net = A.add(net, fit, vtyp, {vrole.port("node"): line}, {vrole.param("volume"): LINE_VOLUME * max(v_dead, 1e-6)})
        net = A.add(net, name, typ, {role.port("chamber"): chamber, role.port("line"): line,
                                     role.port("motion"): node, role.port("reference"): ref}, values)
        if fixed:
            net = A.set_values(net, fixed)
        net = A.free_new(net, params)
        p0 = (net.doc.get("initial") or {}).get(f"{chamber}.p")
        return A.set_initial(net, {f"{line}.p": p0}) if p0 is not None and not isinstance(p0, dict) else net
    return Candidate("end_stop", act.name, params, build, "continuity" if not fixed else "force",
                     f"end-position cushioning at the {'upper' if end == 'max' else 'lower'} end: the emptied "
                     "chamber's outflow throttled to a needle over the last part of the stroke",
                     fixed=fixed, variant=f"cushion_{end}")


def _metal_stop(ctx: Context, act: Part, end: str, lo: float, hi: float, span: float,
                x_end: NewParam) -> tuple[list[NewParam], dict]:
    """The metal stop the cushion ends at, where the machine file has none (``stop_stiffness``
    0): a cushion brakes the piston over its last millimetres, the stop behind it takes what is
    left, and without it a piston the cushion has not stopped overruns the stroke in the
    model (dev EHA, seed 101: the cushion alone, fitted at 0.1261 m and 3.4 mm long — the
    truth's place and length — gained 4.8 % of a 181 % held-out error, while the piston ran on
    through the end). Its position (the end's stop slot, judged as a stop's: a primary, so a
    stop without a cushion — the fit moving the cushion out of reach — is still the end stop it
    is: the concealed head stop at 0.128 m was found at 0.12795 m that way) and the contact
    stiffness (a companion) start where the cushion's end (``x_end``) starts; the other end's
    stop is put out of reach and the contact damping fixed as the stop candidate fixes it.
    Returns the stop's new parameters and the fixed values (none when the file has stops, or
    the actuator offers none)."""
    names = {s: act.param(s) for s in ("stop_min", "stop_max", "stop_stiffness", "stop_damping")}
    if None in (names["stop_min"], names["stop_max"], names["stop_stiffness"]):
        return [], {}
    try:
        if ctx.value(names["stop_stiffness"]) > 0:
            return [], {}
    except (KeyError, TypeError, ValueError):
        return [], {}
    mine, other = ("stop_max", "stop_min") if end == "max" else ("stop_min", "stop_max")
    stop = [NewParam(names[mine], x_end.start, x_end.bounds, x_end.plausible, x_end.probe, scale=span,
                     reach=x_end.reach),
            stop_stiffness(ctx, act, names["stop_stiffness"], span)]
    far = hi + 2.0 * span if other == "stop_max" else lo - 2.0 * span
    fixed = {names[other]: far}
    if names["stop_damping"]:
        fixed[names["stop_damping"]] = stop_damping(ctx, act)
    return stop, fixed
