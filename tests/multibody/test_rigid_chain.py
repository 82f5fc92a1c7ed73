"""Rigid serial chains against closed forms: pendulum period, energy conservation (planar and
with a slewing joint), static gravity torques (seed 002 eq. 1 with q̇ = q̈ = 0)."""
import numpy as np
import pytest

from _chain_util import build, run, state

G = 9.81


def test_single_pendulum_small_angle_period():
    # compound pendulum: T = 2π sqrt(I_O/(m g d)), I_O = I_G + m d²
    m, d, ig = 3.0, 0.4, 0.05
    model = build(f"""
name: pendulum
components:
  arm: {{type: serial_chain, m: [{m}], jx: [0], jz: [0], cx: [{d}], cz: [0], Iyy: [{ig}]}}
initial: {{arm.q1: "-88 deg"}}
""")
    t, tr = run(model, 6.0, n=6001, rtol=1e-9)
    q = state(model, tr, "arm.q1") + np.pi / 2
    up = np.where((q[:-1] < 0) & (q[1:] >= 0))[0]
    tc = t[up] - q[up] * (t[up + 1] - t[up]) / (q[up + 1] - q[up])   # interpolated crossings
    period = np.mean(np.diff(tc))
    expected = 2 * np.pi * np.sqrt((ig + m * d * d) / (m * G * d))
    assert len(tc) >= 3
    assert period == pytest.approx(expected, rel=0.01)


DOUBLE = """
name: double_pendulum
components:
  arm:
    type: serial_chain
    m: [2.0, 1.5]
    jx: [0, 1.0]
    jz: [0, 0]
    cx: [0.5, 0.35]
    cz: [0, 0.05]
    Iyy: [0.2, 0.08]
initial: {arm.q1: "20 deg", arm.q2: "-50 deg", arm.w1: 1.0}
"""


def _planar_energy(q1, q2, w1, w2):
    m1, m2, i1, i2, l1 = 2.0, 1.5, 0.2, 0.08, 1.0
    c1 = np.array([0.5, 0.0])
    c2 = np.array([0.35, 0.05])

    def rot(a, v):
        return np.array([np.cos(a) * v[0] - np.sin(a) * v[1], np.sin(a) * v[0] + np.cos(a) * v[1]])

    def drot(a, v):  # d/da rot(a) v
        return np.array([-np.sin(a) * v[0] - np.cos(a) * v[1], np.cos(a) * v[0] - np.sin(a) * v[1]])

    g1 = rot(q1, c1)
    v1 = drot(q1, c1) * w1
    g2 = rot(q1, np.array([l1, 0.0])) + rot(q1 + q2, c2)
    v2 = drot(q1, np.array([l1, 0.0])) * w1 + drot(q1 + q2, c2) * (w1 + w2)
    kin = 0.5 * m1 * (v1 @ v1) + 0.5 * i1 * w1 ** 2 + 0.5 * m2 * (v2 @ v2) + 0.5 * i2 * (w1 + w2) ** 2
    return kin + G * (m1 * g1[1] + m2 * g2[1]), kin


def test_double_pendulum_conserves_energy():
    model = build(DOUBLE)
    t, tr = run(model, 3.0, n=301, rtol=1e-10)
    q1, q2, w1, w2 = (state(model, tr, f"arm.{s}") for s in ("q1", "q2", "w1", "w2"))
    e, kin = np.array([_planar_energy(*v) for v in zip(q1, q2, w1, w2)]).T
    assert kin.max() > 5.0                     # it really moves (chaotic regime)
    assert np.max(np.abs(e - e[0])) / kin.max() < 1e-4


SLEWING = """
name: slewing_arm
components:
  arm:
    type: serial_chain
    axis: [3, -2, -2]
    m: [50.0, 8.0, 3.0]
    jx: [0, 0.3, 1.2]
    jz: [0, 0.8, 0]
    cx: [0.1, 0.6, 0.4]
    cz: [0.2, 0.05, 0]
    Ixx: [4.0, 0.1, 0.02]
    Iyy: [3.0, 1.1, 0.2]
    Izz: [5.0, 1.0, 0.19]
initial: {arm.q2: "30 deg", arm.q3: "-20 deg", arm.w1: 1.5, arm.w2: 0.5}
"""


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _rny(a):  # rotation about −y by a
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, -s], [0, 1.0, 0], [s, 0, c]])


def _slewing_energy(q, w):
    """Energy of the slewing arm from an independent forward kinematics (numeric velocities)."""
    m = [50.0, 8.0, 3.0]
    r = [np.zeros(3), np.array([0.3, 0, 0.8]), np.array([1.2, 0, 0])]
    cg = [np.array([0.1, 0, 0.2]), np.array([0.6, 0, 0.05]), np.array([0.4, 0, 0])]
    inert = [np.diag([4.0, 3.0, 5.0]), np.diag([0.1, 1.1, 1.0]), np.diag([0.02, 0.2, 0.19])]

    def frames(qq):
        rots = [_rz(qq[0]), _rz(qq[0]) @ _rny(qq[1]), _rz(qq[0]) @ _rny(qq[1]) @ _rny(qq[2])]
        org = [np.zeros(3)]
        org.append(org[0] + rots[0] @ r[1])
        org.append(org[1] + rots[1] @ r[2])
        return rots, [o + R @ c for o, R, c in zip(org, rots, cg)]

    rots, gs = frames(q)
    h = 1e-6
    rots_h, gs_h = frames(q + h * w)
    e = kin = 0.0
    for k in range(3):
        v = (gs_h[k] - gs[k]) / h
        wx = (rots_h[k] - rots[k]) / h @ rots[k].T       # skew(ω)
        om = np.array([wx[2, 1], wx[0, 2], wx[1, 0]])
        iw = rots[k] @ inert[k] @ rots[k].T
        t = 0.5 * m[k] * v @ v + 0.5 * om @ iw @ om
        e, kin = e + t + m[k] * G * gs[k][2], kin + t
    return e, kin


def test_slewing_chain_conserves_energy():
    model = build(SLEWING)
    t, tr = run(model, 2.0, n=201, rtol=1e-10)
    q = np.column_stack([state(model, tr, f"arm.q{i}") for i in (1, 2, 3)])
    w = np.column_stack([state(model, tr, f"arm.w{i}") for i in (1, 2, 3)])
    e, kin = np.array([_slewing_energy(qq, ww) for qq, ww in zip(q, w)]).T
    assert np.ptp(q[:, 1]) + np.ptp(q[:, 2]) > 0.5
    # numeric velocities in the reference carry ~1e-6 relative error
    assert np.max(np.abs(e - e[0])) / kin.max() < 1e-4


TWO_LINK = """
name: two_link
inputs: {T1: {unit: "N*m"}, T2: {unit: "N*m"}}
components:
  arm:
    type: serial_chain
    ports: {j1: shoulder, j2: elbow}
    m: [12.0, 5.0]
    jx: [0, 1.5]
    jz: [0, 0]
    cx: [0.7, 0.6]
    cz: [0.1, 0]
    Iyy: [2.0, 0.6]
  m1: {type: torque_source, ports: {a: shoulder, tau: T1}}
  m2: {type: torque_source, ports: {a: elbow, tau: T2}}
initial: {arm.q1: 0.4, arm.q2: -0.9}
"""


def _gravity_torques(q1, q2):
    # τ_i = ∂(potential)/∂q_i for COGs at (0.7, 0.1) on link 1 and (0.6, 0) on link 2
    g1 = 12.0 * G * (0.7 * np.cos(q1) - 0.1 * np.sin(q1))
    g2 = 5.0 * G * 0.6 * np.cos(q1 + q2)
    return g1 + g2 + 5.0 * G * 1.5 * np.cos(q1), g2


def test_static_torque_balance_two_link_arm():
    from hydrocli.solve.simulate import InputTable
    model = build(TWO_LINK)
    tau1, tau2 = _gravity_torques(0.4, -0.9)
    x0 = model.x0
    vs = model.evaluate_along(np.zeros(1), x0[None, :], np.array([[tau1, tau2]]))
    assert vs["arm.bias1"][0] == pytest.approx(tau1, rel=1e-12)
    assert vs["arm.bias2"][0] == pytest.approx(tau2, rel=1e-12)
    # holding torques equal to the analytic gravity torques keep the arm still
    t, tr = run(model, 1.0, n=11, inputs=InputTable(np.array([0.0]), np.array([[tau1, tau2]])))
    assert np.max(np.abs(tr.X[:, :2] - x0[:2])) < 1e-9
    # 1 % less torque on the elbow and it falls
    t, tr = run(model, 1.0, n=11, inputs=InputTable(np.array([0.0]), np.array([[tau1, 0.99 * tau2]])))
    assert state(model, tr, "arm.q2")[-1] < -0.9 - 1e-3
