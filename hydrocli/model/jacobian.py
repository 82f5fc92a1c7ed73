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
from .equations import Equations, StateDeps, jacobian_pattern, order_variables


def _dname(var: str, j: int, kind: str = "state") -> str:
    return f"{var}@{j}" if kind == "state" else f"{var}@p{j}"


def _dsym(var: str, j: int, kind: str = "state") -> E.Expr:
    return E.sym("dvar", _dname(var, j, kind))


def _total(e: E.Expr, j: int, deps: StateDeps, states: list[str] | None = None) -> E.Expr:
    """d e/d x_j (or d e/d p_j when ``deps.kind == "param"``) with variables' derivatives
    referenced as dvar symbols."""
    out = E.ZERO
    for key in sorted(e.symbol_set):
        kind, name = key
        if kind == deps.kind and deps.index[name] == j:
            out = E.add(out, E.partial(e, key))
        elif kind == "var" and j in deps.of_var.get(name, ()):
            out = E.add(out, E.mul(E.partial(e, key), _dsym(name, j, deps.kind)))
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


# -- sensitivities: ∂f/∂p, ∂g/∂x, ∂g/∂p ------------------------------------------------------
def _dvars(eqs: Equations, order: list[str], deps: StateDeps) -> list[tuple[str, E.Expr]]:
    return [(_dname(v, j, deps.kind), _total(eqs.variables[v], j, deps))
            for v in order for j in sorted(deps.of_var.get(v, ()))]


def _csc(roots: list[E.Expr], deps: StateDeps, ncols: int):
    """Column-compressed pattern (ptr, rows) and entry expressions of ∂roots/∂(deps.kind)."""
    per_col: list[list[int]] = [[] for _ in range(ncols)]
    for i, r in enumerate(roots):
        for j in deps.of(r):
            per_col[j].append(i)
    ptr, rows, entries = [0], [], []
    for j, col in enumerate(per_col):
        for i in sorted(col):
            rows.append(i)
            entries.append(_total(roots[i], j, deps))
        ptr.append(len(rows))
    return ptr, rows, entries


def sensitivity_definitions(eqs: Equations) -> dict:
    """Everything the sensitivity code needs, as expressions.

    ``fp``: ∂f/∂p (column-compressed over parameters); ``gx``: ∂g/∂x (column-compressed
    over states); ``gp``: ∂g/∂p. Each is (ptr, rows, entries) with the variables and
    derivative variables its entries use (forward-mode chain rule as for ∂f/∂x)."""
    f_roots = [eqs.derivatives[s] for s in eqs.states]
    g_roots = [eqs.output_exprs[o] for o in eqs.outputs]
    f_order = order_variables(eqs, f_roots)
    g_order = order_variables(eqs, g_roots)
    pdeps_f, pdeps_g, xdeps_g = (StateDeps(eqs, "param"), StateDeps(eqs, "param"), StateDeps(eqs, "state"))
    fp = _csc(f_roots, pdeps_f, len(eqs.params))
    gp = _csc(g_roots, pdeps_g, len(eqs.params))
    gx = _csc(g_roots, xdeps_g, len(eqs.states))
    return {"f_order": f_order, "g_order": g_order, "fp": fp, "fp_dvars": _dvars(eqs, f_order, pdeps_f),
            "gp": gp, "gx": gx, "g_dvars": _dvars(eqs, g_order, xdeps_g) + _dvars(eqs, g_order, pdeps_g)}


def _c_array(name: str, values: list[int]) -> str:
    return f"static const int {name}[{max(len(values), 1)}] = {{{', '.join(map(str, values)) or '0'}}};"


def sensitivity_c(eqs: Equations, names) -> list[str]:
    """C lines of ``hy_jfp`` (∂f/∂x in ``HY_JAC_ROW/COL`` order and ∂f/∂p in
    ``HY_FP_PTR/ROW`` order, one pass over the variables) and ``hy_gjac`` (∂g/∂x in
    ``HY_GX_PTR/ROW`` order, ∂g/∂p in ``HY_GP_PTR/ROW`` order); defines ``HY_HAS_SENS`` so
    that the integrator exports ``hy_simulate_sens``."""
    d = sensitivity_definitions(eqs)
    (fptr, frows, fent), (gxptr, gxrows, gxent), (gpptr, gprows, gpent) = d["fp"], d["gx"], d["gp"]
    rows, cols = jacobian_pattern(eqs)
    order, jdvars, jent = jacobian_definitions(eqs, rows, cols)
    head = "(double t, const double *x, const double *p, const double *u, "
    lines = ["#define HY_HAS_SENS", f"#define HY_FP_NNZ {len(frows)}", f"#define HY_GX_NNZ {len(gxrows)}",
             f"#define HY_GP_NNZ {len(gprows)}", _c_array("HY_FP_PTR", fptr), _c_array("HY_FP_ROW", frows),
             _c_array("HY_GX_PTR", gxptr), _c_array("HY_GX_ROW", gxrows),
             _c_array("HY_GP_PTR", gpptr), _c_array("HY_GP_ROW", gprows),
             "static int hy_jfp" + head + "double *jv, double *fpv) {",
             "    (void)t; (void)x; (void)p; (void)u; (void)jv; (void)fpv;"]
    lines += [f"    const double {names(('var', v))} = {E.to_c(eqs.variables[v], names)};" for v in order]
    lines += [f"    const double {names(('dvar', n))} = {E.to_c(e, names)};" for n, e in jdvars + d["fp_dvars"]]
    lines += [f"    jv[{k}] = {E.to_c(e, names)};" for k, e in enumerate(jent)]
    lines += [f"    fpv[{k}] = {E.to_c(e, names)};" for k, e in enumerate(fent)]
    lines += ["    return 0;", "}", "",
              "static int hy_gjac" + head + "double *gxv, double *gpv) {",
              "    (void)t; (void)x; (void)p; (void)u; (void)gxv; (void)gpv;"]
    lines += [f"    const double {names(('var', v))} = {E.to_c(eqs.variables[v], names)};" for v in d["g_order"]]
    lines += [f"    const double {names(('dvar', n))} = {E.to_c(e, names)};" for n, e in d["g_dvars"]]
    lines += [f"    gxv[{k}] = {E.to_c(e, names)};" for k, e in enumerate(gxent)]
    lines += [f"    gpv[{k}] = {E.to_c(e, names)};" for k, e in enumerate(gpent)]
    lines += ["    return 0;", "}", ""]
    return lines
