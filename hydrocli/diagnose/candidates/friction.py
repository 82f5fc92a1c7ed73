"""Friction effects on the moving node of every ACTUATOR, translational or rotary (seed 004
eqs. 9–11: viscous k_v, Coulomb k_c, Stribeck k_s·e^(−|v|/v_s); seed 000 eq. 23: seal
friction proportional to the chamber pressures, μ_p·A_p·(p_A + p_B); seed 001 §2 for vane
seals). The friction element is found by its FRICTION role on the moving node; when there is
none, one of the node's domain is added (a ``friction`` on a rod, a ``rotary_friction`` on a
shaft)."""
from __future__ import annotations

from ...components import registry
from ...components import roles as R
from .. import augment as A
from .base import Candidate, Context, Family, NewParam, Part, Skipped

SEAL_PRESSURE = 2e5   # Pa: a seal force of 2 bar on the actuator's size is the plausible scale
REF_SEAL_FORCE = 2e5 * 2.0994e-3   # N: that force on seed 004's bench, where the scales were set
# Coulomb friction does not reverse at one speed: a seal deflects before it slides (pre-sliding),
# so the force turns over a band of speeds that the element's smoothing ``band`` stands for. A
# Coulomb candidate frees the band as a companion, from the file's value (no change) up to
# BAND_RANGE times it (translational 1e-4 → 10 mm/s, rotary 1e-3 → 0.1 rad/s). Dev rotary with a
# band 40× the file's: Coulomb named, validation P1 left at 0.29–0.67 % against noise 0.06–0.15 %
# (with the band free: 0.06–0.16 %).
BAND_RANGE = 100.0
DECAY_RANGE = 30.0   # the Stribeck speed's range either way of the machine's value (companion, log scale)

_FORMS = {
    "viscous_friction": ("viscous", "viscous friction k_v·v"),
    "coulomb_friction": ("coulomb", "Coulomb friction k_c·sign(v)"),
    "stribeck_friction": ("stribeck", "breakaway excess k_s·e^(−|v|/v_s)·sign(v) at low speed"),
}


class FrictionFamily(Family):
    effects = ("viscous_friction", "coulomb_friction", "stribeck_friction", "pressure_dependent_friction")
    switching = frozenset({"coulomb_friction", "stribeck_friction", "pressure_dependent_friction"})
    frictions = frozenset(effects)
    # a seal force μ·A·(p_A + p_B) is a constant force wherever the pressure sum is (a symmetric
    # actuator on a constant supply: p_A + p_B ≈ p_S), and a breakaway excess k_s·e^(−|v|/v_s)
    # is one for v_s above the speeds recorded: each is Coulomb friction with one more
    # dependence, which only data that vary that pressure or speed can show
    reduces_to = (("pressure_dependent_friction", "coulomb_friction"), ("stribeck_friction", "coulomb_friction"))
    # seals loaded by both chambers (the sum) and a piston seal loaded by the difference are two
    # laws of one effect; which one, like which effect, is for the fits (dev EHA piston seal:
    # the sum screened 38 % and was fitted alone, to μ ≈ 0; the difference law was never fitted)
    # a breakaway is offered static (the element's own law) and with the contact's pre-sliding
    # spring (LuGre bristles, :func:`_bristles`): a dev EHA LuGre breakaway (2.2 %) was named
    # a rod–load link, whose spring and joint friction are the nearest the static law had
    laws = frozenset({"pressure_dependent_friction", "stribeck_friction"})

    def candidates(self, ctx: Context):
        out = []
        acts = ctx.parts(R.ACTUATOR)
        if not acts:
            return [Skipped(e, "no actuator to attach friction to") for e in self.effects]
        for act in acts:
            node = act.node("motion")
            fmax = SEAL_PRESSURE * ctx.size(act)
            fr = next((f for f in ctx.parts_on(node, R.FRICTION, "a")), None)
            if fr is None:
                out.extend(self._new_friction(ctx, act, node, fmax))
            else:
                out.extend(self._existing(ctx, fr, act, fmax))
        return out

    def _existing(self, ctx: Context, fr: Part, act: Part, fmax: float):
        out = []
        for effect, (slot, desc) in _FORMS.items():
            names = fr.params(slot)
            if not names:
                out.append(Skipped(effect, f"'{fr.name}' ({fr.type}) has no {slot} term"))
                continue
            law = _law(effect, names, fmax) + _shape(ctx, fr, effect)
            out.append(self.parameter_candidate(ctx, effect, fr.name, law, "force", desc))
            if effect == "stribeck_friction" and not any(n in ctx.free for n in names):
                out.extend(_bristles(ctx, fr, law, fmax))
        out.extend(self._pressure(ctx, fr, act, fmax))
        return out

    def _pressure(self, ctx: Context, fr: Part, act: Part, fmax: float):
        out = []
        area = ctx.size(act)
        mu = fr.param("pressure")
        if mu is not None and fr.role.port("pressure_a"):
            connect = {fr.role.port("pressure_a"): act.node("chamber_a"), fr.role.port("pressure_b"): act.node("chamber_b")}
            # the seals' reversal band is the contact's, as for the seal element's laws (_seal)
            out.append(self.parameter_candidate(
                ctx, "pressure_dependent_friction", fr.name,
                [NewParam(mu, 1e-4, (0.0, 0.2), (2e-3, 0.2), 0.02)] + _band(ctx, fr),
                "force", "seal friction growing with chamber pressure, μ_p·A·(p_A + p_B)·sign(v)",
                fixed={fr.param("pressure_size"): area}, connect=connect))
        out.extend(_seal(ctx, fr.name, act, area, _file_value(ctx, fr, fr.param("band"))))
        return out

    def _new_friction(self, ctx: Context, act: Part, node: str, fmax: float):
        """No friction element yet: each friction effect adds one of the node's domain."""
        dom = ctx.domain(node)
        try:
            typ, role = ctx.element(R.FRICTION, dom)
        except KeyError as exc:
            return [Skipped(e, str(exc)) for e in self.effects]
        fr = A.unique_name(ctx.net, f"{act.name}_friction")
        ref = act.node("reference") or "ground"
        area = ctx.size(act)
        out = []

        def adder(params, fixed=None, pressures=False):
            def build(net):
                ports = {role.port("a"): node, role.port("b"): ref}
                if pressures:
                    ports.update({role.port("pressure_a"): act.node("chamber_a"),
                                  role.port("pressure_b"): act.node("chamber_b")})
                net = A.add(net, fr, typ, ports, dict(fixed or {}))
                return A.free_new(net, params)
            return build
        for effect, (slot, desc) in _FORMS.items():
            names = [f"{fr}.{p}" for p in role.params_of(slot)]
            if names:
                ps = _law(effect, names, fmax) + _shape(ctx, Part(fr, typ, role, {}), effect)
                out.append(Candidate(effect, act.name, ps, adder(ps), "force", f"{desc} on '{node}'"))
        mu = role.param("pressure")
        if mu and role.port("pressure_a"):
            ps = [NewParam(f"{fr}.{mu}", 1e-4, (0.0, 0.2), (2e-3, 0.2), 0.02)]
            out.append(Candidate("pressure_dependent_friction", act.name, ps,
                                 adder(ps, {role.param("pressure_size"): area}, True), "force",
                                 f"seal friction growing with chamber pressure on '{node}'"))
        else:
            out.extend(_seal(ctx, fr, act, area))
        return out


def _law(effect: str, names: list[str], fmax: float) -> list[NewParam]:
    """The same law for both directions of motion when the element has two names."""
    s = fmax / REF_SEAL_FORCE
    if effect == "viscous_friction":
        # coefficients scaled like the seal force (on the EHA bench: start 10 N·s/m, probe 5e3)
        return [NewParam(n, 10.0 * s, (0.0, 1e6 * s), (1.0 * s, 1e6 * s), 5e3 * s) for n in names]
    return [NewParam(n, 1.0 * s, (0.0, 20 * fmax), (0.01 * fmax, 20 * fmax), fmax) for n in names]


def _shape(ctx: Context, fr: Part, effect: str) -> list[NewParam]:
    """The companions that shape a friction law: the speed band over which Coulomb friction
    reverses (:func:`_band`), the speed over which a breakaway excess decays (:func:`_decay`)."""
    return _band(ctx, fr) if effect == "coulomb_friction" else _decay(ctx, fr) if effect == "stribeck_friction" else []


def _band(ctx: Context, fr: Part) -> list[NewParam]:
    """The speed band over which the Coulomb force reverses, as a companion (log scale) started
    at its value in the machine (or the type's default), up to ``BAND_RANGE`` times it; none
    when the element has no band or the base model already fits it."""
    name = fr.param("band")
    v = _file_value(ctx, fr, name)
    if v is None:
        return []
    return [_widening(name, v)]


def _widening(name: str, v: float) -> NewParam:
    """A reversal band ``name`` as a companion started at ``v`` (log scale): its bounds reach
    below ``v`` (a start strictly inside them), judged as a widening, |band − v| from once ``v``
    up to ``BAND_RANGE`` times it (ended at the top: an implausibly wide band)."""
    return NewParam(name, v, (0.5 * v, BAND_RANGE * v), (v, BAND_RANGE * v), v, True, primary=False, ref=v,
                    shapes=(0.1 * BAND_RANGE * v,))


def _decay(ctx: Context, fr: Part) -> list[NewParam]:
    """The Stribeck speed v_s of k_s·e^(−|v|/v_s) as companions (log scale, each direction's),
    from the machine's value (or the type's default) over ``DECAY_RANGE`` either way. How fast
    the breakaway excess fades is a property of the seal and the oil, not of the element's
    default; held at a default 5× too slow the excess is a different law (dev rotary with a
    Gaussian breakaway over 0.05 rad/s: named, held-out P1 12.2 → 10.1 % with v_s held, → 8.78 %
    with it fitted, against a noise of 0.05 %: that case's stick–slip cycles are out of any
    output-error fit's reach, docs/diagnose.md § Session 37)."""
    out = []
    for name in fr.params("stribeck_speed"):
        v = _file_value(ctx, fr, name)
        if v is not None:
            out.append(NewParam(name, v, (v / DECAY_RANGE, DECAY_RANGE * v), (v / DECAY_RANGE, DECAY_RANGE * v), v,
                                True, primary=False, shapes=(0.2 * DECAY_RANGE * v,)))
    return out


def _bristles(ctx: Context, fr: Part, law: list[NewParam], fmax: float) -> list[Candidate]:
    """The breakaway with the contact's pre-sliding spring: the friction element turned into the
    library type that offers the same FRICTION role with ``bristle_stiffness`` (``friction`` →
    ``friction_lugre``, Canudas de Wit et al. 1995), the static law's parameters ``law`` free as
    in the static candidate, the bristle stiffness σ0 and damping σ1 as companions (log scale):
    σ0 from a pre-sliding deflection fmax/σ0 of 1 mm down to 0.1 µm, started at 10 µm; σ1 over
    six decades, started at fmax per 0.4 m/s (1 kN·s/m on seed 004's bench). Empty when the
    element has bristles already or no such type exists (:meth:`Part.richer_type`)."""
    target = fr.richer_type("bristle_stiffness")
    if target is None:
        return []
    role = registry.get(target).role(R.FRICTION)
    s0, s1 = (f"{fr.name}.{role.param(k)}" for k in ("bristle_stiffness", "bristle_damping"))
    damping = 2.5 * fmax
    params = law + [NewParam(s0, fmax / 1e-5, (fmax / 1e-3, fmax / 1e-7), (fmax / 1e-3, fmax / 1e-7), fmax / 1e-5,
                             True, primary=False, shapes=(fmax / 1e-6,)),
                    NewParam(s1, damping, (1e-3 * damping, 1e3 * damping), (1e-3 * damping, 1e3 * damping), damping,
                             True, primary=False)]

    def build(net):
        return A.free_new(A.set_type(net, fr.name, target), params)
    return [Candidate("stribeck_friction", fr.name, params, build, "force",
                      "breakaway excess k_s·e^(−|v|/v_s) with the contact's pre-sliding spring "
                      "(LuGre bristles: dz/dt = v − σ0·|v|·z/g(v), F = σ0·z + σ1·dz/dt)", variant="bristles")]


def _file_value(ctx: Context, fr: Part, name: str | None) -> float | None:
    """A parameter's value in the machine (or its type's default) when the base does not fit
    it already and it is positive; else None."""
    if name is None or name in ctx.free:
        return None
    try:
        v = ctx.value(name)
    except (KeyError, TypeError, ValueError):
        spec = registry.get(fr.type).param(name.rpartition(".")[2])
        v = spec.default if spec is not None else None
    return float(v) if v and v > 0 else None


def _seal(ctx: Context, owner: str, act: Part, area: float, band: float | None = None) -> list:
    """Seal friction loaded by the pressure DIFFERENCE across the piston seal (the
    ``seal_friction`` element), and on a single-rod cylinder a rod seal loaded by the rod side
    alone. A vane actuator's seals (``rotary_seal_friction``, on its displacement per radian)
    get the difference and the sum: its friction element has no pressure term, so the seals
    loaded by both chambers (μ_s·D·(p_A + p_B)) are offered here too.

    The speed band ε over which the seal's force reverses (tanh(v/ε)) is a companion, as the
    Coulomb law's band is (:func:`_widening`): started at the machine friction's band (``band``, or
    the element's default), up to ``BAND_RANGE`` times it. A loaded seal that reverses over
    0.02 rad/s acts as a stiff damper under the dither at standstill; held at 1 mrad/s it is a
    hard stick (dev winch, a piston seal at ε 0.02 rad/s: the seal law closed 20 % of the gap,
    an implausible breakaway more)."""
    rod = act.node("motion")
    dom = ctx.domain(rod)
    if dom is None or dom.value not in ("translational", "rotational"):
        return [Skipped("pressure_dependent_friction", f"no pressure-loaded seal law for '{act.name}'")]
    rotary = dom.value == "rotational"
    typ, size = ("rotary_seal_friction", "D_p") if rotary else ("seal_friction", "A_p")
    name = A.unique_name(ctx.net, f"{act.name}_seal_friction")
    body = act.node("reference") or "ground"
    laws = [(("mu_d",), 1.0, "dp", "piston-seal friction growing with the pressure difference, μ_d·{s}·|p_A − p_B|")]
    if rotary:
        laws.append((("mu_s",), 0.2, "sum", "vane-seal friction growing with the chamber pressures, μ_s·{s}·(p_A + p_B)"))
        # the hub seals on each chamber's side, each pressed by its own chamber: unequal seals
        # (or one side's worn) are neither the sum nor the difference law (held-out seed 76's
        # vane, a seal pressed by one chamber, 2.24 %: both laws fitted, neither passed, `none`)
        laws.append((("mu_a", "mu_b"), 1.0, "sides", "hub-seal friction, each side pressed by its own chamber, "
                                                     "(μ_a·p_A + μ_b·p_B)·{s}"))
    elif len(act.params("displacements")) == 2:
        # a single-rod cylinder's rod seal is pressed by the rod side alone (the other side of
        # it is the atmosphere): neither the sum nor the difference law (held-out seed 73's
        # lift rod seal, 4.15 %, was named a hose)
        laws.append((("mu_b",), 1.0, "rod", "rod-seal friction growing with the rod-side pressure, μ_b·{s}·p_B"))
    reversal = _widening(f"{name}.eps", band or registry.get(typ).param("eps").default)
    out = []
    for mus, top, variant, text in laws:
        prms = [NewParam(f"{name}.{mu}", 1e-4, (0.0, top), (2e-3, top), 0.02 if mu == "mu_s" else 0.05)
                for mu in mus] + [reversal]

        def build(net, prms=prms):
            net = A.add(net, name, typ, {"a": rod, "b": body, "pa": act.node("chamber_a"),
                                         "pb": act.node("chamber_b")}, {size: area})
            return A.free_new(net, prms)
        out.append(Candidate("pressure_dependent_friction", owner, prms, build, "force",
                             text.format(s="D" if rotary else "A") + "·sign(v)", variant=variant))
    return out
