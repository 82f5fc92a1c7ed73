"""Valve effects of every 4/3 valve: spool overlap/underlap of the metering edges
(seed 000 Fig. 8), asymmetric edge gains (valve asymmetry), and spool play/hysteresis
(a play operator between the command and the spool, Tao & Kokotović ch. 2)."""
from __future__ import annotations

from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Skipped

_EDGES = ("overlap_PA", "overlap_BT", "overlap_PB", "overlap_AT")


class ValveFamily(Family):
    effects = ("valve_overlap", "valve_asymmetry", "valve_hysteresis")

    def candidates(self, ctx: Context):
        valves = ctx.of_type("valve_4_3", "valve_pc")
        if not valves:
            return [Skipped(e, "no proportional directional valve in the machine") for e in self.effects]
        out = []
        for v in valves:
            out.append(self.parameter_candidate(
                ctx, "valve_overlap", v,
                [NewParam(f"{v}.{e}", 0.0, (-0.05, 0.1), (5e-3, 0.1), 0.01) for e in _EDGES]
                + [NewParam(f"{v}.G_leak", 1e-14, (1e-15, 1e-10), (1e-14, 1e-10), 1e-12, True, primary=False)],
                "valve", "overlap (dead band) of the metering edges around spool centre, with the leakage "
                         "of the covered edges (below 0.5 % of the stroke: within the lap tolerance of a "
                         "zero-lap spool, not an effect)"))
            out.append(self.parameter_candidate(
                ctx, "valve_asymmetry", v, [NewParam(f"{v}.Kv_neg_ratio", 1.0, (0.5, 2.0), (0.05, 1.0), 0.8, ref=1.0)],
                "valve", "different flow gains for positive and negative spool openings"))
            if ctx.net.components[v].type == "valve_4_3":
                out.append(self._edges(ctx, v))
            out.append(self._hysteresis(ctx, v))
        return out

    @staticmethod
    def _edges(ctx: Context, valve: str):
        """Four unmatched metering edges: one gain per edge (meter-in and meter-out differ, and
        the two directions differ). When Kv is free in the base model one edge gain is fixed
        at 1 (Kv carries the common scale)."""
        kv_free = f"{valve}.Kv" in ctx.free
        edges = ("g_BT", "g_PB", "g_AT") if kv_free else ("g_PA", "g_BT", "g_PB", "g_AT")
        probes = {"g_PA": 1.2, "g_BT": 1.2, "g_PB": 0.8, "g_AT": 0.8}
        params = [NewParam(f"{valve}.{g}", 1.0, (0.3, 3.0), (0.08, 2.0), probes[g], ref=1.0) for g in edges]

        def build(net):
            net = A.set_type(net, valve, "valve_4_3_edges")
            return A.free_new(net, params)
        return Candidate("valve_asymmetry", valve, params, build, "valve",
                         "unmatched metering edges: one flow gain per edge (meter-in/meter-out, both directions)",
                         variant="edges")

    @staticmethod
    def _hysteresis(ctx: Context, valve: str):
        cmd = ctx.net.components[valve].ports.get("cmd")
        if cmd is None:
            return Skipped("valve_hysteresis", f"'{valve}' has no command signal")
        play = A.unique_name(ctx.net, f"{valve}_play")
        node = A.unique_name(ctx.net, f"{cmd}_{valve}")
        # half-width b, and the rounding of the band's edges (a companion): magnetic hysteresis
        # of a torque motor closes its loop gradually, a worn linkage's play abruptly
        params = [NewParam(f"{play}.b", 1e-4, (0.0, 0.1), (2e-3, 0.1), 0.01),
                  NewParam(f"{play}.eps", 1e-4, (1e-5, 0.02), (1e-5, 0.02), 2e-3, True, primary=False)]

        def build(net):
            net = A.add(net, play, "play", {"in": cmd, "out": node})
            net = A.connect(net, valve, "cmd", node)
            return A.free_new(net, params)
        return Candidate("valve_hysteresis", valve, params, build,
                         "valve", "play (backlash, rounded or sharp) between command and spool: the spool lags a "
                                  "reversing command")
