"""The view a component gets of the model while it writes its equations.

Everything a component contributes goes through these calls ("stamps"): flows/forces it
draws from its nodes (``through``), capacitance it adds to a node (``capacitance``: a
volume's V/β, a mass, an inertia), across values it imposes (``impose``: a pressure or
velocity source), its own states and their derivatives, named intermediate variables,
and guards that stop the solver with a message. The :class:`Assembly` gathers the
stamps; the builder turns them into node equations.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..components.base import Component, Domain
from ..graph.linear import REFERENCE_NODES
from . import expr as E


@dataclass
class NodeInfo:
    name: str
    domain: Domain
    ports: list[tuple[str, str]] = field(default_factory=list)   # (component, port)
    through: list[tuple[str, E.Expr]] = field(default_factory=list)  # (component, expr into component)
    capacitance: list[tuple[str, E.Expr]] = field(default_factory=list)
    imposed: list[tuple[str, E.Expr, E.Expr | None]] = field(default_factory=list)  # (comp, across, position)

    @property
    def is_reference(self) -> bool:
        return self.name in REFERENCE_NODES


def across_name(node: str, domain: Domain) -> str:
    return f"{node}.{domain.across}" if domain != Domain.SIGNAL else node


def rate_name(node: str, domain: Domain) -> str:
    return f"{node}.{domain.across}_rate"


def position_name(node: str, domain: Domain) -> str:
    return f"{node}.{domain.position}"


@dataclass
class Assembly:
    """Everything the components stamped; read by the builder."""

    nodes: dict[str, NodeInfo] = field(default_factory=dict)
    states: dict[str, tuple] = field(default_factory=dict)   # name → (unit, initial, nominal, description)
    derivatives: dict[str, E.Expr] = field(default_factory=dict)
    variables: dict[str, E.Expr] = field(default_factory=dict)
    variable_units: dict[str, str] = field(default_factory=dict)
    guards: list[tuple[E.Expr, str]] = field(default_factory=list)
    rest: dict[str, E.Expr] = field(default_factory=dict)    # state → what it equals at rest (a sensor's reading)
    params: dict[str, tuple] = field(default_factory=dict)   # name → (SI value, unit)
    warnings: list[str] = field(default_factory=list)
    position_requests: set[str] = field(default_factory=set)  # node names whose position is read
    node_through_requests: set[str] = field(default_factory=set)
    rate_requests: set[str] = field(default_factory=set)     # node names whose across rate is read


class Context:
    """A component's handle on the model (one per component instance)."""

    def __init__(self, asm: Assembly, name: str, comp: type[Component], ports: dict[str, str],
                 values: dict[str, object], structural: dict[str, object], free: set[str] = frozenset()):
        self._asm = asm
        self.name = name
        self._comp = comp
        self._ports = ports
        self._values = values
        self._structural = structural
        self._free = set(free)
        self.p = _ParamView(self)
        self.time = E.TIME

    # -- parameters -------------------------------------------------------------------
    def param(self, pname: str):
        spec = self._comp.param(pname)
        if spec is None:
            raise KeyError(f"{self._comp.type} has no parameter '{pname}'")
        if spec.structural:
            return self._structural[pname]
        value = self._values[pname]
        if spec.vector:
            out = []
            for i, v in enumerate(value):
                full = f"{self.name}.{pname}[{i}]"
                self._asm.params.setdefault(full, (float(v), spec.unit))
                out.append(E.param(full))
            return out
        full = f"{self.name}.{pname}"
        self._asm.params.setdefault(full, (float(value), spec.unit))
        return E.param(full)

    def value(self, pname: str):
        """The numeric (build-time) value of a parameter, for structure decisions only."""
        return self._structural.get(pname, self._values.get(pname))

    def active(self, pname: str) -> bool:
        """True when an optional effect's parameter is non-zero or free for identification;
        components leave the effect's terms out of the equations otherwise."""
        v = self._values.get(pname, 0.0)
        return pname in self._free or (v != 0.0 if not isinstance(v, list) else any(v))

    # -- ports and nodes ----------------------------------------------------------------
    def connected(self, port: str) -> bool:
        return port in self._ports

    def node(self, port: str) -> NodeInfo:
        if port not in self._ports:
            raise KeyError(f"port '{port}' of '{self.name}' is not connected")
        return self._asm.nodes[self._ports[port]]

    def across(self, port: str) -> E.Expr:
        """Pressure, velocity, angular velocity or signal value at a port's node."""
        n = self.node(port)
        if n.is_reference:
            return E.const(0.0)
        return E.var(across_name(n.name, n.domain))

    def position(self, port: str) -> E.Expr:
        """Position (translational) or angle (rotational) of a port's node."""
        n = self.node(port)
        if n.domain.position is None:
            raise ValueError(f"port '{port}' of '{self.name}' is {n.domain.value}: it has no position")
        if n.is_reference:
            return E.const(0.0)
        self._asm.position_requests.add(n.name)
        return E.var(position_name(n.name, n.domain))

    def through(self, port: str, value) -> None:
        """Flow (force, torque) that this component takes from the node at ``port``."""
        n = self.node(port)
        n.through.append((self.name, E.as_expr(value)))

    def capacitance(self, port: str, value) -> None:
        """Add V/β (hydraulic), mass (translational) or inertia (rotational) to a node."""
        n = self.node(port)
        n.capacitance.append((self.name, E.as_expr(value)))

    def rate(self, port: str) -> E.Expr:
        """d(across)/dt at a port's node (acceleration, angular acceleration): the node's own
        balance −Σthrough/ΣC, a function of the states, for an element whose own states are
        driven by the motion it rides on (a pendulum on an arm). A node whose across value a
        source imposes has none (reading it is an error)."""
        n = self.node(port)
        if n.is_reference:
            return E.const(0.0)
        self._asm.rate_requests.add(n.name)
        return E.var(rate_name(n.name, n.domain))

    def impose(self, port: str, across, position=None) -> None:
        """Make this component the source of the node's across value (and position)."""
        n = self.node(port)
        n.imposed.append((self.name, E.as_expr(across), None if position is None else E.as_expr(position)))

    def node_through(self, port: str) -> E.Expr:
        """Sum of what all *other* components at the node take from it (for sources)."""
        n = self.node(port)
        self._asm.node_through_requests.add(n.name)
        return E.var(f"{n.name}.through_except.{self.name}")

    def signal(self, port: str) -> E.Expr:
        return self.across(port)

    def drive(self, port: str, value) -> None:
        """Set the value of a signal output port."""
        self.impose(port, value)

    # -- own states and variables -----------------------------------------------------------
    def state(self, sname: str) -> E.Expr:
        spec = self._comp.state_spec(sname)
        if spec is None:
            raise KeyError(f"{self._comp.type} declares no state '{sname}'")
        full = f"{self.name}.{sname}"
        if full not in self._asm.states:
            self._asm.states[full] = (spec.unit, spec.initial, spec.nominal, spec.description)
        return E.state(full)

    def der(self, sname: str, value) -> None:
        self.state(sname)
        self._asm.derivatives[f"{self.name}.{sname}"] = E.as_expr(value)

    def at_rest(self, sname: str, value) -> None:
        """At rest the state equals ``value`` (a sensor's reading equals what it senses): a
        recording that starts the state at its first sample starts the sensed quantity there too
        (:func:`hydrocli.experiments.initial.given_state`)."""
        self.state(sname)
        self._asm.rest[f"{self.name}.{sname}"] = E.as_expr(value)

    def let(self, vname: str, value, unit: str = "") -> E.Expr:
        full = f"{self.name}.{vname}"
        self._asm.variables[full] = E.as_expr(value)
        spec = next((v for v in self._comp.variables if v.name == vname), None)
        self._asm.variable_units[full] = spec.unit if spec else unit
        return E.var(full)

    def guard(self, condition: E.Expr, message: str) -> None:
        """Stop the simulation with ``message`` when ``condition`` holds."""
        self._asm.guards.append((condition, f"{self.name}: {message}"))

    def warn(self, message: str) -> None:
        self._asm.warnings.append(f"{self.name}: {message}")


class _ParamView:
    """``c.p.Kv`` is shorthand for ``c.param("Kv")``."""

    def __init__(self, ctx: Context):
        self._ctx = ctx

    def __getattr__(self, item: str):
        if item.startswith("_"):
            raise AttributeError(item)
        return self._ctx.param(item)
