"""The parsed, normalised machine: plain data with SI values and source locations."""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import Location


@dataclass
class ParamValue:
    """A parameter as the machine file gives it (SI), with its identification settings."""

    value: float | list[float]
    loc: Location = field(default_factory=Location)
    free: bool = False
    bounds: tuple[float, float] | None = None
    unit: str | None = None         # the unit the file wrote it in (kept on write-back)
    log: bool | None = None         # log-scaled search (None = decide from the bounds)
    given: bool = True              # False when the value is the spec's default


@dataclass
class ComponentDecl:
    name: str
    type: str
    ports: dict[str, str]
    params: dict[str, ParamValue]
    loc: Location = field(default_factory=Location)
    template: str | None = None     # instance name it was expanded from


@dataclass
class InputDecl:
    name: str
    unit: str = "1"                 # display unit of recordings/designs (values are SI inside)
    hold: str = "linear"            # linear | zoh
    description: str = ""
    loc: Location = field(default_factory=Location)


@dataclass
class OutputDecl:
    name: str
    expr: str
    unit: str | None = None         # display unit
    description: str = ""
    loc: Location = field(default_factory=Location)


@dataclass
class Netlist:
    name: str
    file: str
    components: dict[str, ComponentDecl]
    inputs: dict[str, InputDecl]
    outputs: dict[str, OutputDecl]
    initial: dict[str, ParamValue] = field(default_factory=dict)
    fluid: dict[str, ParamValue] = field(default_factory=dict)
    description: str = ""
    text: str = ""                  # the main file's text as loaded
    doc: object = None              # the main file's round-trip document (for write-back)
    unit_defaults: dict[str, str] = field(default_factory=dict)  # dimensionality → file default unit

    def param_value(self, dotted: str):
        comp, _, pname = dotted.rpartition(".")
        return self.components[comp].params[pname]

    def nodes(self) -> dict[str, list[tuple[str, str]]]:
        out: dict[str, list[tuple[str, str]]] = {}
        for c in self.components.values():
            for port, node in c.ports.items():
                out.setdefault(node, []).append((c.name, port))
        return out
