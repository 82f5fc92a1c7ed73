"""The candidate catalogue's plug-in interface (pysindy-style: this base module plus one
small module per family of effects).

A :class:`Candidate` is a named netlist augmentation: the effect (a name from DESIGN.md's
vocabulary), the component it attaches to, its new parameters (start value = effect off or
negligible, identification bounds, plausibility range, a probe value for the screening
signature) and ``build(net) -> net`` that returns the machine with the effect modelled and
its parameters free. Families find where an effect can attach by the ROLES components offer
(:mod:`hydrocli.components.roles`: an actuator's chambers and moving node, a metering valve's
work ports, a load on a node) and by graph connections — never by type name — so the
catalogue works for any machine of the library, translational or rotary.

The screening SIGNATURE of a candidate is computed by :mod:`hydrocli.diagnose.screen` from
the augmented model itself: the secant sensitivity of the outputs (and of the balance
equations) to the new parameters between ``start`` and ``probe`` — a Lagrange-multiplier
(score) test of the effect (Rao 1948; Engle 1984, *Handbook of Econometrics* II ch. 13).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from ...components import registry
from ...components.base import Domain
from ...components.roles import Role
from ...netlist.model import Netlist
from .. import augment as A

VOCABULARY = ("internal_leakage", "external_leakage", "viscous_friction", "coulomb_friction",
              "stribeck_friction", "pressure_dependent_friction", "entrained_air", "line_dynamics",
              "valve_overlap", "valve_hysteresis", "valve_asymmetry", "input_delay", "load_compliance",
              "structural_flexibility", "payload_swing", "end_stop", "supply_pressure_drop", "sensor_lag")


@dataclass(frozen=True)
class NewParam:
    name: str                              # model parameter name after augmentation
    start: float                           # effect off (or negligible)
    bounds: tuple[float, float]            # identification bounds (SI)
    plausible: tuple[float, float]         # physically plausible |value − ref| range for acceptance
    probe: float                           # value of the screening secant
    log: bool | None = None
    primary: bool = True                   # False: a companion parameter (acceptance looks at primaries)
    ref: float = 0.0                       # value meaning "no effect": plausibility is judged on |value − ref|
    scale: float = 0.0                     # > 0: a position-like parameter with no "off" value (a stop):
                                           # ``plausible`` bounds the value itself and the standard error
                                           # is judged against this length (the stroke seen), not |value − ref|
    reach: tuple[float, float] = ()        # a stop's: the positions recorded (± margin). Fitted outside
                                           # them it is not engaged: only bounded from one side, its
                                           # standard error is no test of the effect (accept.judge)
    seen: tuple[float, float] = ()         # a stop's: the positions recorded (min, max). A stop fitted
                                           # beyond them is pressed by nothing in training: the fit
                                           # withdraws it to its outer bound (workers.withdraw_idle_stops)
    grid: int = 4                          # how many geometric starts span the plausible range (a primary
                                           # whose "off" value is 0; workers._log_grid): a range of many
                                           # decades declares more, so neighbouring starts stay close
    shapes: tuple[float, ...] = ()         # a companion's other typical values: the fit's grid of starts
                                           # (workers._log_grid) is crossed with them (the k-th value of
                                           # every companion together), so an amount is tried with each
                                           # shape (a hose's length with each common bore)
    basins: bool = False                   # each of its shapes is a basin of its own (a spring's mild or
                                           # strong hardening): the fit also runs from the best start of
                                           # each shape (workers._fit_starts), not only from the best start
    takes_over: tuple = ()                 # (base parameter, its "off" value, power): a law that can hold
                                           # what that base parameter holds (a seal's resistance, the base's
                                           # shared leak conductance: power −1). The fit also starts from the
                                           # base re-expressed in this law (workers._transfer_starts)
    limits: bool = False                   # a companion whose bounds are its law's limiting forms, each a
                                           # law of its own (a restriction's sharp-orifice and fully laminar
                                           # laws, air's isothermal and adiabatic exponents): a fit that ends
                                           # on one names the form, it has not pushed a value out of reach


@dataclass
class Candidate:
    effect: str
    component: str
    params: list[NewParam]
    build: Callable[[Netlist], Netlist]    # machine (with fitted base values) → augmented machine
    equation: str                          # balance it acts in: force | continuity | valve | signal | measurement
    description: str
    fixed: dict[str, float] = field(default_factory=dict)   # extra non-free values it sets
    variant: str = ""                      # several physical forms of one effect on one component
    # plausibility of what the parameters make together (a payload's swing frequency √(k/J)):
    # each check maps the fitted {name: value} to why they are implausible, or None
    checks: tuple[Callable[[dict[str, float]], str | None], ...] = ()
    # the one mode a compliance adds, as the names of its (stiffness, damping, mass): its damping
    # ratio tells a mode from a creep (:meth:`damping_ratio`)
    mode: tuple[str, str, str] | None = None

    @property
    def key(self) -> str:
        return f"{self.effect}@{self.component}" + (f"#{self.variant}" if self.variant else "")

    def damping_ratio(self, est: dict[str, float]) -> float | None:
        """ζ = c / (2·√(k·m)) of the mode (:attr:`mode`) at the fitted values ``est``, or None
        when the candidate declares none or a value is missing or not positive. With the mass
        ahead of the spring alone (a rod–load link's rod side, not the reduced mass with the
        load) the ratio is a lower bound."""
        if self.mode is None:
            return None
        k, c, m = (est.get(n) for n in self.mode)
        if not all(v is not None and v > 0 for v in (k, c, m)):
            return None
        return float(c / (2.0 * (k * m) ** 0.5))


@dataclass
class Skipped:
    effect: str
    reason: str


@dataclass
class Context:
    """What families may look at: the machine, and position ranges seen in the data."""

    net: Netlist
    free: set[str]                                          # parameters free in the base model
    position_range: dict[str, tuple[float, float]] = field(default_factory=dict)  # node → (min, max) m
    outputs: dict[str, str] = field(default_factory=dict)   # output → quantity ("pressure", "position", …)
    inputs_start: dict[str, float] = field(default_factory=dict)  # input → first sample (mean over training)
    position_censored: dict[str, tuple[bool, bool]] = field(default_factory=dict)  # node → (min, max) hidden
                                                            # by the recording's mask (a clipping sensor)
    residual_peaks_hz: tuple[float, ...] = ()               # where the base fit's residual spectra peak
                                                            # (locate.residual_peaks): a mode it lacks
    recorded_range: dict[str, tuple[float, float]] = field(default_factory=dict)  # node → (min, max) m over
                                                            # every recording, training and held-out: a stop
                                                            # the training never pressed is withdrawn beyond it
    drawn: Netlist | None = None                            # the machine as drawn (the file's values): what a
                                                            # law takes a geometry from that the base fit may
                                                            # have bent to stand in for the law itself

    def parts(self, role: str) -> list["Part"]:
        """Every component of the machine that offers ``role``, in file order."""
        out = []
        for n, c in self.net.components.items():
            cls = registry.get(c.type)
            r = cls.role(role) if cls is not None else None
            if r is not None:
                out.append(Part(n, c.type, r, dict(c.ports)))
        return out

    def parts_on(self, node: str | None, role: str, slot: str | None = None) -> list["Part"]:
        """Components offering ``role`` connected to ``node`` (through the role's ``slot``
        port when given)."""
        if node is None:
            return []
        return [p for p in self.parts(role) if (p.node(slot) == node if slot else node in p.ports.values())]

    def size(self, act: "Part") -> float:
        """An actuator's size (its role's ``size``: area, or displacement per radian); 1e-3
        when it cannot be read."""
        name = act.param("size")
        try:
            return abs(self.value(name)) if name else 1e-3
        except (KeyError, TypeError, ValueError):
            return 1e-3

    def domain(self, node: str) -> Domain | None:
        for comp, port in self.on_node(node):
            spec = registry.get(self.net.components[comp].type)
            ps = spec.port(port) if spec is not None else None
            if ps is not None:
                return ps.domain
        return None

    @staticmethod
    def element(role: str, domain: Domain, slot: str | None = None) -> tuple[str, Role]:
        """The library type offering ``role`` on ``domain`` (a spring for a translational
        node, a shaft for a rotational one) at its ``a`` or ``node`` slot, or at ``slot`` when
        given (a band leak whose ``motion`` reads a rod or a shaft): (type name, its role)."""
        for t, cls in registry.offering(role).items():
            r = cls.role(role)
            slot_port = r.port(slot) if slot else (r.port("a") or r.port("node"))
            ps = cls.port(slot_port) if slot_port else None
            if ps is not None and ps.domain == domain:
                return t, r
        raise KeyError(f"no component type offers '{role}' on a {domain.value} node")

    def on_travel(self, act: "Part", role: str) -> tuple[str, str, tuple[float, float], str, Role] | None:
        """What an element that READS an actuator's travel needs (a leak over a band of it, a
        cushion at its end): the actuator's motion and reference nodes, the travel seen, and the
        library type offering ``role`` with its ``motion`` slot on that node's domain (a rod or
        a shaft). None without a reference, a travel seen, or such a type."""
        node, ref = act.node("motion"), act.node("reference")
        rng = self.position_range.get(node)
        if rng is None or ref is None:
            return None
        try:
            typ, r = self.element(role, self.domain(node), slot="motion")
        except KeyError:
            return None
        return node, ref, rng, typ, r

    def drawn_value(self, name: str) -> float:
        """The file's value of model parameter ``name`` (the current one when no drawing is known)."""
        return _value_in(self.net if self.drawn is None else self.drawn, name)

    def on_node(self, node: str) -> list[tuple[str, str]]:
        return self.net.nodes().get(node, [])

    def value(self, name: str) -> float:
        return _value_in(self.net, name)


def _value_in(net: Netlist, name: str) -> float:
    """Model parameter ``name`` (``component.param``) as ``net`` sets it, SI."""
    comp, _, p = name.rpartition(".")
    return float(net.components[comp].params[p].value)


@dataclass(frozen=True)
class Part:
    """A component of the machine in one of its roles: names of its nodes and parameters by
    the role's slots."""

    name: str
    type: str
    role: Role
    ports: dict[str, str]            # the component's port → node

    def node(self, slot: str) -> str | None:
        port = self.role.port(slot)
        return self.ports.get(port) if port else None

    def param(self, slot: str) -> str | None:
        """Full model name (``comp.param``) of the first parameter filling ``slot``."""
        p = self.role.param(slot)
        return f"{self.name}.{p}" if p else None

    def params(self, slot: str) -> list[str]:
        return [f"{self.name}.{p}" for p in self.role.params_of(slot)]

    def richer_type(self, slot: str) -> str | None:
        """The library type that derives from this part's type and offers its role on the same
        ports with ``slot`` as well (``valve_4_3`` → ``valve_4_3_edges``, ``friction`` →
        ``friction_lugre``): an effect the part's own type has no term for, reached by
        :func:`augment.set_type`. None when the part offers ``slot`` already or no type does."""
        if self.role.params_of(slot):
            return None
        mine = registry.get(self.type)
        return next((t for t, cls in registry.offering(self.role.name).items()
                     if cls.role(self.role.name).params_of(slot) and cls.role(self.role.name).ports == self.role.ports
                     and issubclass(cls, mine)), None)


class Family:
    """A family of effects: ``candidates(ctx)`` and ``skipped(ctx)`` (effects it covers but
    cannot attach anywhere in this machine, each with a reason)."""

    effects: tuple[str, ...] = ()
    # traits the engine reads (declared here, by the family that models the effect, so a new
    # candidate module needs no edit elsewhere):
    switching: frozenset[str] = frozenset()     # effects whose law switches (sign, contact, band):
                                                # fitted on both Jacobians (engine)
    compliances: frozenset[str] = frozenset()   # effects that add a compliance (a mode whose
                                                # frequency moves with its stiffness): once one is
                                                # shortlisted the others are fitted too (engine.shortlist)
    lags: frozenset[str] = frozenset()          # effects that retard the response to a command (a
                                                # delay, a play, a slow reading): likewise
    bands: frozenset[str] = frozenset()         # dead bands of one element (a spool's overlap around
                                                # centre, its play around the last reversal): likewise
    laws: frozenset[str] = frozenset()          # effects offered in more than one LAW of one flow
                                                # (a leak: laminar or orifice): once the effect is
                                                # shortlisted every significant law is fitted, not
                                                # only the best-screening one (engine.shortlist)
    frictions: frozenset[str] = frozenset()     # effects that add a force following the speed of a
                                                # sliding contact (viscous, dry with its reversal band,
                                                # a breakaway, a seal): what an OVERDAMPED compliance
                                                # stands for, fitted next to it (engine.round_step)
    reduces_to: tuple[tuple[str, str], ...] = ()  # (richer, simpler): the richer law becomes the
                                                # simpler one where the data do not exercise what it
                                                # adds; when the data do not tell them apart the
                                                # simpler one is named (ranking.simplest)

    def candidates(self, ctx: Context) -> list[Candidate]:  # pragma: no cover - abstract
        raise NotImplementedError

    def parameter_candidate(self, ctx: Context, effect: str, comp: str, params: list[NewParam], equation: str,
                            description: str, fixed: dict[str, float] | None = None,
                            connect: dict[str, str] | None = None, variant: str = "") -> Candidate | Skipped:
        """An effect that is an existing parameter of the component: set it free from its
        start value (and connect sensing ports); skipped when already free in the base."""
        already = [p.name for p in params if p.name in ctx.free]
        if already:
            return Skipped(effect, f"{', '.join(already)} already free in the base model of '{comp}'")

        def build(net, params=params, fixed=dict(fixed or {}), connect=dict(connect or {})):
            for port, node in connect.items():
                net = A.connect(net, comp, port, node)
            if fixed:
                net = A.set_values(net, fixed)
            return A.free_new(net, params)
        return Candidate(effect, comp, params, build, equation, description, dict(fixed or {}), variant)


def split(items) -> tuple[list[Candidate], list[Skipped]]:
    cands = [c for c in items if isinstance(c, Candidate)]
    return cands, [s for s in items if isinstance(s, Skipped)]
