"""Generate the model's flat right-hand side as C (compiled) and NumPy (fallback, vectorised).

Input: ordered variable definitions, state derivatives, outputs and guards, all as
:class:`~hydrocli.model.expr.Expr`. The C text follows the integrator's contract
(``HY_NX``…, ``hy_rhs``, ``hy_out``, Jacobian sparsity ``HY_JAC_ROW/COL``); parameters
and inputs are array arguments, so changing them never recompiles.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

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


MAX_JACOBIAN_CHARS = 1_000_000  # beyond this, compile time outweighs the gain: finite differences


class StateDeps:
    """Which states (or, with ``kind="param"``, which parameters) each variable and each
    derivative depends on (through variables)."""

    def __init__(self, eqs: Equations, kind: str = "state"):
        self.eqs = eqs
        self.kind = kind
        self.index = {s: i for i, s in enumerate(eqs.states if kind == "state" else eqs.params)}
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


def _ident(prefix: str, i: int, name: str) -> str:
    return f"{prefix}{i}_" + re.sub(r"[^A-Za-z0-9]", "_", name)[:40]


class _Names:
    """C/NumPy identifiers of every symbol; derivative symbols ("dvar", "v@j") on demand."""

    def __init__(self, eqs: Equations, x="x", p="p", u="u"):
        self.map = {}
        for i, s in enumerate(eqs.states):
            self.map[("state", s)] = f"{x}[{i}]"
        for i, s in enumerate(eqs.params):
            self.map[("param", s)] = f"{p}[{i}]"
        for i, s in enumerate(eqs.inputs):
            self.map[("input", s)] = f"{u}[{i}]"
        for i, v in enumerate(sorted(eqs.variables)):
            self.map[("var", v)] = _ident("v", i, v)
        self.map[("time", "t")] = "t"

    def __call__(self, key):
        got = self.map.get(key)
        if got is None and key[0] == "dvar":
            got = self.map[key] = _ident("d", len(self.map), key[1])
        return got if got is not None else self.map[key]


def generate_c(eqs: Equations, name: str = "model", analytic_jacobian: bool = True,
               sensitivities: bool = False) -> str:
    """The model's C translation unit; ``sensitivities`` adds ∂f/∂p, ∂g/∂x and ∂g/∂p
    (``HY_HAS_SENS``, see :mod:`hydrocli.model.jacobian`) for ``hy_simulate_sens``."""
    nx, npar, nu, ny = len(eqs.states), len(eqs.params), len(eqs.inputs), len(eqs.outputs)
    names = _Names(eqs)
    rows, cols = jacobian_pattern(eqs)
    rhs_roots = [eqs.derivatives[s] for s in eqs.states] + [g for g, _ in eqs.guards]
    out_roots = [eqs.output_exprs[o] for o in eqs.outputs]
    lines = [f"/* generated by hydrocli for machine '{name}': do not edit */",
             "#include <math.h>",
             f"#define HY_NX {nx}", f"#define HY_NP {max(npar, 0)}", f"#define HY_NU {nu}",
             f"#define HY_NY {ny}", f"#define HY_NNZ {len(rows)}",
             f"static const int HY_JAC_ROW[{max(len(rows), 1)}] = {{{', '.join(map(str, rows)) or '0'}}};",
             f"static const int HY_JAC_COL[{max(len(cols), 1)}] = {{{', '.join(map(str, cols)) or '0'}}};",
             "static inline double hy_sign(double v) { return (double)((v > 0) - (v < 0)); }",
             "",
             "static int hy_rhs(double t, const double *x, const double *p, const double *u, double *dx) {",
             "    (void)t; (void)x; (void)p; (void)u;"]
    lines += _c_body(eqs, names, rhs_roots)
    for k, (g, _msg) in enumerate(eqs.guards):
        lines.append(f"    if ({E.to_c(g, names)}) return {k + 1};")
    for i, s in enumerate(eqs.states):
        lines.append(f"    dx[{i}] = {E.to_c(eqs.derivatives[s], names)};")
    lines += ["    return 0;", "}", "",
              "static int hy_out(double t, const double *x, const double *p, const double *u, double *y) {",
              "    (void)t; (void)x; (void)p; (void)u; (void)y;"]
    lines += _c_body(eqs, names, out_roots)
    for i, o in enumerate(eqs.outputs):
        lines.append(f"    y[{i}] = {E.to_c(eqs.output_exprs[o], names)};")
    lines += ["    return 0;", "}", ""]
    if analytic_jacobian:
        from .jacobian import jacobian_c
        jac = jacobian_c(eqs, names, rows, cols, max_chars=None if sensitivities else MAX_JACOBIAN_CHARS)
        lines += jac
        if sensitivities:
            from .jacobian import sensitivity_c
            lines += sensitivity_c(eqs, names)
    return "\n".join(lines)


def _c_body(eqs, names, roots) -> list[str]:
    out = []
    for v in order_variables(eqs, roots):
        out.append(f"    const double {names(('var', v))} = {E.to_c(eqs.variables[v], names)};  /* {v} */")
    return out


def generate_numpy(eqs: Equations) -> str:
    """Python source defining ``evaluate(t, x, p, u, want)``: works on floats or on arrays
    (``x`` a sequence of state arrays); returns (dx list, y list, vars dict, status)."""
    names = _Names(eqs)
    all_roots = ([eqs.derivatives[s] for s in eqs.states] + [eqs.output_exprs[o] for o in eqs.outputs]
                 + [g for g, _ in eqs.guards])
    order = order_variables(eqs, all_roots + [E.var(v) for v in eqs.variables])
    lines = ["import numpy as np", "", "def evaluate(t, x, p, u):",
             "    with np.errstate(all='ignore'):"]
    for v in order:
        lines.append(f"        {names(('var', v))} = {E.to_numpy(eqs.variables[v], names)}")
    lines.append("        status = 0")
    for k, (g, _msg) in enumerate(eqs.guards):
        lines.append(f"        if status == 0 and np.any({E.to_numpy(g, names)}): status = {k + 1}")
    lines.append("        dx = [" + ", ".join(E.to_numpy(eqs.derivatives[s], names) for s in eqs.states) + "]")
    lines.append("        y = [" + ", ".join(E.to_numpy(eqs.output_exprs[o], names) for o in eqs.outputs) + "]")
    lines.append("        vs = {" + ", ".join(f"{v!r}: {names(('var', v))}" for v in order) + "}")
    lines.append("    return dx, y, vs, status")
    return "\n".join(lines) + "\n"
