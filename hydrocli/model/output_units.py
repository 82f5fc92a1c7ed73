"""The unit a machine output declares must have the dimension of its expression.

``P2: {expr: chamber_2.p, unit: mm}`` would otherwise plot a pressure as millimetres.
The dimension of an expression is inferred from its symbols (states, variables, parameters,
inputs: their SI units) through + − × ÷, powers with constant exponents, sqrt, abs, min/max
and branches; transcendental functions give dimensionless results. Where it cannot be
inferred (a sum of different dimensions, a power with a symbolic exponent) nothing is said.
"""
from __future__ import annotations

from ..errors import Problem
from ..units import registry

CONST, UNKNOWN = "const", "unknown"
_SAME = ("abs", "min", "max", "where")


def check_output_units(model, outputs) -> list[Problem]:
    """Problems for outputs (``{name: OutputDecl}``) whose declared unit has the wrong dimension."""
    problems = []
    units = _symbol_units(model)
    for name, decl in outputs.items():
        e = model.equations.output_exprs.get(name)
        if e is not None and not _finite_constants(e):
            problems.append(Problem(f"output '{name}': a number in '{decl.expr}' is not finite", decl.loc,
                                    "write finite numbers (1e999 overflows to infinity)"))
            continue
        if e is None or not decl.unit:
            continue
        got = _dim(e, units)
        if got in (CONST, UNKNOWN):
            continue
        want = _quantity(decl.unit)
        if want is None or want.dimensionality == got.dimensionality:
            continue
        si = f"{got.to_base_units().units:~}".replace(" ", "") or "1"
        problems.append(Problem(f"output '{name}': unit '{decl.unit}' has dimension {want.dimensionality} but "
                                f"'{decl.expr}' is in {si} ({got.dimensionality})", decl.loc,
                                f"give a unit convertible to {si}"))
    return problems


def _finite_constants(e) -> bool:
    import math
    stack = [e]
    while stack:
        x = stack.pop()
        if x.op == "const":
            if not math.isfinite(x.args[0]):
                return False
        elif x.op != "sym":
            stack.extend(a for a in x.args if hasattr(a, "op"))
    return True


def _symbol_units(model) -> dict[tuple[str, str], str]:
    out = {("state", s.name): s.unit for s in model.states}
    out.update({("var", k): v for k, v in model.variable_units.items()})
    out.update({("param", p.name): p.unit for p in model.params})
    out.update({("input", k): v for k, v in model.input_units.items()})
    return out


def _quantity(unit: str):
    from ..units import parse_unit
    try:
        return registry().Quantity(1.0, parse_unit(unit))
    except Exception:
        return None


def _dim(e, units):
    op, a = e.op, e.args
    if op == "const":
        return CONST
    if op == "sym":
        unit = units.get((a[0], a[1]))
        q = _quantity(unit) if unit else None
        return q if q is not None else UNKNOWN
    if op in ("<", "<=", ">", ">=", "==", "!="):
        return CONST
    if op == "where":
        a = a[1:]
    dims = [_dim(x, units) for x in a]
    if UNKNOWN in dims and op not in ("exp", "log", "tanh", "sin", "cos", "tan", "atan", "asin", "acos",
                                      "sinh", "cosh", "asinh", "atan2", "sign"):
        return UNKNOWN
    if op in ("+", "-") or op in _SAME:
        known = [d for d in dims if d is not CONST]
        if not known:
            return CONST
        if all(d.dimensionality == known[0].dimensionality for d in known):
            return known[0]
        return UNKNOWN
    if op in ("*", "/"):
        x, y = dims
        if x is CONST and y is CONST:
            return CONST
        x = registry().Quantity(1.0) if x is CONST else x
        y = registry().Quantity(1.0) if y is CONST else y
        return x * y if op == "*" else x / y
    if op == "sqrt":
        return CONST if dims[0] is CONST else dims[0] ** 0.5
    if op == "pow":
        base, ex = a
        if dims[0] is CONST:
            return CONST
        return dims[0] ** ex.args[0] if ex.op == "const" else UNKNOWN
    return registry().Quantity(1.0)      # exp, log, trigonometric, sign, atan2: dimensionless
