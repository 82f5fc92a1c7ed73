"""The built model: named states, a parameter vector, inputs/outputs and generated code.

Build once, solve many times: :meth:`Model.simulate` takes parameter arrays and input
tables; the compiled library is built on first use and cached on disk by source hash.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..units import si_unit
from . import expr as E
from .codegen import generate_c, generate_numpy
from .equations import Equations


@dataclass
class StateInfo:
    name: str
    unit: str
    initial: float
    nominal: float
    description: str


@dataclass(frozen=True)
class InitialRule:
    """An initial value given by a rule, resolved per experiment (:mod:`hydrocli.experiments.initial`):
    ``same_as`` another state's start, the first measured sample of an ``output`` (one Newton
    step on this state), or ``balance``: the value that makes the ``ref`` state's derivative
    zero at the start (a spring's force holding a node at rest)."""
    state: str
    kind: str          # same_as | output | balance
    ref: str           # a state name (same_as, balance) or an output name (output)


@dataclass
class ParamInfo:
    name: str
    value: float                 # SI value from the machine file
    unit: str                    # SI unit
    bounds: tuple[float, float] | None
    free: bool
    log: bool | None
    description: str
    display_unit: str | None = None
    min: float | None = None
    max: float | None = None
    positive: bool = False


@dataclass
class Model:
    name: str
    netlist_sha: str
    equations: Equations
    states: list[StateInfo]
    x0: np.ndarray
    params: list[ParamInfo]
    input_units: dict[str, str]
    input_hold: dict[str, str]
    output_units: dict[str, str | None]
    variable_units: dict[str, str]
    warnings: list[str]
    netlist_text: str = ""
    file: str = ""
    initial_rules: list[InitialRule] = field(default_factory=list)
    _c_source: str | None = field(default=None, repr=False)
    _compiled: object = field(default=None, repr=False)
    _numpy_fn: object = field(default=None, repr=False)

    # -- names and vectors -----------------------------------------------------------
    @property
    def state_names(self) -> list[str]:
        return self.equations.states

    @property
    def param_names(self) -> list[str]:
        return self.equations.params

    @property
    def input_names(self) -> list[str]:
        return self.equations.inputs

    @property
    def output_names(self) -> list[str]:
        return self.equations.outputs

    @property
    def p0(self) -> np.ndarray:
        return np.array([p.value for p in self.params], dtype=float)

    def param_index(self, name: str) -> int:
        try:
            return self.equations.params.index(name)
        except ValueError:
            from ..suggest import suggest
            from ..errors import NetlistError
            raise NetlistError(f"unknown parameter '{name}'{suggest(name, self.equations.params)}",
                               hint="'hydro check MACHINE' lists the parameters") from None

    def state_index(self, name: str) -> int:
        return self.equations.states.index(name)

    def param_vector(self, overrides: dict[str, float] | None = None, base: np.ndarray | None = None) -> np.ndarray:
        """A new parameter vector: ``base`` (the file's values when None) with the named
        ``overrides`` set."""
        p = self.p0 if base is None else np.array(base, dtype=float)
        for k, v in (overrides or {}).items():
            p[self.param_index(k)] = v
        return p

    @property
    def free_params(self) -> list[str]:
        return [p.name for p in self.params if p.free]

    def guard_message(self, code: int) -> str:
        g = self.equations.guards
        return g[code - 1][1] if 1 <= code <= len(g) else f"model status {code}"

    def output_unit_si(self, name: str) -> str:
        e = self.equations.output_exprs[name]
        if e.op == "sym":
            kind, n = e.args
            if kind == "var":
                return self.variable_units.get(n, "")
            if kind == "state":
                return self.states[self.state_index(n)].unit
        return self.output_units.get(name) and si_unit(self.output_units[name], fallback="") or ""

    # -- generated code --------------------------------------------------------------
    @property
    def c_source(self) -> str:
        if self._c_source is None:
            self._c_source = generate_c(self.equations, self.name)
        return self._c_source

    def numpy_evaluate(self):
        """``evaluate(t, x, p, u) -> (dx, y, vars, status)`` on floats or arrays."""
        if self._numpy_fn is None:
            ns: dict = {}
            exec(compile(generate_numpy(self.equations), f"<hydrocli model {self.name}>", "exec"), ns)
            self._numpy_fn = ns["evaluate"]
        return self._numpy_fn

    def evaluate_along(self, t: np.ndarray, X: np.ndarray, U: np.ndarray, p: np.ndarray | None = None) -> dict:
        """All named variables evaluated along a trajectory (rows = samples)."""
        p = self.p0 if p is None else p
        _, _, vs, _ = self.numpy_evaluate()(t, list(X.T), p, list(U.T))
        return {k: np.broadcast_to(np.asarray(v, dtype=float), t.shape).copy() for k, v in vs.items()}

    def __getstate__(self):
        d = dict(self.__dict__)
        d["_numpy_fn"] = None
        return d

    def describe_expr(self, e: E.Expr) -> str:
        return E.to_python(e)
