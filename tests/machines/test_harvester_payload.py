"""Seed 002 harvester with its processing head on a free 2-axis Hooke joint (issue 4): with the
arm hydraulically held, the head swings with the compound-pendulum period 2π·sqrt(I_O/(m g d)),
and the stick joint torque equals an independent planar Newton–Euler balance of stick + head
about the stick joint, i.e. the swing is felt as a reaction torque at the stick joint."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_experiment_file
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]
G = 9.81


@pytest.fixture(scope="module")
def swing():
    model = build_model(load_netlist(ROOT / "machines" / "harvester_payload.yaml"))
    exp = load_experiment_file(ROOT / "experiments" / "harvester" / "head_swing.yaml", model)
    x0 = model.x0.copy()
    x0[model.state_index("arm.q4")] += np.radians(3.0)          # 3° off the hanging pose, in plane
    p = model.param_vector()
    tr = simulate(model, exp.inputs, exp.t_out, p=p, x0=x0, opts=SolverOptions(rtol=1e-7))
    u = np.zeros((exp.t_out.size, len(model.input_names)))
    vs = model.evaluate_along(exp.t_out, tr.X, u, p)
    return model, exp.t_out, tr, vs, p


def _vec(model, p, name):
    n = 5
    return np.array([p[model.param_index(f"arm.{name}[{i}]")] for i in range(n)])


def test_head_swing_period_matches_compound_pendulum(swing):
    model, t, tr, _, p = swing
    m, cz, iyy = _vec(model, p, "m"), _vec(model, p, "cz"), _vec(model, p, "Iyy")
    # pivot O = Hooke centre; cross (body 4) has its COG at O, head (body 5) at d below O
    d = -cz[4]
    i_o = iyy[3] + iyy[4] + m[4] * d ** 2
    period = 2 * np.pi * np.sqrt(i_o / (m[4] * G * d))
    q = lambda k: tr.X[:, model.state_index(f"arm.q{k}")]
    assert np.ptp(q(2)) < np.radians(0.05) and np.ptp(q(3)) < np.radians(0.05)   # arm held
    assert np.ptp(q(5)) < 1e-9                                                   # in-plane swing
    phi = q(2) + q(3) + q(4)                                 # absolute head angle
    s = phi - phi.mean()
    z = np.where((s[:-1] < 0) & (s[1:] >= 0))[0]
    tz = t[z] - s[z] * (t[z + 1] - t[z]) / (s[z + 1] - s[z])
    assert len(tz) >= 3
    assert np.mean(np.diff(tz)) == pytest.approx(period, rel=0.02)
    assert np.ptp(s) == pytest.approx(2 * np.radians(3.0), rel=0.05)            # undamped: free swing


def test_head_swing_loads_the_stick_joint(swing):
    model, t, tr, vs, p = swing
    st = lambda n: tr.X[:, model.state_index(f"arm.{n}")]
    m, cx, cz, iyy = (_vec(model, p, k) for k in ("m", "cx", "cz", "Iyy"))
    jx, jz = _vec(model, p, "jx"), _vec(model, p, "jz")
    assert np.max(np.abs(st("w1"))) < 1e-6                # swing joint still: planar motion
    # planar kinematics in the working plane (x out, z up; angles counter-clockwise)
    th = {2: st("q2"), 3: st("q2") + st("q3"), 4: st("q2") + st("q3") + st("q4")}
    om = {2: st("w2"), 3: st("w2") + st("w3"), 4: st("w2") + st("w3") + st("w4")}
    al = {2: vs["arm.qdd2"], 3: vs["arm.qdd2"] + vs["arm.qdd3"],
          4: vs["arm.qdd2"] + vs["arm.qdd3"] + vs["arm.qdd4"]}

    def rot(k, v):
        c, s = np.cos(th[k]), np.sin(th[k])
        return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    def acc(k, a_base, d):                                # a = a_O + α × d − ω² d
        return a_base + al[k] * np.stack([-d[1], d[0]]) - om[k] ** 2 * d

    zero = np.zeros((2, t.size))
    j2 = np.array([jx[1], jz[1]])[:, None] + zero
    d23 = rot(2, (jx[2], jz[2]))
    j3, a_j3 = j2 + d23, acc(2, zero, d23)
    d3p = rot(3, (jx[3], jz[3]))
    a_o = acc(3, a_j3, d3p)                               # Hooke centre O
    bodies = {3: (rot(3, (cx[2], cz[2])), acc(3, a_j3, rot(3, (cx[2], cz[2]))), 3),
              4: (d3p, a_o, 4),
              5: (d3p + rot(4, (cx[4], cz[4])), acc(4, a_o, rot(4, (cx[4], cz[4]))), 4)}
    g = np.array([0.0, -G])[:, None]

    def moment(b):                                        # torque about J3 that body b needs
        r, a, k = bodies[b]
        f = m[b - 1] * (a - g)
        return iyy[b - 1] * al[k] + r[0] * f[1] - r[1] * f[0]

    tau_head = moment(4) + moment(5)
    tau_ref = moment(3) + tau_head
    tau3 = vs["arm.tau3"]
    osc = np.ptp(tau_head)
    assert osc > 1.0e3                                   # ≈ m g θ0 × 3 m lever: a real load
    assert np.max(np.abs(tau3 - tau_ref)) < 0.01 * osc   # Newton–Euler about the stick joint
    # the cylinder torque at the stick joint oscillates with the head's reaction torque
    late = t > 1.0
    a, b = tau3[late] - tau3[late].mean(), tau_head[late] - tau_head[late].mean()
    assert np.corrcoef(a, b)[0, 1] > 0.98
    assert np.ptp(a) == pytest.approx(np.ptp(b), rel=0.1)
