"""Parse the small expression language of machine outputs, e.g. ``"chamber_a.p - chamber_b.p"``.

Names are dotted model quantities (node ``.p``/``.v``/``.x``, component variables and
states, parameters, machine inputs); allowed are numbers, + − * / **, unary minus and the
functions of :mod:`hydrocli.model.expr`. Parsed with :mod:`ast`, never evaluated.
"""
from __future__ import annotations

import ast

from ..suggest import suggest
from . import expr as E

FUNCS = {"abs": E.fabs, "sqrt": E.sqrt, "exp": E.exp, "log": E.log, "tanh": E.tanh, "sin": E.sin,
         "cos": E.cos, "atan2": E.atan2, "min": E.fmin, "max": E.fmax, "sign": E.sign}


class ExprSyntaxError(ValueError):
    pass


def parse_expression(text: str, resolve) -> E.Expr:
    """``resolve(dotted_name) -> Expr | None``; raises ExprSyntaxError with a clear message."""
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExprSyntaxError(f"cannot parse expression '{text}': {exc.msg}") from None
    return _walk(tree.body, resolve, text)


def _dotted(node) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        base = _dotted(node.value)
        return f"{base}.{node.attr}" if base else None
    return None


def _walk(node, resolve, text):
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return E.const(node.value)
    name = _dotted(node)
    if name is not None:
        got = resolve(name)
        if got is None:
            known = getattr(resolve, "known", lambda: [])()
            raise ExprSyntaxError(f"unknown quantity '{name}' in '{text}'{suggest(name, known)}")
        return got
    if isinstance(node, ast.BinOp):
        a, b = _walk(node.left, resolve, text), _walk(node.right, resolve, text)
        ops = {ast.Add: E.add, ast.Sub: E.sub, ast.Mult: E.mul, ast.Div: E.div, ast.Pow: E.power}
        fn = ops.get(type(node.op))
        if fn is None:
            raise ExprSyntaxError(f"operator not allowed in '{text}'")
        return fn(a, b)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = _walk(node.operand, resolve, text)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCS and not node.keywords:
        return FUNCS[node.func.id](*(_walk(a, resolve, text) for a in node.args))
    raise ExprSyntaxError(f"not allowed in an output expression: '{ast.unparse(node)}' in '{text}' "
                          f"(functions: {', '.join(FUNCS)})")
