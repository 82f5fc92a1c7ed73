"""Mechanical effects on the load side of every cylinder (linear-graph elements of the
library: mass, spring, damper).

* load_compliance: the rod drives the load through a spring–damper (rod/coupling
  elasticity): the load's mass and external forces move to a new node; the rod keeps a
  small mass; position/velocity outputs read the load side (seed 002 §4; Jelali & Kroll §3.6).
* structural_flexibility: the cylinder body sits on a compliant structure (a frame mass on
  a spring–damper to ground) instead of rigid ground.
* payload_swing: a pendulum payload of mass m_p on a rope of length L; for small angles it
  acts on the node as a mass on a spring k = m_p·g/L (plus damping).
"""
from __future__ import annotations

from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Skipped

G = 9.81


class MechanicsFamily(Family):
    effects = ("load_compliance", "structural_flexibility", "payload_swing")

    def candidates(self, ctx: Context):
        out = []
        for cyl in ctx.of_type("cylinder"):
            ports = ctx.net.components[cyl].ports
            rod, body = ports.get("rod"), ports.get("body")
            masses = [c for c, _ in ctx.on_node(rod) if ctx.net.components[c].type == "mass"]
            if not masses:
                out.append(Skipped("load_compliance", f"no mass on the rod node '{rod}' of '{cyl}'"))
                out.append(Skipped("payload_swing", f"no mass on the rod node '{rod}' of '{cyl}'"))
            else:
                m = ctx.value(f"{masses[0]}.m")
                out.append(self._compliance(ctx, cyl, rod, masses[0], m))
                out.append(self._payload(ctx, cyl, rod, m))
            out.append(self._structure(ctx, cyl, body, masses and ctx.value(f"{masses[0]}.m") or 100.0))
        return out or [Skipped(e, "no cylinder in the machine") for e in self.effects]

    @staticmethod
    def _compliance(ctx: Context, cyl: str, rod: str, mass: str, m: float):
        load = A.unique_name(ctx.net, f"{rod}_load")
        spring, damper, rodm = (A.unique_name(ctx.net, f"{cyl}_{s}") for s in ("coupling", "coupling_damper", "rod_mass"))
        keep = {c for c, _ in ctx.on_node(rod) if ctx.net.components[c].type in ("friction",) or c == cyl}
        # the rod side keeps a small mass (piston and rod; the load's mass stays free); the
        # coupling's stiffness AND damping are identified (log scale): a fixed damper sized for
        # a stiff link would overdamp a soft one and hide it. Probes where a link is visible
        # (a mode at some 10–30 Hz for the identified mass).
        k_probe = (2 * 3.14159 * 25.0) ** 2 * 0.3 * m
        c0 = 0.2 * (1e7 * 0.1 * m) ** 0.5
        params = [NewParam(f"{spring}.k", 1e9, (1e5, 1e10), (1e5, 5e8), k_probe, True),
                  NewParam(f"{damper}.c", c0, (1.0, 1e5), (1.0, 1e5), 0.3 * c0, True, primary=False)]

        def build(net):
            net = A.move_node(net, rod, load, keep)
            net = A.add(net, rodm, "mass", {"m": rod}, {"m": 0.1 * m})
            net = A.add(net, spring, "spring", {"a": rod, "b": load})
            net = A.add(net, damper, "damper", {"a": rod, "b": load}, {"c": c0})
            net = A.rewrite_outputs(net, {f"{rod}.x": f"{load}.x", f"{rod}.v": f"{load}.v"})
            net = _move_initial(net, rod, load)
            return A.free_new(net, params)
        return Candidate("load_compliance", cyl, params,
                         build, "force", f"elastic coupling between the rod of '{cyl}' and its load "
                                         "(x and v measured on the load side)")

    @staticmethod
    def _payload(ctx: Context, cyl: str, rod: str, m: float):
        node = A.unique_name(ctx.net, f"{rod}_payload")
        pm, sp, dm = (A.unique_name(ctx.net, f"payload_{s}") for s in ("mass", "rope", "damper"))
        mp = 0.3 * m

        def build(net):
            net = A.add(net, pm, "mass", {"m": node}, {"m": 1e-3 * m})
            net = A.add(net, sp, "spring", {"a": rod, "b": node}, {"k": mp * G / 1.0})
            net = A.add(net, dm, "damper", {"a": rod, "b": node}, {"c": 0.05 * mp * (G / 1.0) ** 0.5})
            return A.free(net, f"{pm}.m", 1e-3 * m, (1e-4 * m, 2.0 * m), True)
        return Candidate("payload_swing", rod, [NewParam(f"{pm}.m", 1e-3 * m, (1e-4 * m, 2 * m), (0.02 * m, 2 * m),
                                                         0.3 * m, True)],
                         build, "force", f"a swinging payload (pendulum, L = 1 m) hanging on '{rod}'")

    @staticmethod
    def _structure(ctx: Context, cyl: str, body: str | None, m: float):
        if body is None or body != "ground":
            return Skipped("structural_flexibility", f"the body of '{cyl}' is not fixed to ground")
        frame = A.unique_name(ctx.net, f"{cyl}_frame")
        fm, sp, dm = (A.unique_name(ctx.net, f"{cyl}_{s}") for s in ("frame_mass", "mount", "mount_damper"))

        def build(net):
            net = A.connect(net, cyl, "body", frame)
            net = A.add(net, fm, "mass", {"m": frame}, {"m": 2.0 * m})
            net = A.add(net, sp, "spring", {"a": frame, "b": "ground"})
            net = A.add(net, dm, "damper", {"a": frame, "b": "ground"}, {"c": 0.1 * 2 * (1e9 * 2 * m) ** 0.5})
            return A.free(net, f"{sp}.k", 1e9, (1e5, 1e10), True)
        return Candidate("structural_flexibility", cyl, [NewParam(f"{sp}.k", 1e9, (1e5, 1e10), (1e5, 5e8), 1e7, True)],
                         build, "force", f"compliant mounting of the body of '{cyl}'")


def _move_initial(net, old: str, new: str):
    """Initial position of the old node also for the new one (the coupling starts relaxed)."""
    init = net.doc.get("initial") or {}
    return A.set_initial(net, {f"{new}.{str(k).split('.', 1)[1]}": v for k, v in init.items()
                               if str(k).startswith(f"{old}.")})
