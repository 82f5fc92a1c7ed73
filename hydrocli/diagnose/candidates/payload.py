"""A payload hanging on the moved load, on a rotary drive or a cylinder (a load on a rope
from an arm: a harvester's head, a crane's hook seen from the slewing or luffing joint; a hook
load bouncing on the rope under a lifting cylinder).

Rotary: a payload of mass m_p on a rope of length L hanging at radius r from the joint, for small
swing angles, is a tangential spring–mass on the arm: the rope's restoring force
m_p·g·s/L on the tangential offset s = r·(φ − θ) gives, in the joint's coordinates, an inertia
J_p = m_p·r² coupled to the arm by a torsion spring k = m_p·g·r²/L = J_p·g/L (Meirovitch,
*Fundamentals of Vibrations* §6.2; seed 002 §4 treats the harvester head this way). Both J_p
(how much swings) and k (its frequency √(k/J_p) = √(g/L)) are identified, so neither r nor L
needs to be known; elements are the rotational load, spring and damper found by role. A boom-tip
mass on a flexible tip is the same spring–mass with a stiffer spring, and both lose energy (air,
the rope's or the tip's own damping): the damping is identified too, a companion started at 5 %
of critical, and the swing is tried at three frequencies (rope lengths 1 m, 10 cm, 1.5 cm: 0.5,
1.6 and 4 Hz), each a basin of its own (dev rotary boom-tip payload at 1.4 Hz, ζ ≈ 4 %: from
the 0.5 Hz start alone the fit let the spring go slack and nothing was found), and at the
frequencies where the base fit's residual spectra peak: a lightly damped swing is a narrow
basin (a rope payload swinging at 0.70 Hz, started at 0.5 Hz, fitted a 15 Hz spring).
That spring–mass is a mass on a flexible tip at every angle, and a rope only at the hanging
pose: an arm that carries a weight (it swings in a vertical plane) is also offered the exact
pendulum on its swinging tip (``_on_a_rope``, ``hanging_payload``), whose coupling falls as the
arm leaves the hanging pose and whose tension follows the tip's acceleration (session 45).

Translational: the payload m_p on a rope of stiffness k (its weight is already in the load's
force) bounces on the rope at √(k/m_p), or, on a luffing boom seen from its cylinder, swings at
√(g/L); either is a spring–mass–damper on the moved node, the same three identified parameters
and the same starts. (Until session 40 a cylinder's payload had its rope fixed at 0.5 Hz and
no damping: any other swing could not be found.)

A hook load under a drum (a winch: a rotary actuator without ends of travel) hangs on the rope
the drum pays out, whose stiffness EA/L grows as it is wound in: the rope's winding r/L₀ is a
companion (:func:`_winding`, ``shaft.wind``). The rope's sheaves carry dry friction on every
payload, as the rod–load link carries its joint's (``mechanics.dry_joint``).
"""
from __future__ import annotations

import math
from dataclasses import replace

from ...components import roles as R
from ...components.base import Domain
from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Part, Skipped
from .mechanics import dry_joint

G = 9.81
L_START = 1.0        # m: rope length of the start and probe values (frequency 0.5 Hz)
L_SHAPES = (0.1, 0.015)   # m: the other swings tried (1.6 and 4 Hz)
ZETA = 0.05          # damping ratio of the start values
#: Hz: the swings and bounces the residual's peak frequency is taken as a start for: a pendulum
#: on a rope of 50 m (√(g/L)/2π) up to a hook load bouncing on a short stiff rope (EA/L, not g/L:
#: a winch's 400 kg hook on a few metres of wire rope rings at 16–24 Hz; until session 40 the
#: ceiling was a 5 mm pendulum's 7 Hz, and such a bounce was out of the stiffness's bounds)
F_RANGE = ((G / 50.0) ** 0.5 / (2 * math.pi), 30.0)
K_MAX = 2.0 * (2 * math.pi * F_RANGE[1]) ** 2      # stiffness ceiling per unit of the load's mass or inertia
WIND_MAX = 0.5       # rad⁻¹: a drum's radius over the rope's length (``_winding``)
L_BOUNDS = (0.01, 50.0)   # m: a rope from an arm's tip (``_on_a_rope``): 5 Hz … 0.07 Hz
R_BOUNDS = (0.05, 20.0)   # m: the arm's radius to the rope
SWING_HZ = ((G / L_BOUNDS[1]) ** 0.5 / (2 * math.pi), (G / L_BOUNDS[0]) ** 0.5 / (2 * math.pi))


class PayloadFamily(Family):
    effects = ("payload_swing",)
    # a mode whose frequency moves with the rope's stiffness, as a compliant link's or mount's
    # does: a score test ranks them poorly against each other (a winch's hook bouncing at 19 Hz
    # screened 2.9 % beside a mount's 14 % and was never fitted; fitted, it explained as much),
    # so once one is shortlisted the others are fitted too (shortlist.GROUPS)
    compliances = frozenset({"payload_swing"})
    # an arm's payload in two forms (a mass on a flexible tip, a bob on a rope: ``_on_a_rope``):
    # a score test at one probe ranks the rope's parametric swing poorly against the
    # spring–mass (dev vane rope payload: not shortlisted, the spring–mass named at P2 3.21 →
    # 1.53 %, the rope fitted on top of it 1.53 → 0.041 %), so both are fitted (shortlist: LAWS)
    laws = frozenset({"payload_swing"})

    def candidates(self, ctx: Context):
        out = []
        for act in ctx.parts(R.ACTUATOR):
            node = act.node("motion")
            loads = ctx.parts_on(node, R.LOAD)
            if not loads:
                out.append(Skipped("payload_swing", f"no load (mass or inertia) on the moving node '{node}' of '{act.name}'"))
                continue
            out.extend(_payload(ctx, act, node, loads[0]))
        return out or [Skipped("payload_swing", "no actuator in the machine")]


def _payload(ctx: Context, act: Part, node: str, load: Part) -> list[Candidate]:
    J = _value(ctx, load.param("inertia"), 1.0)
    J_max = 2.0 * max(J, _ceiling(ctx, load.param("inertia")))
    dom = ctx.domain(node)
    ltype, lrole = ctx.element(R.LOAD, dom)
    stype, srole = ctx.element(R.SPRING, dom)
    dtype, drole = ctx.element(R.DAMPER, dom)
    swing = A.unique_name(ctx.net, f"{node}_payload")
    pj, rope, loss = (A.unique_name(ctx.net, n) for n in ("payload_inertia", "payload_rope", "payload_damper"))
    jp, kp, cp = f"{pj}.{lrole.param('inertia')}", f"{rope}.{srole.param('stiffness')}", f"{loss}.{drole.param('damping')}"
    j0 = 1e-3 * J
    k0, k_probe = j0 * G / L_START, 0.3 * J * G / L_START
    # a swing the residual shows: its frequency f is a start of its own, k = 0.3·J·(2πf)²
    # (0.07–30 Hz: F_RANGE)
    seen = tuple(f for f in ctx.residual_peaks_hz if F_RANGE[0] <= f <= F_RANGE[1])[:2]
    k_shapes = tuple(0.3 * J * G / L for L in L_SHAPES) + tuple(0.3 * J * (2 * math.pi * f) ** 2 for f in seen)

    def critical(k: float, j: float) -> float:
        return 2.0 * ZETA * (k * j) ** 0.5
    c0 = critical(k0, j0)
    params = [NewParam(jp, j0, (1e-4 * J, J_max), (0.02 * J, J_max), 0.3 * J, True),
              # k/J_p = g/L for a pendulum of 50 m and longer, up to a stiff rope's bounce (log
              # scale); a companion (shapes the swing)
              NewParam(kp, k0, (1e-4 * J * G / 50.0, K_MAX * J),
                       (1e-4 * J * G / 50.0, K_MAX * J), k_probe, True, primary=False,
                       shapes=k_shapes, basins=True),
              NewParam(cp, c0, (1e-6 * J, 1e3 * J), (1e-6 * J, 1e3 * J), critical(k_probe, 0.3 * J), True,
                       primary=False, shapes=tuple(critical(k, 0.3 * J) for k in k_shapes))]
    # an arm swinging in a vertical plane: what hangs from its tip on a rope swings in
    # gravity's frame, a mass on a flexible tip in the arm's; both are offered
    weight = _weight(ctx, node, dom)
    on_a_rope = [] if weight is None else [_on_a_rope(ctx, act, node, weight, J, params[0])]
    params += _winding(act, dom, rope, srole)
    # the rope's sheaves (a hook block reeved over them, a boom-tip sheave): dry friction that
    # grows with the tension damps the bounce by a fixed amount per cycle, not a fixed share —
    # the rod–load link carries its joint's dry friction alike (mechanics.dry_joint), so the
    # two readings of one two-mass mode are fitted with the same freedoms
    sheave_params, add_sheaves = dry_joint(ctx, act, dom, f"{swing}_sheaves")
    params += sheave_params

    def build(net):
        net = A.add(net, pj, ltype, {lrole.port("node"): swing}, {lrole.param("inertia"): j0})
        net = A.add(net, rope, stype, {srole.port("a"): node, srole.port("b"): swing}, {srole.param("stiffness"): k0})
        net = A.add(net, loss, dtype, {drole.port("a"): node, drole.port("b"): swing}, {drole.param("damping"): c0})
        net = add_sheaves(net, node, swing)
        return A.free_new(net, params)
    what = ("a payload swinging on a rope (or a flexible tip) from the arm of '{0}' (tangential spring–mass–damper)"
            if dom == Domain.ROTATIONAL else
            "a payload hanging on a rope (bouncing or swinging) from the load of '{0}' (spring–mass–damper)")
    return [Candidate("payload_swing", act.name, params, build, "force", what.format(act.name),
                      checks=(lambda est: _swing_outside(est[kp], est[jp]),))] + on_a_rope


def _weight(ctx: Context, node: str, dom: Domain) -> Part | None:
    """The weight (a gravity load offering its ``hanging`` angle) on a rotational ``node``: the
    arm swings in a vertical plane and what hangs from its tip swings in gravity's frame. None
    otherwise (a slewing joint, a drum, a cylinder)."""
    if dom != Domain.ROTATIONAL:
        return None
    return next((w for w in ctx.parts_on(node, R.WEIGHT, "node") if w.param("hanging") is not None), None)


def _on_a_rope(ctx: Context, act: Part, node: str, weight: Part, J: float, swing: NewParam) -> Candidate:
    """The payload of an arm that swings in a vertical plane: one ``hanging_payload`` element
    (:mod:`hydrocli.components.rotational.hanging`, the exact pendulum on a moving support) on
    the joint, hanging where ``weight`` (the arm's gravity load) hangs. Its inertia m_p·r² is
    the spring–mass's (same start, bounds and grid); the rope's length L takes the
    spring–mass's swing frequencies as its shapes (L = g/(2πf)², a basin each), the arm's
    radius r starts at twice the weight's lever g·J/W (a uniform arm's tip at
    1.5×) and the rope's damping at 5 % of critical. No sheaves: a rope from an arm's tip runs
    over none. Dev vane, rope payloads swinging at 0.7 Hz on an arm sweeping ±0.8 rad whose
    tip accelerates at up to 4 g: the spring–mass on the joint left P1 1.35 → 0.93 % and
    2.73 → 1.38 %, its coupling and tension fixed at the hanging pose's."""
    ptype, prole = ctx.element(R.PENDULUM, Domain.ROTATIONAL)
    el = A.unique_name(ctx.net, f"{node}_hanging_payload")
    jp, ln, rn, cn = (f"{el}.{prole.param(k)}" for k in ("inertia", "length", "radius", "damping"))
    W = _value(ctx, weight.param("weight"), 0.0)
    try:      # the angle at which the arm hangs straight down; left at its default (0) when not given
        theta0 = float(ctx.value(weight.param("hanging")))
    except (KeyError, TypeError, ValueError):
        theta0 = 0.0
    r0 = min(max(2.0 * G * J / W, R_BOUNDS[0]), R_BOUNDS[1]) if W > 0 else 1.0
    lengths = [G / (2 * math.pi * f) ** 2 for f in ctx.residual_peaks_hz if SWING_HZ[0] <= f <= SWING_HZ[1]][:2]
    l_shapes = tuple(min(max(x, L_BOUNDS[0]), L_BOUNDS[1]) for x in (*L_SHAPES, *lengths))

    def critical(j: float, length: float) -> float:
        return 2.0 * ZETA * (j * length ** 2 / r0 ** 2) * (G / length) ** 0.5
    j0 = swing.start
    params = [replace(swing, name=jp),
              NewParam(ln, L_START, L_BOUNDS, L_BOUNDS, L_START, True, primary=False, shapes=l_shapes, basins=True),
              NewParam(rn, r0, R_BOUNDS, R_BOUNDS, r0, True, primary=False),
              NewParam(cn, critical(j0, L_START), (0.0, 1e3 * J), (0.0, 1e3 * J), critical(swing.probe, L_START),
                       False, primary=False, shapes=tuple(critical(swing.probe, x) for x in l_shapes))]

    def build(net):
        net = A.add(net, el, ptype, {prole.port("node"): node},
                    {prole.param("inertia"): j0, prole.param("length"): L_START, prole.param("radius"): r0,
                     prole.param("damping"): critical(j0, L_START), prole.param("hanging"): theta0})
        return A.free_new(net, params)
    return Candidate("payload_swing", act.name, params, build, "force",
                     f"a payload on a rope from the arm of '{act.name}' (the exact pendulum on the swinging arm)",
                     fixed={f"{el}.{prole.param('hanging')}": theta0}, variant="rope")


def _value(ctx: Context, name: str | None, default: float) -> float:
    try:
        return abs(float(ctx.value(name))) if name else default
    except (KeyError, TypeError, ValueError):
        return default


def _winding(act: Part, dom: Domain, rope: str, srole) -> list[NewParam]:
    """The rope's winding on a drum (``Shaft.wind`` = r/L₀, a companion started at 0, signed):
    a rotary actuator without ends of travel (a motor, no stop slots) turns a drum, and what
    hangs from the drum hangs on the rope it pays out — stiffness EA/L with L = L₀ − r·θ, so
    the bounce stiffens as the load is hoisted (a steel rope's axial stiffness, not a
    pendulum's g/L). A shaft, a gearbox or a mount keeps its stiffness at every angle:
    this is what a hook load has and the two-mass readings of the same mode do not. Bounds
    ±0.5 rad⁻¹: a 0.5 m drum on a 1 m rope to the longest ropes (0 at the start)."""
    name = srole.param("winding")
    if dom != Domain.ROTATIONAL or not name or act.param("stop_min") is not None:
        return []
    return [NewParam(f"{rope}.{name}", 0.0, (-WIND_MAX, WIND_MAX), (-WIND_MAX, WIND_MAX), 0.0, False, primary=False)]


def _swing_outside(k: float, j: float) -> str | None:
    """Why a fitted payload is no payload: its swing √(k/J)/2π outside ``F_RANGE`` (a 50 m
    pendulum to a stiff rope's bounce), or None. Each bound alone allows a far slower pair: dev
    winch, a shear-thinning viscous drag (3.0 %) answered by a 105 kg·m² "payload" on
    0.36 N·m/rad, a 0.009 Hz swing (a 3 km pendulum) standing in for a slow drag."""
    f = (k / j) ** 0.5 / (2 * math.pi) if k > 0 and j > 0 else 0.0
    if F_RANGE[0] <= f <= F_RANGE[1]:
        return None
    return (f"its swing at {f:.2g} Hz is outside a rope's {F_RANGE[0]:.2g}–{F_RANGE[1]:.0f} Hz "
            "(a 50 m pendulum to a stiff rope's bounce)")


def _ceiling(ctx: Context, name: str | None) -> float:
    """The upper bound the machine file gives the load's mass or inertia when it is free, else
    0. A base fit without the payload lowers the rigid load to what moves with the rod at the
    swing's frequency: a hook load 0.85 of what a lift carries left 500 kg of 1.5 t (its lower
    bound), and a payload bounded at twice that ended at its bound. What hangs may weigh as
    much as the file lets the load weigh."""
    if name is None or name not in ctx.free:
        return 0.0
    comp, _, p = name.rpartition(".")
    b = ctx.net.components[comp].params[p].bounds
    return float(b[1]) if b else 0.0
