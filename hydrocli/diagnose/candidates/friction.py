"""Friction effects on the moving node of every cylinder (seed 004 eqs. 9–11:
viscous k_v, Coulomb k_c, Stribeck k_s·e^(−|v|/v_s); seed 000 eq. 23: seal friction
proportional to the chamber pressures, μ_p·A_p·(p_A + p_B))."""
from __future__ import annotations

from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Skipped


class FrictionFamily(Family):
    effects = ("viscous_friction", "coulomb_friction", "stribeck_friction", "pressure_dependent_friction")

    def candidates(self, ctx: Context):
        out = []
        cyls = ctx.of_type("cylinder")
        if not cyls:
            return [Skipped(e, "no cylinder rod to attach friction to") for e in self.effects]
        for cyl in cyls:
            decl = ctx.net.components[cyl]
            rod = decl.ports.get("rod")
            fr = next((c for c, port in ctx.on_node(rod) if ctx.net.components[c].type == "friction" and port == "a"),
                      None)
            area = self._area(ctx, cyl)
            if fr is None:
                fr = A.unique_name(ctx.net, f"{cyl}_friction")
                out.extend(self._new_friction(ctx, fr, rod, cyl, area))
                continue
            out.extend(self._existing(ctx, fr, cyl, area))
        return out

    @staticmethod
    def _area(ctx: Context, cyl: str) -> float:
        params = ctx.net.components[cyl].params
        return float(params["A"].value if "A" in params else params["A_A"].value)

    def _existing(self, ctx: Context, fr: str, cyl: str, area: float):
        f = f"{fr}."
        fmax = 2e5 * area  # a seal force of 2 bar on the piston area: the plausible scale
        out = [
            self.parameter_candidate(ctx, "viscous_friction", fr, _pair(f + "kv", 10.0, (0.0, 1e6), (1.0, 1e6), 5e3),
                                     "force", "viscous friction k_v·v"),
            self.parameter_candidate(ctx, "coulomb_friction", fr,
                                     _pair(f + "kc", 1.0, (0.0, 20 * fmax), (0.01 * fmax, 20 * fmax), fmax),
                                     "force", "Coulomb friction k_c·sign(v)"),
            self.parameter_candidate(ctx, "stribeck_friction", fr,
                                     _pair(f + "ks", 1.0, (0.0, 20 * fmax), (0.01 * fmax, 20 * fmax), fmax),
                                     "force", "breakaway excess k_s·e^(−|v|/v_s)·sign(v) at low speed"),
        ]
        pa, pb = ctx.net.components[cyl].ports.get("A"), ctx.net.components[cyl].ports.get("B")
        connect = {"pa": pa, "pb": pb}
        out.append(self.parameter_candidate(
            ctx, "pressure_dependent_friction", fr, [NewParam(f + "mu_p", 1e-4, (0.0, 0.2), (2e-3, 0.2), 0.02)],
            "force", "seal friction growing with chamber pressure, μ_p·A·(p_A + p_B)·sign(v)",
            fixed={f + "A_p": area}, connect=connect))
        out.append(self._seal(ctx, fr, cyl, area))
        return out

    @staticmethod
    def _seal(ctx: Context, fr: str, cyl: str, area: float) -> Candidate:
        """Seal friction loaded by the pressure DIFFERENCE across the piston seal."""
        ports = ctx.net.components[cyl].ports
        rod = ports["rod"]
        name = A.unique_name(ctx.net, f"{cyl}_seal_friction")
        prm = NewParam(f"{name}.mu_d", 1e-4, (0.0, 1.0), (2e-3, 1.0), 0.05)
        body = ports.get("body", "ground")

        def build(net):
            net = A.add(net, name, "seal_friction", {"a": rod, "b": body, "pa": ports["A"], "pb": ports["B"]},
                        {"A_p": area})
            return A.free(net, prm.name, prm.start, prm.bounds)
        return Candidate("pressure_dependent_friction", fr, [prm], build, "force",
                         "piston-seal friction growing with the pressure difference, μ_d·A·|p_A − p_B|·sign(v)",
                         variant="dp")

    def _new_friction(self, ctx: Context, fr: str, rod: str, cyl: str, area: float):
        """No friction element yet: each friction effect adds one on the rod node."""
        def adder(params, connect_pressures=False):
            def build(net):
                ports = {"a": rod, "b": "ground"}
                if connect_pressures:
                    d = net.components[cyl].ports
                    ports.update(pa=d["A"], pb=d["B"])
                extra = {"A_p": area} if connect_pressures else {}
                net = A.add(net, fr, "friction", ports, extra)
                return A.free_new(net, params)
            return build
        fmax = 2e5 * area
        f = f"{fr}."
        specs = {
            "viscous_friction": (_pair(f + "kv", 10.0, (0.0, 1e6), (1.0, 1e6), 5e3), False),
            "coulomb_friction": (_pair(f + "kc", 1.0, (0.0, 20 * fmax), (0.01 * fmax, 20 * fmax), fmax), False),
            "stribeck_friction": (_pair(f + "ks", 1.0, (0.0, 20 * fmax), (0.01 * fmax, 20 * fmax), fmax), False),
            "pressure_dependent_friction": ([NewParam(f + "mu_p", 1e-4, (0.0, 0.2), (2e-3, 0.2), 0.02)], True),
        }
        return [Candidate(e, cyl, ps, adder(ps, pr), "force", f"{e.replace('_', ' ')} on '{rod}'")
                for e, (ps, pr) in specs.items()]


def _pair(prefix: str, start, bounds, plausible, probe) -> list[NewParam]:
    """The same law for both directions of motion (``_p``: v > 0, ``_m``: v < 0)."""
    return [NewParam(f"{prefix}_{d}", start, bounds, plausible, probe) for d in ("p", "m")]
