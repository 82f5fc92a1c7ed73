"""3-vector and 3×3-matrix algebra on expressions (tuples of Expr or floats).

Constants fold through :mod:`hydrocli.model.expr`, so the zeros of planar chains vanish
from the generated code. :class:`Namer` names every non-trivial intermediate once with
``c.let`` so recursive algorithms produce linear-size code, never exponential trees.
"""
from __future__ import annotations

from ...model import expr as E

ZERO = (0.0, 0.0, 0.0)
EYE = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _trivial(e) -> bool:
    return isinstance(e, (int, float)) or e.op in ("const", "sym")


class Namer:
    """``L(name, expr)`` → ``c.let(name, expr)`` unless the expression is a constant or symbol."""

    def __init__(self, c):
        self.c = c

    def __call__(self, name: str, e, unit: str = ""):
        if _trivial(e):
            return e.value if not isinstance(e, (int, float)) and e.op == "const" else e
        return self.c.let(name, e, unit)

    def vec(self, name: str, v, unit: str = ""):
        return tuple(self(f"{name}_{k}", x, unit) for k, x in zip("xyz", v))

    def mat(self, name: str, m, unit: str = ""):
        return tuple(tuple(self(f"{name}_{i}{j}", m[i][j], unit) for j in range(3)) for i in range(3))

    def sym(self, name: str, m, unit: str = ""):
        """Name a symmetric matrix's six distinct entries once."""
        d = {(i, j): self(f"{name}_{i}{j}", m[i][j], unit) for i in range(3) for j in range(i, 3)}
        return tuple(tuple(d[(min(i, j), max(i, j))] for j in range(3)) for i in range(3))


def add(a, b): return tuple(x + y for x, y in zip(a, b))
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def scale(s, a): return tuple(s * x for x in a)
def dot(a, b): return E.sum_exprs(x * y for x, y in zip(a, b)) if _any_expr(a, b) else sum(x * y for x, y in zip(a, b))


def _any_expr(*vs) -> bool:
    return any(isinstance(x, E.Expr) for v in vs for x in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def matvec(m, v):
    return tuple(dot(row, v) for row in m)


def matmul(a, b):
    cols = tuple(tuple(b[k][j] for k in range(3)) for j in range(3))
    return tuple(tuple(dot(a[i], cols[j]) for j in range(3)) for i in range(3))


def transpose(m):
    return tuple(tuple(m[j][i] for j in range(3)) for i in range(3))


def madd(a, b):
    return tuple(tuple(a[i][j] + b[i][j] for j in range(3)) for i in range(3))


def shift_inertia(m, r):
    """Parallel-axis term m·(|r|²·1 − r rᵀ) (Steiner)."""
    rr = dot(r, r)
    return tuple(tuple(m * ((rr if i == j else 0.0) - r[i] * r[j]) for j in range(3)) for i in range(3))


def rotation(axis: int, angle):
    """Rotation by ``angle`` about ±x (±1), ±y (±2) or ±z (±3) (right-hand rule)."""
    k = abs(axis) - 1
    s = (1.0 if axis > 0 else -1.0) * E.sin(angle)
    c = E.cos(angle)
    m = [[0.0] * 3 for _ in range(3)]
    i, j = (k + 1) % 3, (k + 2) % 3
    m[k][k] = 1.0
    m[i][i], m[j][j] = c, c
    m[i][j], m[j][i] = -1.0 * s, s
    return tuple(tuple(r) for r in m)


def unit_axis(axis: int):
    k = abs(axis) - 1
    return tuple((1.0 if axis > 0 else -1.0) if n == k else 0.0 for n in range(3))
