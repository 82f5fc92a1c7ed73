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


def feeders(ctx: Context, actuator: str, chamber_nodes: tuple[str | None, ...]) -> tuple[tuple[Feeder, ...], ...]:
    """For each node of ``chamber_nodes`` (an actuator's chambers, in its ``dead_volumes``
    order), the free volumes on its side of the circuit (module docstring)."""
    asm, _ = stamp(ctx.net)
    flow: dict[str, set[str]] = {}          # component -> hydraulic nodes where it takes flow
    for node, info in asm.nodes.items():
        if info.domain != Domain.HYDRAULIC:
            continue
        for comp, expr in info.through:
            if not (expr.op == "const" and expr.args[0] == 0.0):
                flow.setdefault(comp, set()).add(node)
    stops = {actuator} | {p.name for role in (R.ACTUATOR, R.METERING_VALVE, R.PRESSURE_SOURCE, R.TANK)
                          for p in ctx.parts(role)}
    volumes: dict[str, list] = {}
    for p in ctx.parts(R.VOLUME):
        if p.param("volume") in ctx.free:
            volumes.setdefault(p.node("node"), []).append(p)
    out = []
    for start in chamber_nodes:
        others = {n for n in chamber_nodes if n is not None and n != start}
        seen, queue, found = {start}, [start] if start is not None else [], []
        while queue:
            node = queue.pop()
            found += [_feeder(ctx, part) for part in volumes.get(node, [])]
            for comp, nodes in flow.items():
                if comp in stops or node not in nodes:
                    continue
                for nxt in sorted(nodes - seen - others):
                    seen.add(nxt)
                    queue.append(nxt)
        out.append(tuple(found))
    return tuple(out)


def _feeder(ctx: Context, part) -> Feeder:
    vol, mod = part.param("volume"), part.param("bulk_modulus") or ""
    try:
        beta = ctx.value(mod)
    except (KeyError, TypeError, ValueError):     # no modulus slot, or not set: the chamber's is used
        beta = float("nan")
    return Feeder(vol, mod, ctx.value(vol), beta)
