"""Circuit effects between the components: line dynamics between each valve work port and
its cylinder chamber (a fluid line with inertance and laminar loss, plus the line's volume
at the valve end; seed 001 eqs. 7, 11; seed 002 §3) and a supply pressure drop (an orifice
and a volume between the pressure source and the valve; seed 004's supply droop)."""
from __future__ import annotations

from ...components import roles as R
from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Part, Skipped


class CircuitFamily(Family):
    effects = ("line_dynamics", "supply_pressure_drop")

    def candidates(self, ctx: Context):
        out = []
        for v in ctx.parts(R.METERING_VALVE):
            out.append(self._lines(ctx, v))
            out.append(self._supply(ctx, v.name, v.node("supply")))
        return out or [Skipped(e, "no directional valve in the machine") for e in self.effects]

    @staticmethod
    def _lines(ctx: Context, v: Part):
        valve = v.name
        pairs = []
        for slot in ("work_a", "work_b"):
            node, vp = v.node(slot), v.role.port(slot)
            if ctx.parts_on(node, R.ACTUATOR):
                pairs.append((vp, node))
        if not pairs:
            return Skipped("line_dynamics", f"the work ports of '{valve}' do not lead to an actuator")
        params, plan = [], []
        for vp, node in pairs:
            line = A.unique_name(ctx.net, f"{valve}_line_{vp}")
            vol = A.unique_name(ctx.net, f"{valve}_port_{vp}")
            new = A.unique_name(ctx.net, f"{node}_valve")
            params.append(NewParam(f"{line}.l", 0.05, (0.01, 20.0), (0.2, 20.0), 2.0, True))
            plan.append((vp, new, node, line, vol))

        def build(net):
            for vp, new, node, line, vol in plan:
                net = A.connect(net, valve, vp, new)
                net = A.add(net, vol, "volume", {"P": new}, {"V": 2e-5})
                net = A.add(net, line, "fluid_line", {"A": new, "B": node}, {"d": 0.01})
            net = A.free_new(net, params)
            return _initial_like(net, [(new, node) for _, new, node, _, _ in plan])
        return Candidate("line_dynamics", valve, params, build, "continuity",
                         f"hoses between '{valve}' and the cylinder: inertance, loss and volume")

    @staticmethod
    def _supply(ctx: Context, valve: str, node: str | None):
        """Supply line restriction (clogged filter, thin line: turbulent orifice) with the oil
        and accumulator capacity behind it at the valve's P port. Sized from the valve's own
        flow coefficient: the drop is (Kv_valve/Kv_supply)² of the valve's, so the orifice
        starts at 30× Kv_valve (drop 0.1 %, no effect) and is probed at 1.5× (drop ~45 %)."""
        if node is None:
            return Skipped("supply_pressure_drop", f"'{valve}' has no supply port")
        srcs = ctx.parts_on(node, R.PRESSURE_SOURCE, "out")
        if not srcs:
            return Skipped("supply_pressure_drop", f"no pressure source at the supply of '{valve}'")
        src = [srcs[0].name]
        out_port = srcs[0].role.port("out")
        kv = _valve_kv(ctx, valve)
        orf = A.unique_name(ctx.net, "supply_orifice")
        vol = A.unique_name(ctx.net, "supply_volume")
        new = A.unique_name(ctx.net, f"{node}_source")
        params = [NewParam(f"{orf}.Kv", 30 * kv, (0.03 * kv, 100 * kv), (0.1 * kv, 10 * kv), 1.5 * kv, True),
                  # line oil + any accumulator: an equivalent oil volume (log scale), a companion
                  NewParam(f"{vol}.V", 1e-3, (1e-5, 2e-2), (1e-5, 2e-2), 2e-3, True, primary=False)]
        p_start = _source_pressure(ctx, srcs[0])

        def build(net):
            net = A.connect(net, src[0], out_port, new)
            net = A.add(net, orf, "orifice", {"A": new, "B": node})
            net = A.add(net, vol, "volume", {"P": node}, {"V": 1e-3})
            net = A.free_new(net, params)
            return A.set_initial(net, {f"{node}.p": p_start}) if p_start else net
        return Candidate("supply_pressure_drop", src[0], params, build, "continuity",
                         f"pressure drop in the supply line of '{valve}' (turbulent restriction + line/accumulator volume)")


def _valve_kv(ctx: Context, valve: str) -> float:
    """The valve's flow coefficient per edge (SI, its role's ``flow_gain``), or a mid-size
    valve's when not readable."""
    part = next((p for p in ctx.parts(R.METERING_VALVE) if p.name == valve), None)
    name = part.param("flow_gain") if part else None
    try:
        return ctx.value(name) if name else 5e-7
    except (KeyError, TypeError, ValueError):
        return 5e-7


def _source_pressure(ctx: Context, src: Part) -> float | None:
    """The source's pressure at the start: its input's first sample, or its parameter."""
    ref = src.node("reference")
    if ref is not None:
        return ctx.inputs_start.get(ref)
    try:
        return ctx.value(src.param("pressure"))
    except (KeyError, TypeError, ValueError):
        return None


def _initial_like(net, pairs):
    """New nodes start like the node they were split from (its ``initial`` entry, if any)."""
    init = net.doc.get("initial") or {}
    return A.set_initial(net, {f"{new}.p": init[f"{old}.p"] for new, old in pairs if f"{old}.p" in init})
