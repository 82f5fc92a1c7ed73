"""Circuit effects between the components: line dynamics between each valve work port and
its cylinder chamber (a fluid line with inertance and laminar loss, plus the line's volume
at the valve end; seed 001 eqs. 7, 11; seed 002 §3) and a supply pressure drop (an orifice
and a volume between the pressure source and the valve; seed 004's supply droop)."""
from __future__ import annotations

from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Skipped


class CircuitFamily(Family):
    effects = ("line_dynamics", "supply_pressure_drop")

    def candidates(self, ctx: Context):
        out = []
        for valve in ctx.of_type("valve_4_3", "valve_pc"):
            ports = ctx.net.components[valve].ports
            out.append(self._lines(ctx, valve, ports))
            out.append(self._supply(ctx, valve, ports.get("P")))
        return out or [Skipped(e, "no directional valve in the machine") for e in self.effects]

    @staticmethod
    def _lines(ctx: Context, valve: str, ports: dict[str, str]):
        pairs = []
        for vp in ("A", "B"):
            node = ports.get(vp)
            cyl = [(c, p) for c, p in ctx.on_node(node) if ctx.net.components[c].type.startswith("cylinder")]
            if cyl:
                pairs.append((vp, node, cyl[0]))
        if not pairs:
            return Skipped("line_dynamics", f"the work ports of '{valve}' do not lead to a cylinder")
        params, plan = [], []
        for vp, node, (cyl, cport) in pairs:
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
            for p in params:
                net = A.free(net, p.name, p.start, p.bounds, True)
            return _initial_like(net, [(new, node) for _, new, node, _, _ in plan])
        return Candidate("line_dynamics", valve, params, build, "continuity",
                         f"hoses between '{valve}' and the cylinder: inertance, loss and volume")

    @staticmethod
    def _supply(ctx: Context, valve: str, node: str | None):
        if node is None:
            return Skipped("supply_pressure_drop", f"'{valve}' has no supply port")
        src = [c for c, _ in ctx.on_node(node) if ctx.net.components[c].type == "pressure_source"]
        if not src:
            return Skipped("supply_pressure_drop", f"no pressure source at the supply of '{valve}'")
        orf = A.unique_name(ctx.net, "supply_orifice")
        vol = A.unique_name(ctx.net, "supply_volume")
        new = A.unique_name(ctx.net, f"{node}_source")

        def build(net):
            net = A.connect(net, src[0], "P", new)
            net = A.add(net, orf, "orifice", {"A": new, "B": node})
            net = A.add(net, vol, "volume", {"P": node}, {"V": 1e-4})
            net = A.free(net, f"{orf}.Kv", 1e-5, (1e-7, 1e-4), True)
            return net
        return Candidate("supply_pressure_drop", src[0], [NewParam(f"{orf}.Kv", 1e-5, (1e-7, 1e-4), (1e-7, 5e-6), 2e-6, True)],
                         build, "continuity", f"pressure drop in the supply line of '{valve}' (orifice + volume)")


def _initial_like(net, pairs):
    from ...netlist import yamldoc as Y
    doc = Y.load_text(Y.dump_text(net.doc), net.file)
    init = doc.get("initial")
    if init is not None:
        for new, old in pairs:
            if f"{old}.p" in init:
                init[f"{new}.p"] = init[f"{old}.p"]
    return A.reload(net, Y.dump_text(doc))
