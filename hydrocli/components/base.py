"""Component specs as data, and the base class every component type derives from.

A component type declares its ports (with a physical domain), parameters (SI unit,
default, validity limits, identification bounds, description, source equation), states
and exposed variables as class-level tuples; its physics is one short ``equations``
method written against :class:`hydrocli.components.stamps.Stamps` (implemented by
:class:`hydrocli.model.context.Context`). The builder never needs
to know a component's internals, and ``hydro components``, the JSON Schema and the docs
tables come from these same specs.
"""
from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import ClassVar

from .roles import Role
from .stamps import Stamps


class Domain(str, Enum):
    """Physical domain of a port: across/through variables and their SI units."""

    HYDRAULIC = "hydraulic"          # across: pressure [Pa], through: volume flow [m^3/s]
    TRANSLATIONAL = "translational"  # across: velocity [m/s] (position [m]), through: force [N]
    ROTATIONAL = "rotational"        # across: angular velocity [rad/s] (angle [rad]), through: torque [N m]
    SIGNAL = "signal"                # a value; no through variable

    @property
    def across(self) -> str:
        return {"hydraulic": "p", "translational": "v", "rotational": "w", "signal": "y"}[self.value]

    @property
    def position(self) -> str | None:
        return {"translational": "x", "rotational": "theta"}.get(self.value)

    @property
    def across_unit(self) -> str:
        return {"hydraulic": "Pa", "translational": "m/s", "rotational": "rad/s", "signal": "1"}[self.value]

    @property
    def position_unit(self) -> str:
        return {"translational": "m", "rotational": "rad"}.get(self.value, "1")

    @property
    def through_unit(self) -> str:
        return {"hydraulic": "m^3/s", "translational": "N", "rotational": "N*m", "signal": "1"}[self.value]

    @property
    def capacitance_name(self) -> str:
        return {"hydraulic": "volume", "translational": "mass", "rotational": "inertia"}.get(self.value, "-")

    @property
    def nominal_across(self) -> float:
        """Typical magnitude, used to scale absolute tolerances."""
        return {"hydraulic": 1e5, "translational": 1e-2, "rotational": 1e-2, "signal": 1.0}[self.value]

    @property
    def nominal_position(self) -> float:
        return {"translational": 1e-3, "rotational": 1e-3}.get(self.value, 1.0)


H, T, R, S = Domain.HYDRAULIC, Domain.TRANSLATIONAL, Domain.ROTATIONAL, Domain.SIGNAL


@dataclass(frozen=True)
class Port:
    name: str
    domain: Domain
    description: str = ""
    optional: bool = False     # may be left unconnected (e.g. an optional reference signal)
    direction: str = ""        # signal ports: "in" or "out"


#: the ports of a single-input, single-output signal block
SIGNAL_IN = Port("in", Domain.SIGNAL, "input signal", direction="in")
SIGNAL_OUT = Port("out", Domain.SIGNAL, "output signal", direction="out")


#: Largest plausible magnitude of a parameter, by its SI unit (data, not code): a value beyond
#: it is a typing or unit slip ("1e300 kg", a volume in mm³ read as m³), refused at load.
MAGNITUDE_LIMITS: dict[str, float] = {
    "kg": 1e8,            # mass: a large offshore crane's payload is ~1e7 kg
    "kg*m^2": 1e10,       # moment of inertia
    "Pa": 1e12,           # pressures, bulk and Young's moduli (steel 2.1e11 Pa)
    "m^3": 1e2,           # oil volumes
    "m^2": 1e2,           # areas
    "m": 1e4,             # lengths, strokes
    "s": 1e6,             # time constants, delays
    "N": 1e10,            # forces
    "N/m": 1e13,          # stiffnesses
}
DEFAULT_MAGNITUDE_LIMIT = 1e100  # any other unit (1e30 stands for "no leakage" in some files)


#: States that cannot be negative (absolute pressures; the model's pressures are absolute).
NON_NEGATIVE_STATE_UNITS = ("Pa",)


def check_state_value(name: str, unit: str, value: float) -> str | None:
    """A problem text for a non-physical initial state value (NaN, ±inf, a negative absolute
    pressure, a magnitude beyond :data:`MAGNITUDE_LIMITS`), else None."""
    if value != value or value in (float("inf"), float("-inf")):
        return f"initial {name} must be a finite number (got {value})"
    if unit in NON_NEGATIVE_STATE_UNITS and value < 0:
        return f"initial {name} = {value:g} {unit} is below 0 Pa absolute (pressures are absolute)"
    limit = MAGNITUDE_LIMITS.get(unit)
    if limit is not None and abs(value) > limit:
        return f"initial {name} = {value:g} {unit} is beyond the physical range (|value| ≤ {limit:g} {unit})"
    return None


@dataclass(frozen=True)
class Param:
    """One parameter: SI unit, default, hard validity limits and identification bounds."""

    name: str
    unit: str
    default: float | None
    description: str
    source: str = ""
    min: float | None = None           # hard validity limit (inclusive), e.g. 0 for a volume
    max: float | None = None
    bounds: tuple[float, float] | None = None  # default identification bounds (SI)
    fluid: str | None = None           # take the machine's fluid property of this name by default
    structural: bool = False           # changes the equations' structure; fixed at build time
    vector: bool = False               # a list of values (table, polynomial)
    positive: bool = False             # strictly > 0

    def check(self, value) -> str | None:
        """A problem text when ``value`` is not valid for this parameter, else None."""
        values = value if isinstance(value, (list, tuple)) else [value]
        limit = MAGNITUDE_LIMITS.get(self.unit.replace(" ", ""), DEFAULT_MAGNITUDE_LIMIT)
        for v in values:
            if v != v:
                return f"{self.name} is NaN"
            if v in (float("inf"), float("-inf")):
                return f"{self.name} must be finite (got {v})"
            if limit is not None and abs(v) > limit:
                return f"{self.name} = {v:g} {self.unit} is beyond the physical range (|value| ≤ {limit:g} {self.unit})"
            if self.positive and v <= 0:
                return f"{self.name} must be > 0 (got {v:g} {self.unit})"
            if self.min is not None and v < self.min:
                return f"{self.name} must be ≥ {self.min:g} {self.unit} (got {v:g})"
            if self.max is not None and v > self.max:
                return f"{self.name} must be ≤ {self.max:g} {self.unit} (got {v:g})"
        return None


@dataclass(frozen=True)
class StateSpec:
    name: str
    unit: str
    description: str
    initial: float = 0.0
    nominal: float = 1.0   # typical magnitude (absolute tolerance scale)


@dataclass(frozen=True)
class VariableSpec:
    """A named quantity the component computes and exposes (usable in outputs)."""

    name: str
    unit: str
    description: str


class Component:
    """Base class of all component types. Subclasses set the class attributes and
    implement :meth:`equations`; they hold no state of their own."""

    type: ClassVar[str] = ""
    family: ClassVar[str] = ""
    description: ClassVar[str] = ""
    source: ClassVar[str] = ""
    ports: ClassVar[tuple[Port, ...]] = ()
    parameters: ClassVar[tuple[Param, ...]] = ()
    states: ClassVar[tuple[StateSpec, ...]] = ()
    variables: ClassVar[tuple[VariableSpec, ...]] = ()
    roles: ClassVar[tuple[Role, ...]] = ()     # what it can play in a machine (:mod:`.roles`)

    def equations(self, c: Stamps) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def check(self, values: dict[str, float]) -> list[str]:
        """Cross-parameter checks (each returns a readable problem); per-parameter limits
        are checked generically from the specs."""
        return []

    # -- spec helpers ----------------------------------------------------------------
    @classmethod
    def port(cls, name: str) -> Port | None:
        return next((p for p in cls.ports if p.name == name), None)

    @classmethod
    def param(cls, name: str) -> Param | None:
        return next((p for p in cls.parameters if p.name == name), None)

    @classmethod
    def role(cls, name: str) -> Role | None:
        return next((r for r in cls.roles if r.name == name), None)

    @classmethod
    def state_spec(cls, name: str) -> StateSpec | None:
        return next((s for s in cls.states if s.name == name), None)
