"""Recursive rigid-body dynamics of a serial chain, unrolled at build time into expressions.

Equations of motion M(q)·q̈ + V(q, q̇) + G(q) = τ (seed 002 eq. 1) are formed as

* forward kinematics from the base out (rotations, joint origins o_i, world joint axes a_i,
  angular velocities ω_i, joint-origin velocities);
* recursive Newton–Euler (RNEA, Featherstone 2008 §5.3, here in world coordinates) with
  q̈ = 0 and a base acceleration of +g·ẑ, giving the bias b = V + G joint by joint;
* the composite-rigid-body algorithm (CRBA, Featherstone §6.2): the subtree of joint i
  (composite mass m_i^C, first moment h_i = Σ m_k g_k, inertia J_i about the world origin)
  accelerated at unit rate about a_i through o_i needs the wrench
  f_i = m_i^C (o_i × a_i) + a_i × h_i,  n_i = J_i a_i + h_i × (o_i × a_i)  (about the origin),
  so M_ji = a_j · (n_i − o_j × f_i) for ancestors j ≤ i;
* an unrolled LDLᵀ factorisation and solve of M q̈ = τ − b (no matrix inverse).

Every intermediate is named once (``Namer``), so code size grows as O(n) for kinematics
and RNEA, O(n²) for M and O(n³) (small) for the factorisation.
"""
from __future__ import annotations

from dataclasses import dataclass

from . import vec as V


@dataclass
class Body:
    """One body and the joint that connects it to the previous body (or the ground).

    ``axis``: ±1/±2/±3 revolute about the parent's ±x/±y/±z, 0 fixed; ``r``: joint position in
    the parent frame; ``c``: centre of gravity in the body frame; ``I``: principal inertias
    (Ixx, Iyy, Izz) about the COG in body axes; ``q``, ``w``: joint angle and rate.
    """

    axis: int
    r: tuple
    m: object
    c: tuple
    I: tuple
    q: object = 0.0
    w: object = 0.0


@dataclass
class Kinematics:
    R: list          # world rotation of each body (index 0 = ground)
    o: list          # world position of each joint origin
    a: list          # world joint axis (None for fixed joints)
    omega: list
    v: list          # world velocity of each joint origin
    alpha: list      # angular acceleration at q̈ = 0
    acc: list        # joint-origin acceleration at q̈ = 0, with gravity as base acceleration
    g: list          # world COG position
    Iw: list         # world inertia tensor about the COG


def forward(L: V.Namer, bodies: list[Body], gravity) -> Kinematics:
    k = Kinematics([V.EYE], [V.ZERO], [None], [V.ZERO], [V.ZERO], [V.ZERO], [(0.0, 0.0, gravity)],
                   [V.ZERO], [None])
    for i, b in enumerate(bodies, start=1):
        Rp, op, wp, ap = k.R[i - 1], k.o[i - 1], k.omega[i - 1], k.alpha[i - 1]
        d = L.vec(f"d{i}", V.matvec(Rp, b.r), "m")
        o = L.vec(f"o{i}", V.add(op, d), "m")
        if b.axis:
            a = L.vec(f"a{i}", V.matvec(Rp, V.unit_axis(b.axis)))
            R = L.mat(f"R{i}", V.matmul(Rp, V.rotation(b.axis, b.q)))
            aw = V.scale(b.w, a)
            w = L.vec(f"omega{i}", V.add(wp, aw), "rad/s")
            alpha = L.vec(f"alpha{i}", V.add(ap, V.cross(wp, aw)), "rad/s^2")
        else:
            a, R, w, alpha = None, Rp, wp, ap
        v = L.vec(f"vo{i}", V.add(k.v[i - 1], V.cross(wp, d)), "m/s")
        acc = L.vec(f"acco{i}", V.add(k.acc[i - 1], V.add(V.cross(ap, d), V.cross(wp, V.cross(wp, d)))),
                    "m/s^2")
        rho = L.vec(f"rho{i}", V.matvec(R, b.c), "m")
        Iw = L.sym(f"Iw{i}", V.matmul(V.matmul(R, _diag(b.I)), V.transpose(R)), "kg*m^2")
        for lst, val in ((k.R, R), (k.o, o), (k.a, a), (k.omega, w), (k.v, v), (k.alpha, alpha),
                         (k.acc, acc), (k.Iw, Iw)):
            lst.append(val)
        k.g.append(L.vec(f"g{i}", V.add(o, rho), "m"))
    return k


def _diag(I):
    return tuple(tuple(I[i] if i == j else 0.0 for j in range(3)) for i in range(3))


def bias_forces(L: V.Namer, bodies: list[Body], k: Kinematics) -> dict[int, object]:
    """RNEA with q̈ = 0: b_i = V_i + G_i for every moving joint i (seed 002 eq. 1)."""
    n = len(bodies)
    f_next, n_next, o_next = V.ZERO, V.ZERO, None
    out = {}
    for i in range(n, 0, -1):
        b = bodies[i - 1]
        rho = V.sub(k.g[i], k.o[i])
        acc_g = V.add(k.acc[i], V.add(V.cross(k.alpha[i], rho), V.cross(k.omega[i], V.cross(k.omega[i], rho))))
        F = V.scale(b.m, acc_g)
        N = V.add(V.matvec(k.Iw[i], k.alpha[i]), V.cross(k.omega[i], V.matvec(k.Iw[i], k.omega[i])))
        f = L.vec(f"f{i}", V.add(F, f_next), "N")
        nn = V.add(N, V.cross(rho, F))
        if o_next is not None:
            nn = V.add(nn, V.add(n_next, V.cross(V.sub(o_next, k.o[i]), f_next)))
        nn = L.vec(f"n{i}", nn, "N*m")
        if b.axis:
            out[i] = L(f"bias{i}", V.dot(k.a[i], nn), "N*m")
        f_next, n_next, o_next = f, nn, k.o[i]
    return out


def mass_matrix(L: V.Namer, bodies: list[Body], k: Kinematics) -> dict[tuple[int, int], object]:
    """CRBA: M[(j, i)] for moving joints j ≤ i (symmetric)."""
    n = len(bodies)
    mC, h, J = 0.0, V.ZERO, ((0.0,) * 3,) * 3
    cols = {}
    for i in range(n, 0, -1):
        b = bodies[i - 1]
        mC = L(f"mC{i}", b.m + mC, "kg")
        h = L.vec(f"hC{i}", V.add(V.scale(b.m, k.g[i]), h), "kg*m")
        J = L.sym(f"JC{i}", V.madd(V.madd(k.Iw[i], V.shift_inertia(b.m, k.g[i])), J), "kg*m^2")
        if b.axis:
            a, o = k.a[i], k.o[i]
            oxa = V.cross(o, a)
            f = L.vec(f"fu{i}", V.add(V.scale(mC, oxa), V.cross(a, h)))
            nO = L.vec(f"nu{i}", V.add(V.matvec(J, a), V.cross(h, oxa)))
            cols[i] = (f, nO)
    M = {}
    for i, (f, nO) in cols.items():
        for j in cols:
            if j <= i:
                M[(j, i)] = L(f"M{j}_{i}", V.dot(k.a[j], V.sub(nO, V.cross(k.o[j], f))), "kg*m^2")
    return M


def ldlt_solve(L: V.Namer, M: dict, idx: list[int], rhs: dict[int, object]) -> dict[int, object]:
    """Solve M x = rhs with an unrolled LDLᵀ factorisation (M symmetric positive definite)."""
    def m(i, j):
        return M[(min(i, j), max(i, j))]
    Lf, D = {}, {}
    for jj, j in enumerate(idx):
        D[j] = L(f"D{j}", m(j, j) - _sum(Lf[(j, k)] ** 2 * D[k] for k in idx[:jj]))
        for i in idx[jj + 1:]:
            Lf[(i, j)] = L(f"L{i}_{j}", (m(i, j) - _sum(Lf[(i, k)] * Lf[(j, k)] * D[k] for k in idx[:jj])) / D[j])
    y = {}
    for ii, i in enumerate(idx):
        y[i] = L(f"y{i}", rhs[i] - _sum(Lf[(i, k)] * y[k] for k in idx[:ii]))
    x = {}
    for ii in range(len(idx) - 1, -1, -1):
        i = idx[ii]
        x[i] = L(f"qdd{i}", y[i] / D[i] - _sum(Lf[(k, i)] * x[k] for k in idx[ii + 1:]), "rad/s^2")
    return x


def _sum(items):
    total = 0.0
    for it in items:
        total = total + it
    return total
