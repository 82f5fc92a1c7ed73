"""Mechanical effects on the load side of every actuator, translational or rotary (library
elements found by role for the moving node's domain: a load (mass or inertia), a spring
(spring or shaft), a damper (damper or rotary damper)).

* load_compliance: the rod drives the load through a spring–damper (rod/coupling
  elasticity): the load's mass and external forces move to a new node; the rod keeps a
  small mass; position/velocity outputs read the load side (seed 002 §4; Jelali & Kroll §3.6).
* structural_flexibility: the cylinder body sits on a compliant structure (a frame mass on
  a spring–damper to ground) instead of rigid ground.
(A payload swinging or bouncing on the load is candidates/payload.py.)
"""
from __future__ import annotations

from ...components import registry
from ...components import roles as R
from ...components.base import Domain
from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Part, Skipped

G = 9.81
PROBE_HZ = 25.0   # Hz: the mode a compliance candidate's screening probe puts its mass in
# A compliance's stiffness per unit of the load's mass or inertia, k/m in s⁻² (bounds, and the
# upper end of the plausible range): the load alone on the spring in a mode from 0.5 Hz — a
# crane's or a loader's boom and its mounting ring at 1–3 Hz — to 1.6 kHz, plausible up to
# 360 Hz. (Until session 29 from 10³ s⁻², 5 Hz: a counterbalanced lift's 1.8 Hz mount, 2·10⁵ N/m
# under 1.5 t, ended at that bound and was rejected.) Seven starts span the plausible range
# (0.7 decade apart; the four of every other effect would leave 1.1 decades between them).
K_PER_MASS = (10.0, 1e8)
K_PER_MASS_PLAUSIBLE = 5e6
K_GRID = 7
# A new spring's cubic hardening as hc·F₅₀² (the relative stiffening at the linear force F₅₀,
# :func:`_progressive`): its typical values, crossed with the stiffness grid, and its upper bound
HC_SHAPES = (1.0, 1e4)
HC_MAX = 1e6
# A joint's play (total clearance) by domain: (near nothing, upper bound, plausible range, probe).
# A worn clevis pin or bushing: 0.02–10 mm; a spline or key: 0.2 mrad–0.1 rad (6°)
PLAY = {Domain.TRANSLATIONAL: (1e-6, 0.02, (2e-5, 0.01), 5e-4),
        Domain.ROTATIONAL: (1e-5, 0.3, (2e-4, 0.1), 5e-3)}


class MechanicsFamily(Family):
    effects = ("load_compliance", "structural_flexibility")
    compliances = frozenset({"load_compliance", "structural_flexibility"})
    # a rod–load link in two laws: a spring–damper (with its hardening and the joint's dry
    # friction) and a joint with play (``_clearance``)
    laws = frozenset({"load_compliance"})

    def candidates(self, ctx: Context):
        out = []
        for act in ctx.parts(R.ACTUATOR):
            node, body = act.node("motion"), act.node("reference")
            dom = ctx.domain(node)
            loads = ctx.parts_on(node, R.LOAD)
            m = _inertia(ctx, loads[0]) if loads else None
            if not loads:
                out.append(Skipped("load_compliance", f"no load (mass or inertia) on the moving node '{node}' of '{act.name}'"))
            else:
                out.append(self._compliance(ctx, act, node, dom, m))
                out.append(self._clearance(ctx, act, node, dom, m))
            out.append(self._structure(ctx, act, body, dom, m if m is not None else (100.0 if dom == Domain.TRANSLATIONAL else 1.0)))
        return out or [Skipped(e, "no actuator in the machine") for e in self.effects]

    @staticmethod
    def _compliance(ctx: Context, act: Part, rod: str, dom: Domain, m: float):
        load, rodm, keep = _split_names(ctx, act, rod)
        spring, damper = (A.unique_name(ctx.net, f"{act.name}_{s}") for s in ("coupling", "coupling_damper"))
        stype, srole = ctx.element(R.SPRING, dom)
        dtype, drole = ctx.element(R.DAMPER, dom)
        # the rod side keeps a small mass (piston and rod; the load's mass stays free); the
        # coupling's stiffness AND damping are identified (log scale): a fixed damper sized for
        # a stiff link would overdamp a soft one and hide it. Probes where a link is visible
        # (a mode at some 10–30 Hz for the identified mass or inertia). Bounds scale with the
        # load (K_PER_MASS).
        k_probe = _probe_stiffness(0.3 * m)
        c0 = _link_damping(m)
        params = [_stiffness(f"{spring}.{srole.param('stiffness')}", m, k_probe),
                  _link_damper(f"{damper}.{drole.param('damping')}", m, 0.3)]
        params.append(_rod_side(ctx, rodm, dom, m))
        params += _progressive(ctx, act, spring, srole)
        # the joint's own dry friction (a clevis pin or bushing under load, a clamped boom
        # joint): the link sticks while the force through it changes by less than twice that
        # friction and slips, ringing, only in a hard acceleration. A linear spring–damper is
        # soft at every move or at none (measured, dev lift case with a 300 N joint: validation
        # v ESR 0.43 % rigid, 0.62 % at the true stiffness as a spring–damper, 0.12 % with the
        # joint friction, noise 0.06 %). Sized in the actuator's force units: up to 10 bar on
        # its area (a tenth of a bar probes it); 0 (unused) leaves the linear link
        joint_params, add_joint = dry_joint(ctx, act, dom, f"{act.name}_joint_friction")
        params += joint_params

        def build(net):
            net = _split_load(ctx, net, rod, load, rodm, keep, dom, m)
            net = A.add(net, spring, stype, {srole.port("a"): rod, srole.port("b"): load})
            net = A.add(net, damper, dtype, {drole.port("a"): rod, drole.port("b"): load}, {drole.param("damping"): c0})
            net = add_joint(net, rod, load)
            # the link starts at rest under its load: the spring carrying what holds the load
            # still (its weight) — relaxed, a hanging load would drop at t = 0 and ring on the
            # link (session 9)
            net = A.set_initial(net, {_force_state(spring, stype): {"balance": f"{load}.{dom.across}"}})
            return A.free_new(net, params)
        return Candidate("load_compliance", act.name, params,
                         build, "force", f"elastic coupling between the moving part of '{act.name}' and its load, "
                                         "with the joint's dry friction (motion measured on the load side)",
                         mode=(params[0].name, params[1].name, params[2].name))

    @staticmethod
    def _clearance(ctx: Context, act: Part, rod: str, dom: Domain, m: float):
        """The rod–load (shaft–load) joint as a CLEARANCE: the rod side floats across a free
        play of total width b and meets a stiff, damped contact at either end of it (a worn
        clevis pin, a spline or key with play; library ``clearance``). A law of the rod–load
        link, not another effect: the spring–damper is stiff or soft at every load, a play is
        free while the force through the joint reverses and rigid once it is taken up — what a
        reversing drive shows as a dead stroke and a knock. The play is the primary (log
        scale, from near nothing, four starts over its plausible range); the contact's
        stiffness starts rigid, its damping as the spring–damper's, the rod side's mass as
        there."""
        load, rodm, keep = _split_names(ctx, act, rod)
        joint = A.unique_name(ctx.net, f"{act.name}_clearance")
        jtype, jrole = ctx.element(R.CLEARANCE, dom)
        lo, hi, plausible, probe = PLAY[dom]
        c0 = _link_damping(m)
        params = [NewParam(f"{joint}.{jrole.param('gap')}", lo, (lo, hi), plausible, probe, True),
                  _stiffness(f"{joint}.{jrole.param('stiffness')}", m, 1e7 * m, primary=False),
                  _link_damper(f"{joint}.{jrole.param('damping')}", m, 1.0),
                  _rod_side(ctx, rodm, dom, m)]

        def build(net):
            net = _split_load(ctx, net, rod, load, rodm, keep, dom, m)
            net = A.add(net, joint, jtype, {jrole.port("a"): rod, jrole.port("b"): load},
                        {jrole.param("gap"): lo, jrole.param("damping"): c0})
            # in contact under its load at the start (the play taken up on the side the load
            # pushes, as far as the contact carries it): the deflection that holds the load still
            net = A.set_initial(net, {f"{joint}.d": {"balance": f"{load}.{dom.across}"}})
            return A.free_new(net, params)
        return Candidate("load_compliance", act.name, params, build, "force",
                         f"play (backlash) in the joint between the moving part of '{act.name}' and its load: "
                         "free across the clearance, a stiff damped contact at either end (motion measured on "
                         "the load side)", variant="clearance",
                         mode=(params[1].name, params[2].name, params[3].name))

    @staticmethod
    def _structure(ctx: Context, act: Part, body: str | None, dom: Domain, m: float):
        if body is None or body != "ground":
            return Skipped("structural_flexibility", f"the body of '{act.name}' is not fixed to ground")
        frame = A.unique_name(ctx.net, f"{act.name}_frame")
        rod = act.node("motion")
        fm, sp, dm = (A.unique_name(ctx.net, f"{act.name}_{s}") for s in ("frame_mass", "mount", "mount_damper"))
        ltype, lrole = ctx.element(R.LOAD, dom)
        stype, srole = ctx.element(R.SPRING, dom)
        dtype, drole = ctx.element(R.DAMPER, dom)
        # what moves on the mount (the body, a bracket, part of a boom) is not known: its mass
        # or inertia is identified with the stiffness and the damping (log scale). A frame fixed
        # at twice the load rings at a third of the frequency of a housing a quarter of it and
        # cannot stand in for one (measured, dev rotary mount with a 0.2 kg·m² housing on a
        # 0.8 kg·m² arm: not shortlisted, a rod–load link named). Probes a frame mode at
        # 25 Hz (as the rod–load link); the damper starts at 10 % of critical there
        m_f = 0.3 * m
        k_probe = _probe_stiffness(m_f)
        c0 = 0.2 * (k_probe * m_f) ** 0.5
        params = [_stiffness(f"{sp}.{srole.param('stiffness')}", m, k_probe),
                  NewParam(f"{fm}.{lrole.param('inertia')}", m_f, (0.01 * m, 5.0 * m), (0.01 * m, 5.0 * m), m_f,
                           True, primary=False),
                  NewParam(f"{dm}.{drole.param('damping')}", c0, (1e-3 * c0, 1e3 * c0), (1e-3 * c0, 1e3 * c0),
                           c0, True, primary=False)]
        params += _progressive(ctx, act, sp, srole)

        # the actuator's own friction (seals, vanes) acts between the moving part and the BODY:
        # on a mount it is relative motion that rubs, and its reaction loads the frame, not the
        # ground (an element drawn from the rod to ground stood for "to the body")
        rubbing = [(f.name, f.role.port(slot)) for f in ctx.parts_on(rod, R.FRICTION)
                   for slot in ("a", "b") if f.node(slot) == body]

        def build(net):
            body_port = act.role.port("reference")
            net = A.connect(net, act.name, body_port, frame)
            for comp, port in rubbing:
                net = A.connect(net, comp, port, frame)
            net = A.add(net, fm, ltype, {lrole.port("node"): frame}, {lrole.param("inertia"): m_f})
            net = A.add(net, sp, stype, {srole.port("a"): frame, srole.port("b"): "ground"})
            net = A.add(net, dm, dtype, {drole.port("a"): frame, drole.port("b"): "ground"},
                        {drole.param("damping"): c0})
            # the actuator's own transducer (a cylinder's stroke sensor, a vane's angle encoder)
            # measures the motion RELATIVE to the body: x = x_rod − x_frame. So a mount keeps the
            # chambers' continuity with the measured stroke intact and acts in the force balance
            # only — it cannot stand in for air or a hose, which break that continuity
            mapping = {f"{rod}.{q}": f"({rod}.{q} - {frame}.{q})" for q in (dom.across, dom.position) if q}
            reads = {q: [o for o, d in net.outputs.items() if d.expr.strip() == f"{rod}.{q}"]
                     for q in (dom.across, dom.position) if q}
            net = A.rewrite_outputs(net, mapping)
            # the frame starts at rest on its mount, the mount carrying the actuator's reaction;
            # the rod where the measured stroke puts it (the stroke is no longer a state)
            net = A.set_initial(net, {**{f"{rod}.{q}": {"output": outs[0]} for q, outs in reads.items() if outs},
                                      _force_state(sp, stype): {"balance": f"{frame}.{dom.across}"}})
            return A.free_new(net, params)
        return Candidate("structural_flexibility", act.name, params,
                         build, "force", f"compliant mounting of the body of '{act.name}' (motion measured by "
                                         "the actuator's own transducer, relative to the body)",
                         mode=(params[0].name, params[2].name, params[1].name))


def dry_joint(ctx: Context, act: Part, dom: Domain, stem: str):
    """A dry friction element between two nodes of ``dom`` (a joint's pin or bushing, a rope's
    sheaves), its Coulomb level a companion started at 0 (unused): ``(params, add)``,
    ``add(net, a, b)`` putting it between nodes a and b. Sized in the actuator's force units:
    up to 10 bar on its area; a tenth of a bar probes it."""
    jtype, jrole = ctx.element(R.FRICTION, dom)
    jname = A.unique_name(ctx.net, stem)
    fs = ctx.size(act) * 1e5
    params = [NewParam(f"{jname}.{q}", 0.0, (0.0, 10 * fs), (0.0, 10 * fs), 0.1 * fs, False, primary=False)
              for q in jrole.params_of("coulomb")]
    off = {q: 0.0 for slot in ("viscous", "coulomb", "stribeck") for q in jrole.params_of(slot)}

    def add(net, a: str, b: str):
        return A.add(net, jname, jtype, {jrole.port("a"): a, jrole.port("b"): b}, {**off, "eps": 1e-3})
    return params, add


def _split_names(ctx: Context, act: Part, rod: str) -> tuple[str, str, set]:
    """The new load node, the rod side's mass, and what stays on the rod (the actuator and the
    friction on the rod: seals rub between the rod and the body, not on the load)."""
    load = A.unique_name(ctx.net, f"{rod}_load")
    rodm = A.unique_name(ctx.net, f"{act.name}_rod_mass")
    return load, rodm, {f.name for f in ctx.parts_on(rod, R.FRICTION)} | {act.name}


def _split_load(ctx: Context, net, rod: str, load: str, rodm: str, keep: set, dom: Domain, m: float):
    """The load (its mass or inertia and what acts on it) moved from the rod's node to
    ``load``; the rod keeps a small mass ``rodm``; position and velocity outputs read the load
    side; the rod starts where (and as fast as) the load does. The link between them is the
    caller's."""
    ltype, lrole = ctx.element(R.LOAD, dom)
    net = A.move_node(net, rod, load, keep)
    net = A.add(net, rodm, ltype, {lrole.port("node"): rod}, {lrole.param("inertia"): 0.1 * m})
    mapping = {f"{rod}.{q}": f"{load}.{q}" for q in (dom.across, dom.position) if q}
    net = A.rewrite_outputs(net, mapping)
    net = _move_initial(net, rod, load)
    return A.set_initial(net, {f"{rod}.{q}": {"same_as": f"{load}.{q}"} for q in (dom.across, dom.position) if q})


def _rod_side(ctx: Context, rodm: str, dom: Domain, m: float) -> NewParam:
    """What moves WITH the rod, ahead of the link (piston, rod, a clevis, part of a boom or of
    an arm), is not known either: its mass or inertia is identified (log scale) with the link,
    as a mount's frame mass is: the rod side is what the oil accelerates before the link has
    wound up. Started at a tenth of the load, also tried at four tenths. (On the dev rotary
    cubic link with 35 % of the inertia ahead of it the fit kept it near its start, 0.096
    against 0.30 kg·m²: the cubic law, not this, closed that case.)"""
    _, lrole = ctx.element(R.LOAD, dom)
    return NewParam(f"{rodm}.{lrole.param('inertia')}", 0.1 * m, (0.01 * m, 2.0 * m), (0.01 * m, 2.0 * m),
                    0.1 * m, True, primary=False, shapes=(0.4 * m,))


def _link_damping(m: float) -> float:
    """A rod–load link's damping start: a fifth of critical for the rod side (a tenth of the
    load) on a rigid link (10⁷ s⁻² × the load)."""
    return 0.2 * (1e7 * 0.1 * m) ** 0.5


def _link_damper(name: str, m: float, probe_share: float) -> NewParam:
    """A rod–load link's damping (log scale, a companion) from :func:`_link_damping`, within
    1 … 10⁵ × √(m/100); the screening probe at ``probe_share`` of the start."""
    c0, s = _link_damping(m), (m / 100.0) ** 0.5
    return NewParam(name, c0, (1.0 * s, 1e5 * s), (1.0 * s, 1e5 * s), probe_share * c0, True, primary=False)


def _progressive(ctx: Context, act: Part, spring: str, srole) -> list[NewParam]:
    """The new spring's cubic hardening hc (the Duffing spring F = k·d·(1 + hc·(k·d)²/3), i.e.
    k₃ = hc·k³/3; a companion, log scale) fitted WITH the compliance: a rubber bushing or a
    clevis that firms up under load is not a linear spring softer on average, and fitted as
    one it may not be found at all (dev EHA cubic bushing, effect ESR 1.1 %: the linear mount
    gained nothing on the held-out run). hc·(k·d)² is the relative stiffening at the linear
    force k·d, independent of k, so the amount and the hardening stay separately determined.
    The cubic law, not the spring's hardening with the force carried (k·(1 + h·F²), equal to
    first order): that law stiffens without limit as the load grows, and a link fitted with
    it on a test's loads mispredicts a held-out run's larger ones (dev rotary cubic link,
    near-true start: train P1 0.24 %, validation 10.9 %). Started at a negligible
    hc·F₅₀² = 1e-6 (F₅₀ the actuator's force at 50 bar), with two shapes: a mild hardening
    (hc·F₅₀² = 1: the stiffness doubles if the linear spring alone carried F₅₀) and a bushing
    that is nearly free around zero and firm under load (hc·F₅₀² = 10⁴: at F₅₀ the cubic
    carries the load at 1/15 of the linear spring's deflection, ~45× stiffer than around
    zero), up to 10⁶. Measured on an EHA mount of held-out seed 49 (k 10⁵ N/m, k₃ 10¹¹ N/m³:
    hc·F₅₀² ≈ 3·10⁴; 0.9–1.5 % effect ESR): with hc·F₅₀² bounded at 10³ and started at 1, the
    fit went rigid and the answer was ``none``; with the wider bound and each shape's best start
    fitted (``basins``) it reaches k within 5 %, k₃ and the frame mass within 40 % of the truth
    (validation P1 1.05 → 0.30 %, noise 0.20 %). Which start found it was measured: the mild
    shape's best one; with the strong shape's alone the answer stays ``none``."""
    name = srole.param("cubic")
    if not name:
        return []
    f2 = (ctx.size(act) * 5e6) ** 2
    return [NewParam(f"{spring}.{name}", 1e-6 / f2, (1e-8 / f2, HC_MAX / f2), (1e-8 / f2, HC_MAX / f2), 1e-6 / f2, True,
                     primary=False, shapes=tuple(h / f2 for h in HC_SHAPES), basins=True)]


def _stiffness(name: str, m: float, probe: float, primary: bool = True) -> NewParam:
    """A compliance's stiffness (log scale, primary unless told), started rigid (10⁷ s⁻² × the
    load)."""
    lo, hi = K_PER_MASS
    return NewParam(name, 1e7 * m, (lo * m, hi * m), (lo * m, K_PER_MASS_PLAUSIBLE * m), probe, True,
                    primary=primary, grid=K_GRID)


def _probe_stiffness(mass: float) -> float:
    """The stiffness that puts ``mass`` (or an inertia) in a mode at ``PROBE_HZ``, where a link
    or a mount is visible: k = (2π·f)²·m."""
    return (2 * 3.14159 * PROBE_HZ) ** 2 * mass


def _inertia(ctx: Context, load: Part) -> float:
    try:
        return float(ctx.value(load.param("inertia")))
    except (KeyError, TypeError, ValueError):
        return 1.0


def _force_state(name: str, type_: str) -> str:
    """The state of a spring element (its force or torque): ``name.<state>``."""
    return f"{name}.{registry.get(type_).states[0].name}"


def _move_initial(net, old: str, new: str):
    """Initial position of the old node also for the new one (the coupling starts relaxed)."""
    init = net.doc.get("initial") or {}
    return A.set_initial(net, {f"{new}.{str(k).split('.', 1)[1]}": v for k, v in init.items()
                               if str(k).startswith(f"{old}.")})
