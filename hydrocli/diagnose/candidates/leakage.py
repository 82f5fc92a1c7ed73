"""Leakage and fluid effects of cylinders: internal (cross-piston) leakage, external
leakage, entrained air (seed 004 eqs. 4–7; Merritt, *Hydraulic Control Systems* §3.3;
Jelali & Kroll eq. 3.12 for the air-in-oil bulk modulus) and end stops."""
from __future__ import annotations

from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Skipped


class CylinderFamily(Family):
    effects = ("internal_leakage", "external_leakage", "entrained_air", "end_stop")

    def candidates(self, ctx: Context):
        out = []
        cyls = ctx.of_type("cylinder")
        if not cyls:
            return [Skipped(e, "no cylinder in the machine") for e in self.effects]
        for cyl in cyls:
            p = f"{cyl}."
            ports = ctx.net.components[cyl].ports
            il = self.parameter_candidate(
                ctx, "internal_leakage", cyl, [NewParam(p + "c_il", 1e-13, (1e-14, 1e-9), (5e-13, 5e-10), 2e-11, True)],
                "continuity", "laminar leakage across the piston, q = c_il·(p_A − p_B)")
            if isinstance(il, Skipped):   # laminar law already identified: try a worn-seal orifice
                il = _orifice(ctx, "internal_leakage", cyl, [(ports["A"], ports["B"])],
                              "turbulent leakage across a worn piston seal (orifice A→B), on top of the laminar one")
            out.append(il)
            el = self.parameter_candidate(
                ctx, "external_leakage", cyl, [NewParam(p + "c_el", 1e-14, (1e-15, 1e-9), (1e-13, 5e-10), 1e-11, True)],
                "continuity", "laminar leakage of each chamber to drain, q = c_el·p")
            tank = _tank_node(ctx)
            if isinstance(el, Skipped) and tank:
                el = _orifice(ctx, "external_leakage", cyl, [(ports["A"], tank), (ports["B"], tank)],
                              "rod/piston seals leaking to drain through orifices (turbulent law)")
            out.append(el)
            out.append(self.parameter_candidate(
                ctx, "entrained_air", cyl, [NewParam(p + "air", 1e-4, (1e-5, 0.3), (1e-3, 0.3), 0.03, True)],
                "continuity", "undissolved air lowers the chamber stiffness at low pressure (log scale up "
                              "to 30 %: an isentropic fit of isothermal, partly dissolving air needs more)"))
            out.append(self._end_stop(ctx, cyl))
        return out

    def _end_stop(self, ctx: Context, cyl: str):
        node = ctx.net.components[cyl].ports.get("rod")
        rng = ctx.position_range.get(node)
        if rng is None:
            return Skipped("end_stop", f"no position range of '{cyl}' seen in the data")
        lo, hi = rng
        span = max(hi - lo, 1e-3)
        # stop positions have no "off" value: judged as positions (plausible range of the value,
        # standard error against the stroke seen)
        params = [NewParam(f"{cyl}.x_min", lo - 0.2 * span, (lo - 0.5 * span, lo + 0.02 * span),
                           (lo - 0.5 * span, lo + 0.02 * span), lo - 0.005 * span, scale=span),
                  NewParam(f"{cyl}.x_max", hi + 0.2 * span, (hi - 0.02 * span, hi + 0.5 * span),
                           (hi - 0.02 * span, hi + 0.5 * span), hi + 0.005 * span, scale=span),
                  # contact stiffness identified too (log scale): a real stop (Hertz/Hunt–Crossley
                  # contact) is far from one fixed linear spring
                  NewParam(f"{cyl}.k_stop", 1e8, (1e5, 1e11), (1e5, 1e11), 3e8, True, primary=False)]
        return self.parameter_candidate(ctx, "end_stop", cyl, params, "force",
                                        "stiff end stops at the stroke ends", fixed={f"{cyl}.c_stop": 1e4})


def _tank_node(ctx: Context) -> str | None:
    return next((c.ports["T"] for c in ctx.net.components.values() if c.type == "tank" and "T" in c.ports), None)


def _orifice(ctx: Context, effect: str, cyl: str, paths: list[tuple[str, str]], description: str) -> Candidate:
    """Leakage paths as turbulent orifices (q = K·dp/(dp² + dp_t²)^¼, seed 004 eq. 3 form)."""
    names = [A.unique_name(ctx.net, f"{cyl}_{effect}_{i + 1}") for i in range(len(paths))]
    params = [NewParam(f"{n}.Kv", 1e-11, (1e-12, 1e-6), (3e-10, 1e-6), 1e-8, True) for n in names]

    def build(net):
        for n, (a, b) in zip(names, paths):
            net = A.add(net, n, "orifice", {"A": a, "B": b}, {"dp_lam": 2e5})
        return A.free_new(net, params)
    return Candidate(effect, cyl, params, build, "continuity", description)
