"""``serial_chain``: a serial chain of rigid bodies on revolute joints, with cylinder ports.

Frames: world x horizontal, z up (gravity −z). Body i hangs on joint i, placed at
(jx_i, jz_i) in the frame of body i−1 (body 0 = ground); ``axis`` picks the joint axis in
the parent frame: −2 (default) is a planar luffing joint whose positive angle turns x toward
z (counter-clockwise in the x–z working plane), 3 a slewing joint about the vertical axis
carrying the following links in their vertical plane, ±1/±2/±3 any principal axis, 0 a rigid
(fixed) connection. Joint angles q_i and rates w_i are states; M(q)q̈ + V + G = τ (seed 002
eq. 1) is formed recursively (see ``recursive``).

Joint ports ``j1…j16`` (rotational): the chain imposes the joint rate w_i and angle q_i;
the torque other components apply at the joint is −(what they take from the node)
(dampers, springs, flexible connections, motors via a gearbox).

Actuator ports ``a1…a6`` (translational): cylinder k is attached at point
(act_ax_k, act_az_k) of body act_a_body_k and point (act_bx_k, act_bz_k) of body act_b_body_k
(0 = ground). The chain imposes the port position x = L_k − act_L0_k (L_k the distance
between the points, so ``act_L0`` is the pin-to-pin length at which the connected
``cylinder``'s x is 0, e.g. the retracted length l_0 of seed 000 Table 6) and velocity
dL_k/dt. The force F_k = −(what the others take from the port's node) pushes the points
apart and enters the joint torques through the Jacobian, τ_j = F_k ∂L_k/∂q_j (seed 002
eq. 4a; eq. 4b is dL/dt = J q̇). Connect the cylinder as ``rod: <port node>``, ``body: ground``.
"""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, Param, Port, R, StateSpec, T
from ..registry import register
from . import recursive as RC
from . import vec as V

MAX_JOINTS = 16
MAX_ACTUATORS = 6
_PER_BODY = ("jx", "jz", "m", "cx", "cz", "Iyy")
_ACT = ("act_ax", "act_az", "act_bx", "act_bz", "act_L0")


def _vp(name, unit, desc, default=(), structural=False, **kw):
    return Param(name, unit, list(default), desc, vector=True, structural=structural, **kw)


@register
class SerialChain(Component):
    type = "serial_chain"
    family = "multibody"
    description = "Serial chain of rigid bodies on revolute joints, recursive dynamics, cylinder ports"
    source = "seed 002 eqs. 1, 4a–4b; seed 000 §3.1 (Fig. 4); Featherstone RNEA/CRBA"
    ports = tuple(Port(f"j{i}", R, f"joint {i} (imposed angle and rate; external torque)", optional=True)
                  for i in range(1, MAX_JOINTS + 1)) + tuple(
        Port(f"a{k}", T, f"actuator {k} (imposed length − act_L0 and its rate; cylinder force)", optional=True)
        for k in range(1, MAX_ACTUATORS + 1))
    parameters = (
        _vp("axis", "1", "joint axis code per body: −2 planar (default), 3 slewing, ±1/±2/±3, 0 fixed",
            structural=True),
        _vp("jx", "m", "joint i position x in the parent frame", ()),
        _vp("jz", "m", "joint i position z in the parent frame", ()),
        _vp("m", "kg", "body masses", (), min=0.0, bounds=(1.0, 1e5)),
        _vp("cx", "m", "COG x in the body frame (seed 000 Table 7 x_i)"),
        _vp("cz", "m", "COG z in the body frame (seed 000 Table 7 z_i)"),
        _vp("Iyy", "kg*m^2", "inertia about the body y axis through the COG (planar joints)", min=0.0),
        _vp("Ixx", "kg*m^2", "inertia about the body x axis through the COG (default 0: slender link)", min=0.0),
        _vp("Izz", "kg*m^2", "inertia about the body z axis through the COG (default Iyy)", min=0.0),
        Param("g", "m/s^2", 9.81, "gravitational acceleration (acts along −z)", min=0.0),
        _vp("act_a_body", "1", "body carrying point a of each actuator (0 = ground)", structural=True),
        _vp("act_b_body", "1", "body carrying point b of each actuator (0 = ground)", structural=True),
        _vp("act_ax", "m", "actuator point a, x in its body frame"),
        _vp("act_az", "m", "actuator point a, z in its body frame"),
        _vp("act_bx", "m", "actuator point b, x in its body frame"),
        _vp("act_bz", "m", "actuator point b, z in its body frame"),
        _vp("act_L0", "m", "pin-to-pin length at which the connected cylinder's x = 0", min=0.0),
    )
    states = tuple(StateSpec(f"q{i}", "rad", f"joint {i} angle", nominal=1e-3) for i in range(1, MAX_JOINTS + 1)) \
        + tuple(StateSpec(f"w{i}", "rad/s", f"joint {i} rate", nominal=1e-3) for i in range(1, MAX_JOINTS + 1))

    def check(self, values):
        n = len(values["m"])
        out = []
        if not 1 <= n <= MAX_JOINTS:
            out.append(f"give between 1 and {MAX_JOINTS} bodies (m has {n} entries)")
        for name in _PER_BODY + ("axis",):
            if name != "axis" or values["axis"]:
                if len(values[name]) != n:
                    out.append(f"{name} needs one entry per body ({n}), has {len(values[name])}")
        for name in ("Ixx", "Izz"):
            if values[name] and len(values[name]) != n:
                out.append(f"{name} needs one entry per body ({n}) or none")
        if any(int(a) not in (0, 1, 2, 3, -1, -2, -3) for a in values["axis"]):
            out.append("axis codes are 0 (fixed), ±1 (x), ±2 (y), ±3 (z)")
        na = len(values["act_a_body"])
        if na > MAX_ACTUATORS:
            out.append(f"at most {MAX_ACTUATORS} actuators")
        for name in _ACT + ("act_b_body",):
            if len(values[name]) != na:
                out.append(f"{name} needs one entry per actuator ({na}), has {len(values[name])}")
        for name in ("act_a_body", "act_b_body"):
            if any(not 0 <= int(b) <= n for b in values[name]):
                out.append(f"{name} entries must be body numbers 0…{n}")
        if any(int(a) == int(b) for a, b in zip(values["act_a_body"], values["act_b_body"])):
            out.append("an actuator must join two different bodies")
        return out

    def equations(self, c):
        bodies = _bodies(c)
        L = V.Namer(c)
        kin = RC.forward(L, bodies, c.p.g)
        moving = [i for i, b in enumerate(bodies, start=1) if b.axis]
        for i in range(1, len(bodies) + 1):
            if c.connected(f"j{i}") and i not in moving:
                raise ValueError(f"port j{i} is connected but joint {i} is fixed (axis 0)")
        bias = RC.bias_forces(L, bodies, kin)
        M = RC.mass_matrix(L, bodies, kin)
        tau_act = _actuators(c, L, kin, moving)
        tau = {}
        for i in moving:
            ext = -c.node_through(f"j{i}") if c.connected(f"j{i}") else 0.0
            tau[i] = L(f"tau{i}", tau_act.get(i, 0.0) + ext, "N*m")
            if c.connected(f"j{i}"):
                c.impose(f"j{i}", bodies[i - 1].w, position=bodies[i - 1].q)
        qdd = RC.ldlt_solve(L, M, moving, {i: tau[i] - bias[i] for i in moving})
        for i in moving:
            c.der(f"q{i}", c.state(f"w{i}"))
            c.der(f"w{i}", qdd[i])


def _bodies(c) -> list[RC.Body]:
    p = c.p
    m = p.m
    n = len(m)
    axis = [int(a) for a in c.value("axis")] or [-2] * n
    Iyy = p.Iyy
    Ixx = p.Ixx if c.value("Ixx") else [0.0] * n
    Izz = p.Izz if c.value("Izz") else Iyy
    jx, jz, cx, cz = p.jx, p.jz, p.cx, p.cz
    out = []
    for i in range(n):
        b = RC.Body(axis[i], (jx[i], 0.0, jz[i]), m[i], (cx[i], 0.0, cz[i]), (Ixx[i], Iyy[i], Izz[i]))
        if axis[i]:
            b.q, b.w = c.state(f"q{i + 1}"), c.state(f"w{i + 1}")
        out.append(b)
    return out


def _actuators(c, L: V.Namer, kin: RC.Kinematics, moving: list[int]) -> dict[int, object]:
    """Cylinder lengths/rates imposed on ports a_k and generalized forces F_k ∂L_k/∂q_j."""
    p = c.p
    na = len(c.value("act_a_body"))
    if not na:
        return {}
    ba = [int(b) for b in c.value("act_a_body")]
    bb = [int(b) for b in c.value("act_b_body")]
    ax, az, bx, bz, L0 = p.act_ax, p.act_az, p.act_bx, p.act_bz, p.act_L0
    tau: dict[int, object] = {}
    for k in range(na):
        n = k + 1
        pa = L.vec(f"pa{n}", V.add(kin.o[ba[k]], V.matvec(kin.R[ba[k]], (ax[k], 0.0, az[k]))), "m")
        pb = L.vec(f"pb{n}", V.add(kin.o[bb[k]], V.matvec(kin.R[bb[k]], (bx[k], 0.0, bz[k]))), "m")
        d = V.sub(pb, pa)
        length = L(f"L{n}", E.sqrt(V.dot(d, d)), "m")
        c.guard(length <= 1e-9, f"actuator {n}: attachment points coincide")
        u = L.vec(f"u{n}", V.scale(1.0 / length, d))
        va = V.add(kin.v[ba[k]], V.cross(kin.omega[ba[k]], V.sub(pa, kin.o[ba[k]])))
        vb = V.add(kin.v[bb[k]], V.cross(kin.omega[bb[k]], V.sub(pb, kin.o[bb[k]])))
        ldot = L(f"Ldot{n}", V.dot(u, V.sub(vb, va)), "m/s")
        if not c.connected(f"a{n}"):
            continue
        c.impose(f"a{n}", ldot, position=length - L0[k])
        force = L(f"F{n}", -c.node_through(f"a{n}"), "N")
        lo, hi = min(ba[k], bb[k]), max(ba[k], bb[k])
        point = pb if bb[k] > ba[k] else pa
        sign = 1.0 if bb[k] > ba[k] else -1.0
        for j in moving:
            if lo < j <= hi:   # joints between the two bodies change the length (closed chain)
                dL = L(f"dL{n}_dq{j}", sign * V.dot(u, V.cross(kin.a[j], V.sub(point, kin.o[j]))), "m/rad")
                tau[j] = tau.get(j, 0.0) + force * dL
    return {j: L(f"tau_act{j}", t, "N*m") for j, t in tau.items()}
