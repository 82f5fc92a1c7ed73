"""The fluid volumes on each side of an actuator, found along the flow paths of the circuit.

A chamber's volume at the reference position is a drawing dimension, and a fit that needs more
of it reads as fluid the drawing leaves out (:mod:`.findings`). But a fit may also move
compliance between two volumes the drawing HAS on the same side of the metering valve: a
counterbalance valve between the valve's work line (with its own oil volume) and the cylinder
leaves the line's volume and the chamber's in series, and a fit can grow the chamber by what it
takes from the line. The total compliance V/β on that side is then what the drawing has, and
there is no undrawn fluid. :func:`feeders` lists, for each chamber, the free ``volume`` parts
reached from the chamber's node along paths that carry flow, without passing the actuator, a
metering valve, a pressure source or a tank: the other side of the actuator lies beyond the
metering valve, the supply and the return beyond the source and the tank.

Flow is read from the stamped equations (:func:`hydrocli.model.builder.stamp`): a component
joins two nodes when it takes a flow other than the constant 0 at both. A counterbalance
valve's pilot port, a sensor, a seal friction sensing the chamber pressures take none, so the
rod-side chamber that pilots the valve is not joined to the piston-side line through it.
"""
from __future__ import annotations

from ..components import roles as R
from ..components.base import Domain
from ..model.builder import stamp
from .candidates import Context
from .findings import Feeder


def feeders(ctx: Context) -> dict[str, tuple[tuple[Feeder, ...], ...]]:
    """{actuator: for each of its chambers (``chamber_a``, ``chamber_b``: its ``dead_volumes``
    order), the free volumes on that side of the circuit} (module docstring). The machine is
    stamped once for all its actuators."""
    asm, _ = stamp(ctx.net)
    joined: dict[str, set[str]] = {}       # hydraulic node -> components taking flow there
    reach: dict[str, set[str]] = {}        # component -> hydraulic nodes where it takes flow
    for node, info in asm.nodes.items():
        if info.domain != Domain.HYDRAULIC:
            continue
        for comp, expr in info.through:
            if not (expr.op == "const" and expr.args[0] == 0.0):
                joined.setdefault(node, set()).add(comp)
                reach.setdefault(comp, set()).add(node)
    stops = {p.name for role in (R.ACTUATOR, R.METERING_VALVE, R.PRESSURE_SOURCE, R.TANK) for p in ctx.parts(role)}
    volumes: dict[str, list[Feeder]] = {}
    for p in ctx.parts(R.VOLUME):
        if p.param("volume") in ctx.free:
            volumes.setdefault(p.node("node"), []).append(_feeder(ctx, p))
    out = {}
    for act in ctx.parts(R.ACTUATOR):
        chambers = (act.node("chamber_a"), act.node("chamber_b"))
        sides = []
        for start in chambers:
            others = {n for n in chambers if n is not None and n != start}
            seen, queue, found = {start}, [start] if start is not None else [], []
            while queue:
                node = queue.pop()
                found += volumes.get(node, [])
                for comp in sorted(joined.get(node, set()) - stops):
                    for nxt in sorted(reach[comp] - seen - others):
                        seen.add(nxt)
                        queue.append(nxt)
            sides.append(tuple(found))
        out[act.name] = tuple(sides)
    return out


def file_value(ctx: Context, name: str | None) -> float:
    """The file's value of parameter ``name``, NaN when there is none (no such slot, not set)."""
    try:
        return ctx.value(name) if name else float("nan")
    except (KeyError, TypeError, ValueError):
        return float("nan")


def _feeder(ctx: Context, part) -> Feeder:
    mod = part.param("bulk_modulus")
    # no modulus slot, or not set: NaN, and the chamber's modulus stands in (findings.net_of_feeders)
    return Feeder(part.param("volume"), mod or "", ctx.value(part.param("volume")), file_value(ctx, mod))
