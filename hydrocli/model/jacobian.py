"""Analytic Jacobian ∂f/∂x of the generated model, by symbolic differentiation.

Forward-mode chain rule through the named variables: for a variable v and a state j it
depends on, dv/dx_j = Σ_s ∂v/∂s · ds/dx_j over the symbols s of v's definition; each such
derivative becomes its own named local in the generated code, so nothing is expanded
twice. The entries follow the CSR sparsity pattern the integrator was given
(``HY_JAC_ROW/COL``); the integrator uses ``hy_jac`` instead of finite differences, which
makes the cost of a Jacobian independent of how many states a row couples (a supply node
shared by many cylinders).
"""
from __future__ import annotations

from . import expr as E
from .equations import Equations, StateDeps, order_variables


def _dsym(var: str, j: int) -> E.Expr:
    return E.sym("dvar", f"{var}@{j}")


def _total(e: E.Expr, j: int, deps: StateDeps, states: list[str]) -> E.Expr:
    """d e/d x_j with variables' derivatives referenced as dvar symbols."""
    out = E.ZERO
    for key in sorted(e.symbol_set):
        kind, name = key
        if kind == "state" and deps.index[name] == j:
            out = E.add(out, E.partial(e, key))
        elif kind == "var" and j in deps.of_var.get(name, ()):
            out = E.add(out, E.mul(E.partial(e, key), _dsym(name, j)))
    return out


def _prepare(eqs: Equations):
    deps = StateDeps(eqs)
    roots = [eqs.derivatives[s] for s in eqs.states]
    for r in roots:
        deps.of(r)
    return deps, order_variables(eqs, roots)


def jacobian_size(eqs: Equations, names) -> int:
    """Estimated characters of the analytic Jacobian's code (cheap: no differentiation):
    each variable's text once per state it depends on."""
    deps, order = _prepare(eqs)
    return sum(len(E.to_c(eqs.variables[v], names)) * (1 + len(deps.of_var.get(v, ()))) for v in order)


def jacobian_definitions(eqs: Equations, rows: list[int], cols: list[int]):
    """(ordered variables, derivative-variable definitions, entry expressions)."""
    deps, order = _prepare(eqs)
    dvars: list[tuple[str, E.Expr]] = []
    for v in order:
        for j in sorted(deps.of_var.get(v, ())):
            d = _total(eqs.variables[v], j, deps, eqs.states)
            dvars.append((f"{v}@{j}", d))
    entries = [_total(eqs.derivatives[eqs.states[i]], j, deps, eqs.states) for i, j in zip(rows, cols)]
    return order, dvars, entries


def jacobian_c(eqs: Equations, names, rows: list[int], cols: list[int], max_chars: int | None = None) -> list[str]:
    """C lines of ``hy_jac`` (empty when its estimated size exceeds ``max_chars``: the
    integrator then uses finite differences)."""
    if max_chars is not None and jacobian_size(eqs, names) > max_chars:
        return []
    order, dvars, entries = jacobian_definitions(eqs, rows, cols)
    lines = ["#define HY_HAS_JAC",
             "static int hy_jac(double t, const double *x, const double *p, const double *u, double *jv) {",
             "    (void)t; (void)x; (void)p; (void)u;"]
    for v in order:
        lines.append(f"    const double {names(('var', v))} = {E.to_c(eqs.variables[v], names)};")
    for dname, d in dvars:
        lines.append(f"    const double {names(('dvar', dname))} = {E.to_c(d, names)};")
    for k, e in enumerate(entries):
        lines.append(f"    jv[{k}] = {E.to_c(e, names)};")
    lines += ["    return 0;", "}", ""]
    return lines


def jacobian_numpy_source(eqs: Equations, names, rows: list[int], cols: list[int]) -> str:
    """Python source of ``jacobian(t, x, p, u) -> list of entries`` (tests, fallback)."""
    order, dvars, entries = jacobian_definitions(eqs, rows, cols)
    body = ["import numpy as np", "", "def jacobian(t, x, p, u):", "    with np.errstate(all='ignore'):"]
    body += [f"        {names(('var', v))} = {E.to_numpy(eqs.variables[v], names)}" for v in order]
    body += [f"        {names(('dvar', d))} = {E.to_numpy(e, names)}" for d, e in dvars]
    body.append("        return [" + ", ".join(E.to_numpy(e, names) for e in entries) + "]")
    return "\n".join(body) + "\n"
