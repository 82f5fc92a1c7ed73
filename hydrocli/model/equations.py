"""The flat model (:class:`Equations`) and its structure: the order in which named
variables are computed (a cycle is an algebraic loop) and which states each derivative
depends on (the Jacobian's sparsity pattern). Used by the code generators
(``codegen``, ``jacobian``) and the builder.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import Problem, TopologyError
from . import expr as E


@dataclass
class Equations:
    """The flat model: everything the code generators need, by name."""

    states: list[str]
    params: list[str]
    inputs: list[str]
    outputs: list[str]
    variables: dict[str, E.Expr]          # name → definition (any order)
    derivatives: dict[str, E.Expr]        # state name → d/dt
    output_exprs: dict[str, E.Expr]
    guards: list[tuple[E.Expr, str]]
    rest: dict[str, E.Expr] = field(default_factory=dict)   # state → what it reads at rest (sensors)


def order_variables(eqs: Equations, roots: list[E.Expr]) -> list[str]:
    """Variables needed by ``roots`` in dependency order; a cycle is an algebraic loop."""
    order: list[str] = []
    mark: dict[str, int] = {}  # 1 visiting, 2 done

    def visit(name: str, chain: list[str]) -> None:
        m = mark.get(name)
        if m == 2:
            return
        if m == 1:
            loop = chain[chain.index(name):] + [name]
            raise TopologyError(Problem(
                "algebraic loop: " + " → ".join(loop),
                hint="these quantities depend on each other instantaneously; add a volume (hydraulic), "
                     "a mass (mechanical) or a lag (signal) to break the loop"))
        if name not in eqs.variables:
            raise TopologyError(Problem(f"quantity '{name}' is used but never defined",
                                        hint="check port connections and node names"))
        mark[name] = 1
        chain.append(name)
        for dep in sorted(n for k, n in eqs.variables[name].symbols() if k == "var"):
            visit(dep, chain)
        chain.pop()
        mark[name] = 2
        order.append(name)

    for r in roots:
        for k, n in sorted(r.symbols()):
            if k == "var":
                visit(n, [])
    return order


class StateDeps:
    """Which states (or, with ``kind="param"`` / ``"input"``, which parameters / inputs) each
    variable and each derivative depends on (through variables)."""

    def __init__(self, eqs: Equations, kind: str = "state"):
        self.eqs = eqs
        self.kind = kind
        names = {"state": eqs.states, "param": eqs.params, "input": eqs.inputs}[kind]
        self.index = {s: i for i, s in enumerate(names)}
        self.of_var: dict[str, frozenset[int]] = {}

    def of(self, e: E.Expr) -> frozenset[int]:
        out: set[int] = set()
        for k, n in e.symbol_set:
            if k == self.kind:
                out.add(self.index[n])
            elif k == "var":
                if n not in self.of_var:
                    self.of_var[n] = frozenset()  # cycles were rejected earlier
                    self.of_var[n] = self.of(self.eqs.variables[n])
                out |= self.of_var[n]
        return frozenset(out)


def state_dependencies(eqs: Equations) -> list[set[int]]:
    """For each derivative, the indices of the states it depends on (Jacobian sparsity)."""
    deps = StateDeps(eqs)
    return [set(deps.of(eqs.derivatives[s])) for s in eqs.states]


def jacobian_pattern(eqs: Equations) -> tuple[list[int], list[int]]:
    """CSR-ordered (row, col) of the structurally non-zero ∂f_i/∂x_j, diagonal included."""
    rows, cols = [], []
    for i, d in enumerate(state_dependencies(eqs)):
        for j in sorted(d | {i}):
            rows.append(i)
            cols.append(j)
    return rows, cols
