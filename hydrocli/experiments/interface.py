"""What loading an experiment needs to know about a machine: its inputs, outputs and states
with their units — not a built model.

``load_all(path, MachineInterface.of(model))`` loads exactly as ``load_all(path, model)``
does (the loaders read only these attributes); an interface is a small picklable value that
can also be written by hand (tests, tools that prepare data before the machine is built).
Binding the loaded data to a model's equations is then a separate step
(``experiments.initial.initial_state`` for the start state, ``solve.simulate`` for the run).
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class StateUnit:
    name: str
    unit: str


@dataclass(frozen=True)
class MachineInterface:
    name: str
    input_names: list[str]
    output_names: list[str]
    states: tuple[StateUnit, ...] = ()
    input_units: dict[str, str] = field(default_factory=dict)     # as declared in the machine file
    input_hold: dict[str, str] = field(default_factory=dict)      # input → "zoh" | "linear"
    output_units: dict[str, str] = field(default_factory=dict)    # display units of the machine file
    output_si: dict[str, str] = field(default_factory=dict)       # output → SI unit

    @classmethod
    def of(cls, model) -> "MachineInterface":
        """The interface of a built :class:`hydrocli.model.model.Model`."""
        return cls(name=model.name, input_names=list(model.input_names), output_names=list(model.output_names),
                   states=tuple(StateUnit(s.name, s.unit) for s in model.states),
                   input_units=dict(model.input_units), input_hold=dict(model.input_hold),
                   output_units=dict(model.output_units),
                   output_si={o: model.output_unit_si(o) for o in model.output_names})

    @property
    def state_names(self) -> list[str]:
        return [s.name for s in self.states]

    def state_index(self, name: str) -> int:
        return self.state_names.index(name)

    def output_unit_si(self, name: str) -> str:
        return self.output_si.get(name, "")
