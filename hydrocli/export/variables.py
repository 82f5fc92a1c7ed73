"""The FMU's flat variable list and its structure, from a built :class:`Model`.

Value references follow the C arrays of the generated code, so the FMI glue needs no
lookup table: states ``[0, nx)``, their derivatives ``[nx, 2nx)``, parameters, inputs,
outputs (in model order). All values are SI; the machine file's units become display units.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import NetlistError, Problem
from ..model import expr as E
from ..model.model import Model


@dataclass
class FmuVariable:
    name: str
    vr: int
    causality: str                  # parameter | input | output | local
    variability: str                # tunable | continuous
    start: float | None
    unit: str = ""                  # SI unit as written by the model ("Pa", "m^3/s")
    display_unit: str | None = None
    description: str = ""
    min: float | None = None
    max: float | None = None
    nominal: float | None = None
    initial: str | None = None      # exact | calculated (None: the standard's default)
    derivative_of: int | None = None  # vr of the state (derivative variables)


@dataclass
class FmuLayout:
    """Variables and the ModelStructure dependencies (by value reference)."""

    variables: list[FmuVariable]
    nx: int
    outputs: list[int]
    derivatives: list[int]
    dependencies: dict[int, list[int]] = field(default_factory=dict)


def _limits(p) -> tuple[float | None, float | None]:
    """min/max of a parameter: the physical limits, widened to contain the bounds and value
    (bounds are the identification range, so a tool may move a parameter inside them)."""
    lo = [v for v in (p.min, p.bounds[0] if p.bounds else None) if v is not None]
    hi = [v for v in (p.max, p.bounds[1] if p.bounds else None) if v is not None]
    lo_v = min(lo + [p.value]) if lo else None
    hi_v = max(hi + [p.value]) if hi else None
    return lo_v, hi_v


class _Deps:
    """States and inputs an expression depends on, through the named variables."""

    def __init__(self, model: Model):
        self.eqs = model.equations
        self.memo: dict[str, frozenset] = {}

    def of(self, e: E.Expr) -> frozenset:
        out: set = set()
        for kind, name in e.symbol_set:
            if kind in ("state", "input"):
                out.add((kind, name))
            elif kind == "var":
                if name not in self.memo:
                    self.memo[name] = frozenset()
                    self.memo[name] = self.of(self.eqs.variables[name])
                out |= self.memo[name]
        return frozenset(out)


def fmu_layout(model: Model, x0: np.ndarray | None = None) -> FmuLayout:
    """All parameters (tunable, start = current value), inputs, outputs, states and derivatives."""
    eqs = model.equations
    x0 = model.x0 if x0 is None else np.asarray(x0, dtype=float)
    nx, npar, nu = len(eqs.states), len(eqs.params), len(eqs.inputs)
    vs: list[FmuVariable] = []
    for i, s in enumerate(model.states):
        vs.append(FmuVariable(s.name, i, "local", "continuous", float(x0[i]), s.unit, None,
                              s.description, nominal=s.nominal, initial="exact"))
    for i, s in enumerate(model.states):
        vs.append(FmuVariable(f"der({s.name})", nx + i, "local", "continuous", None, _der_unit(s.unit),
                              None, f"d/dt of {s.name}", derivative_of=i, initial="calculated"))
    base = 2 * nx
    for i, p in enumerate(model.params):
        lo, hi = _limits(p)
        vs.append(FmuVariable(p.name, base + i, "parameter", "tunable", float(p.value), p.unit,
                              p.display_unit, p.description, lo, hi, initial="exact"))
    base += npar
    for i, u in enumerate(eqs.inputs):
        disp = model.input_units.get(u)
        vs.append(FmuVariable(u, base + i, "input", "continuous", 0.0, _si_name(disp), disp, f"input {u}"))
    base += nu
    for i, y in enumerate(eqs.outputs):
        disp = model.output_units.get(y)
        unit = model.output_unit_si(y) or _si_name(disp)
        vs.append(FmuVariable(y, base + i, "output", "continuous", None, unit, disp, f"output {y}"))
    _check_unique(vs)

    deps = _Deps(model)
    vr_of = {("state", s): i for i, s in enumerate(eqs.states)}
    vr_of.update({("input", u): 2 * nx + npar + i for i, u in enumerate(eqs.inputs)})
    dependencies: dict[int, list[int]] = {}
    outputs = [2 * nx + npar + nu + i for i in range(len(eqs.outputs))]
    for vr, y in zip(outputs, eqs.outputs):
        dependencies[vr] = sorted(vr_of[k] for k in deps.of(eqs.output_exprs[y]))
    derivatives = [nx + i for i in range(nx)]
    for vr, s in zip(derivatives, eqs.states):
        dependencies[vr] = sorted(vr_of[k] for k in deps.of(eqs.derivatives[s]))
    return FmuLayout(vs, nx, outputs, derivatives, dependencies)


def _der_unit(unit: str) -> str:
    return "1/s" if unit in ("", "1") else f"{unit}/s"   # a/b/s = a/(b·s): left-associative


def _si_name(display: str | None) -> str:
    if not display:
        return ""
    from ..units import si_unit
    return si_unit(display, fallback="")


def _check_unique(vs: list[FmuVariable]) -> None:
    seen: dict[str, FmuVariable] = {}
    for v in vs:
        if v.name in seen:
            raise NetlistError(Problem(
                f"FMU export: the name '{v.name}' is used by a {seen[v.name].causality} and by a {v.causality}",
                hint="rename the machine output or input so that it differs from parameter and state names"))
        seen[v.name] = v
