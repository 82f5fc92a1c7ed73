"""A small expression language in which components write their equations.

Components build :class:`Expr` trees with ordinary Python operators and the functions of
this module (``sqrt``, ``tanh``, ``where`` …). The builder prints the trees as C for the
compiled model and as NumPy code for the pure-Python fallback and for vectorised
evaluation (diagnosis regressors). Symbols refer to states, parameters, inputs and named
intermediate variables by their dotted names; the code generator maps names to indices.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Iterable

Number = int | float

_BINARY = {"+": 1, "-": 1, "*": 2, "/": 2}
_FUNCS_1 = ("sqrt", "exp", "log", "tanh", "sin", "cos", "tan", "atan", "abs", "sign", "asin", "acos",
            "cosh", "sinh", "asinh")
_FUNCS_2 = ("atan2", "min", "max", "pow")
_COMPARE = ("<", "<=", ">", ">=")


@dataclass(frozen=True, eq=False)
class Expr:
    """Immutable expression node: ``op`` with ``args`` (sub-expressions or a leaf payload)."""

    op: str
    args: tuple

    # -- construction -----------------------------------------------------------------
    def __add__(self, o): return add(self, o)
    def __radd__(self, o): return add(o, self)
    def __sub__(self, o): return sub(self, o)
    def __rsub__(self, o): return sub(o, self)
    def __mul__(self, o): return mul(self, o)
    def __rmul__(self, o): return mul(o, self)
    def __truediv__(self, o): return div(self, o)
    def __rtruediv__(self, o): return div(o, self)
    def __neg__(self): return mul(-1.0, self)
    def __pos__(self): return self
    def __pow__(self, o): return power(self, o)
    def __rpow__(self, o): return power(o, self)
    def __lt__(self, o): return _cmp("<", self, o)
    def __le__(self, o): return _cmp("<=", self, o)
    def __gt__(self, o): return _cmp(">", self, o)
    def __ge__(self, o): return _cmp(">=", self, o)
    def __abs__(self): return func("abs", self)

    def __bool__(self):
        raise TypeError("an Expr has no truth value; use where(cond, a, b) instead of if/else")

    # -- inspection -------------------------------------------------------------------
    @property
    def is_const(self) -> bool:
        return self.op == "const"

    @property
    def value(self) -> float:
        assert self.op == "const"
        return self.args[0]

    def symbols(self) -> set[tuple[str, str]]:
        """All (kind, name) leaves, kind in state/param/input/var/time."""
        return set(self.symbol_set)

    @functools.cached_property
    def symbol_set(self) -> frozenset:
        """The leaves as a frozenset, computed once per node from its children's."""
        if self.op == "sym":
            return frozenset([(self.args[0], self.args[1])])
        if self.op == "const":
            return frozenset()
        out: frozenset = frozenset()
        for a in self.args:
            if isinstance(a, Expr):
                out = out | a.symbol_set
        return out

    def __repr__(self) -> str:
        return to_python(self)


def const(v: Number) -> Expr:
    return Expr("const", (float(v),))


def sym(kind: str, name: str) -> Expr:
    return Expr("sym", (kind, name))


def state(name: str) -> Expr: return sym("state", name)
def param(name: str) -> Expr: return sym("param", name)
def input_(name: str) -> Expr: return sym("input", name)
def var(name: str) -> Expr: return sym("var", name)


TIME = sym("time", "t")


def as_expr(x) -> Expr:
    if isinstance(x, Expr):
        return x
    if isinstance(x, (int, float)) and not isinstance(x, bool):
        return const(x)
    raise TypeError(f"cannot use {type(x).__name__} in an equation")


def _is(e: Expr, v: float) -> bool:
    return e.op == "const" and e.args[0] == v


def add(a, b) -> Expr:
    a, b = as_expr(a), as_expr(b)
    if a.is_const and b.is_const:
        return const(a.value + b.value)
    if _is(a, 0.0):
        return b
    if _is(b, 0.0):
        return a
    return Expr("+", (a, b))


def sub(a, b) -> Expr:
    a, b = as_expr(a), as_expr(b)
    if a.is_const and b.is_const:
        return const(a.value - b.value)
    if _is(b, 0.0):
        return a
    if _is(a, 0.0):
        return mul(-1.0, b)
    return Expr("-", (a, b))


def mul(a, b) -> Expr:
    a, b = as_expr(a), as_expr(b)
    if a.is_const and b.is_const:
        return const(a.value * b.value)
    if _is(a, 0.0) or _is(b, 0.0):
        return const(0.0)
    if _is(a, 1.0):
        return b
    if _is(b, 1.0):
        return a
    return Expr("*", (a, b))


def div(a, b) -> Expr:
    a, b = as_expr(a), as_expr(b)
    if b.is_const and b.value == 0.0:
        raise ZeroDivisionError("division by a constant zero in an equation")
    if a.is_const and b.is_const:
        return const(a.value / b.value)
    if _is(a, 0.0):
        return const(0.0)
    if _is(b, 1.0):
        return a
    return Expr("/", (a, b))


def power(a, b) -> Expr:
    a, b = as_expr(a), as_expr(b)
    if b.is_const and b.value == 1.0:
        return a
    if b.is_const and b.value == 2.0:
        return mul(a, a)
    return func("pow", a, b)


def _cmp(op: str, a, b) -> Expr:
    return Expr(op, (as_expr(a), as_expr(b)))


def func(name: str, *args) -> Expr:
    xs = tuple(as_expr(a) for a in args)
    if all(x.is_const for x in xs):
        return const(_PY_EVAL[name](*(x.value for x in xs)))
    return Expr(name, xs)


def where(cond: Expr, a, b) -> Expr:
    """``a`` where ``cond`` holds, else ``b`` (a branch; prefer smooth forms inside stiff models)."""
    if cond.op not in _COMPARE:
        raise TypeError("where() needs a comparison such as x > 0 as its condition")
    return Expr("where", (cond, as_expr(a), as_expr(b)))


def sqrt(x): return func("sqrt", x)
def exp(x): return func("exp", x)
def log(x): return func("log", x)
def tanh(x): return func("tanh", x)
def sin(x): return func("sin", x)
def cos(x): return func("cos", x)
def tan(x): return func("tan", x)
def atan(x): return func("atan", x)
def asin(x): return func("asin", x)
def acos(x): return func("acos", x)
def sinh(x): return func("sinh", x)
def cosh(x): return func("cosh", x)
def asinh(x): return func("asinh", x)
def fabs(x): return func("abs", x)
def sign(x): return func("sign", x)
def atan2(y, x): return func("atan2", y, x)
def fmin(a, b): return func("min", a, b)
def fmax(a, b): return func("max", a, b)


def clamp(x, lo, hi) -> Expr:
    return fmin(fmax(x, lo), hi)


# -- smooth helpers used by several components (one definition each) -----------------------
def smooth_abs(x, eps) -> Expr:
    """|x| ≈ sqrt(x² + eps²) − eps … kept ≥ 0 and C¹."""
    return sqrt(x * x + as_expr(eps) * eps)


def smooth_pos(x, eps) -> Expr:
    """max(x, 0) smoothed over a band eps: (x + sqrt(x² + eps²))/2."""
    return 0.5 * (x + sqrt(x * x + as_expr(eps) * eps))


def signed_sqrt(dp, dp_lam) -> Expr:
    """Turbulent orifice law with a laminar transition: dp/(dp² + dp_lam²)^(1/4).

    Equals sign(dp)·sqrt(|dp|) for |dp| ≫ dp_lam and is linear (slope 1/sqrt(dp_lam)) near
    zero, so the flow q = K·signed_sqrt(dp) has a finite derivative (seed 004 eq. 3 with
    the usual laminar regularisation).
    """
    return dp / sqrt(sqrt(dp * dp + as_expr(dp_lam) * dp_lam))


# -- printing ---------------------------------------------------------------------------
_PY_EVAL = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "tanh": math.tanh, "sin": math.sin,
    "cos": math.cos, "tan": math.tan, "atan": math.atan, "asin": math.asin, "acos": math.acos,
    "sinh": math.sinh, "cosh": math.cosh, "asinh": math.asinh,
    "abs": abs, "sign": lambda v: (v > 0) - (v < 0), "atan2": math.atan2, "min": min, "max": max,
    "pow": math.pow,
}
_C_NAMES = {"sqrt": "sqrt", "exp": "exp", "log": "log", "tanh": "hy_tanh", "sin": "sin", "cos": "cos",
            "tan": "tan", "atan": "atan", "asin": "asin", "acos": "acos", "sinh": "sinh", "cosh": "cosh",
            "asinh": "asinh", "abs": "fabs", "sign": "hy_sign", "atan2": "atan2", "min": "fmin", "max": "fmax",
            "pow": "pow"}
_NP_NAMES = {"sqrt": "np.sqrt", "exp": "np.exp", "log": "np.log", "tanh": "np.tanh", "sin": "np.sin",
             "cos": "np.cos", "tan": "np.tan", "atan": "np.arctan", "asin": "np.arcsin",
             "acos": "np.arccos", "sinh": "np.sinh", "cosh": "np.cosh", "asinh": "np.arcsinh", "abs": "np.abs",
             "sign": "np.sign", "atan2": "np.arctan2", "min": "np.minimum", "max": "np.maximum",
             "pow": "np.power"}


def _fmt_num(v: float) -> str:
    if v == int(v) and abs(v) < 1e15:
        return f"{v:.1f}"
    return repr(v)


def _print(e: Expr, names: dict, fn_names: dict, where_fmt: str) -> str:
    """Print with full parenthesisation of binary nodes (clear and safe)."""
    op = e.op
    if op == "const":
        v = e.args[0]
        s = _fmt_num(v)
        return f"({s})" if v < 0 else s
    if op == "sym":
        key = (e.args[0], e.args[1])
        return names(key) if callable(names) else names[key]
    if op in _BINARY:
        a, b = (_print(x, names, fn_names, where_fmt) for x in e.args)
        return f"({a} {op} {b})"
    if op in _COMPARE:
        a, b = (_print(x, names, fn_names, where_fmt) for x in e.args)
        return f"({a} {op} {b})"
    if op == "where":
        c, a, b = (_print(x, names, fn_names, where_fmt) for x in e.args)
        return where_fmt.format(c=c, a=a, b=b)
    args = ", ".join(_print(x, names, fn_names, where_fmt) for x in e.args)
    return f"{fn_names[op]}({args})"


def to_c(e: Expr, names) -> str:
    """C text; ``names`` maps (kind, name) → C identifier (a dict or a callable)."""
    return _print(as_expr(e), names, _C_NAMES, "(({c}) ? ({a}) : ({b}))")


def to_numpy(e: Expr, names) -> str:
    """NumPy text (works elementwise on arrays and on floats)."""
    return _print(as_expr(e), names, _NP_NAMES, "np.where({c}, {a}, {b})")


def to_python(e: Expr) -> str:
    """Readable text for messages and ``hydro check``."""
    return _print(as_expr(e), lambda k: k[1], _NP_NAMES, "where({c}, {a}, {b})").replace("np.", "")


def substitute(e: Expr, mapping: dict[tuple[str, str], Expr]) -> Expr:
    """Replace symbols by expressions (used to rename templates and patch models)."""
    if e.op == "sym":
        return mapping.get((e.args[0], e.args[1]), e)
    if e.op == "const":
        return e
    return Expr(e.op, tuple(substitute(a, mapping) if isinstance(a, Expr) else a for a in e.args))


def sum_exprs(items: Iterable) -> Expr:
    total = const(0.0)
    for it in items:
        total = add(total, it)
    return total


# -- symbolic derivatives (for the analytic Jacobian) ----------------------------------------
def partial(e: Expr, key: tuple[str, str]) -> Expr:
    """∂e/∂(symbol ``key``), treating every other symbol as independent.

    Branches differentiate branch-wise (``where``), comparisons have zero derivative, and
    min/max/abs follow the active branch — the usual almost-everywhere derivative.
    """
    op = e.op
    if op == "const":
        return ZERO
    if op == "sym":
        return ONE if (e.args[0], e.args[1]) == key else ZERO
    if op in _COMPARE:
        return ZERO
    if key not in _symbols_cached(e):
        return ZERO
    a = e.args
    if op == "+":
        return add(partial(a[0], key), partial(a[1], key))
    if op == "-":
        return sub(partial(a[0], key), partial(a[1], key))
    if op == "*":
        return add(mul(partial(a[0], key), a[1]), mul(a[0], partial(a[1], key)))
    if op == "/":
        da, db = partial(a[0], key), partial(a[1], key)
        if _is(db, 0.0):
            return div(da, a[1])
        return div(sub(mul(da, a[1]), mul(a[0], db)), mul(a[1], a[1]))
    if op == "where":
        return where(a[0], partial(a[1], key), partial(a[2], key))
    if op in ("min", "max"):
        cond = (a[0] <= a[1]) if op == "min" else (a[0] >= a[1])
        return where(cond, partial(a[0], key), partial(a[1], key))
    if op == "pow":
        base, ex = a
        db, de = partial(base, key), partial(ex, key)
        out = ZERO
        if not _is(db, 0.0):
            out = mul(mul(ex, power(base, sub(ex, 1.0))), db) if ex.is_const else \
                mul(mul(ex, div(e, base)), db)
        if not _is(de, 0.0):
            out = add(out, mul(mul(e, log(base)), de))
        return out
    if op == "atan2":
        y, x = a
        dy, dx = partial(y, key), partial(x, key)
        return div(sub(mul(x, dy), mul(y, dx)), add(mul(x, x), mul(y, y)))
    d = partial(a[0], key)
    if _is(d, 0.0):
        return ZERO
    x = a[0]
    outer = {
        "sqrt": lambda: div(0.5, e), "exp": lambda: e, "log": lambda: div(1.0, x),
        "tanh": lambda: sub(1.0, mul(e, e)), "sin": lambda: cos(x), "cos": lambda: mul(-1.0, sin(x)),
        "tan": lambda: add(1.0, mul(e, e)), "atan": lambda: div(1.0, add(1.0, mul(x, x))),
        "asin": lambda: div(1.0, sqrt(sub(1.0, mul(x, x)))),
        "acos": lambda: div(-1.0, sqrt(sub(1.0, mul(x, x)))),
        "sinh": lambda: cosh(x), "cosh": lambda: sinh(x), "asinh": lambda: div(1.0, sqrt(add(1.0, mul(x, x)))),
        "abs": lambda: sign(x), "sign": lambda: ZERO,
    }[op]()
    return mul(outer, d)


ZERO = const(0.0)
ONE = const(1.0)


def _symbols_cached(e: Expr) -> frozenset:
    return e.symbol_set
