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
                [NewParam(f"{v}.{e}", 0.0, (-0.05, 0.1), (2e-3, 0.1), 0.01) for e in _EDGES]
                + [NewParam(f"{v}.G_leak", 1e-14, (1e-15, 1e-10), (1e-14, 1e-10), 1e-12, True, primary=False)],
                "valve", "overlap (dead band) of the metering edges around spool centre, with the leakage "
                         "of the covered edges"))
            out.append(self.parameter_candidate(
                ctx, "valve_asymmetry", v, [NewParam(f"{v}.Kv_neg_ratio", 1.0, (0.5, 2.0), (0.03, 1.0), 1.1)],
                "valve", "different flow gains for positive and negative spool openings"))
            out.append(self._hysteresis(ctx, v))
        return out

    @staticmethod
    def _hysteresis(ctx: Context, valve: str):
        cmd = ctx.net.components[valve].ports.get("cmd")
        if cmd is None:
            return Skipped("valve_hysteresis", f"'{valve}' has no command signal")
        play = A.unique_name(ctx.net, f"{valve}_play")
        node = A.unique_name(ctx.net, f"{cmd}_{valve}")
        b = f"{play}.b"

        def build(net):
            net = A.add(net, play, "play", {"in": cmd, "out": node})
            net = A.connect(net, valve, "cmd", node)
            return A.free(net, b, 1e-4, (0.0, 0.1), None)
        return Candidate("valve_hysteresis", valve, [NewParam(b, 1e-4, (0.0, 0.1), (2e-3, 0.1), 0.01)], build,
                         "valve", "play between command and spool: the spool lags a reversing command")
