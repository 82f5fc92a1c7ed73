"""End-position cushioning (end_cushion): the opening law and the steady cushion pressure
against closed forms (turbulent needle orifice, force balance of the piston)."""
import numpy as np
import pytest

from simhelpers import col, run

A_A, A_B, P_T = 2e-4, 1e-4, 1e5
KN, KV, L, W, X_END = 1e-9, 1e-6, 0.01, 0.002, 0.1


def _machine(force, x_end=X_END, kv_check=0.0, kv_spear=0.0):
    """Cylinder pushed by a constant force towards its extended end; chamber A vented to
    tank through a large orifice, chamber B draining to tank through the cushion."""
    return f"""
name: cushion_test
components:
  tank: {{type: tank, ports: {{T: t}}, p: {P_T}}}
  cyl:
    type: cylinder
    ports: {{A: ca, B: cb, rod: piston, body: ground}}
    A_A: {A_A}
    A_B: {A_B}
    V_A0: 2.0e-5
    V_B0: 4.0e-5
  vent: {{type: orifice, ports: {{A: t, B: ca}}, Kv: 1.0e-5, dp_lam: 100}}
  cush:
    type: end_cushion
    ports: {{chamber: cb, line: t, rod: piston, body: ground}}
    Kv: {KV}
    Kv_needle: {KN}
    Kv_check: {kv_check}
    Kv_spear: {kv_spear}
    x_end: {x_end}
    direction: 1
    L: {L}
    w: {W}
    eps: 0.001
    dp_lam: 100
  push: {{type: force_source, ports: {{a: piston}}, F0: {force}}}
  load: {{type: mass, ports: {{m: piston}}, m: 1.0}}
initial: {{ca.p: {P_T}, cb.p: {P_T}}}
"""


def test_steady_cushion_pressure_is_the_needle_law():
    """In the needle zone a constant force F gives the cushion pressure
    Δp = (F + (A_A − A_B) p_T)/A_B and the creep speed v = K_n·sqrt(Δp)/A_B, i.e.
    Δp = (A_B v / K_n)² — independent of the mass and of the main outlet."""
    force = 500.0
    m, tr, _ = run(_machine(force), 1.5, x0={"piston.x": X_END + 2 * L})
    v = col(m, tr, "piston.v")[-1]
    pb = col(m, tr, "cb.p")[-1]
    dp = (force + (A_A - A_B) * P_T) / A_B
    assert pb - P_T == pytest.approx(dp, rel=2e-3)
    assert v == pytest.approx(KN * np.sqrt(dp) / A_B, rel=2e-3)
    assert pb - P_T == pytest.approx((A_B * v / KN) ** 2, rel=4e-3)


def test_main_outlet_open_away_from_the_end_and_closing_linearly():
    """Far from the end the outlet is the main orifice (K = Kv + K_n); halfway through the
    spear's entry (d = L + w/2) K = Kv/2 + K_n; inside the cushion length only the needle."""
    force = 50.0
    for x0, g in ((X_END - 5 * L, 1.0), (X_END - L - 0.5 * W, 0.5), (X_END - 0.5 * L, 0.0)):
        m, tr, _ = run(_machine(force), 1e-3, n=11, x0={"piston.x": x0})
        k = m.evaluate_along(tr.t[:1], tr.X[:1], np.zeros((1, 0)), m.p0)["cush.K"][0]
        assert k == pytest.approx(KV * g + KN, rel=1e-3)


def test_tapered_spear_adds_a_gap_falling_linearly_to_the_stop():
    """With a tapered spear K = Kv_spear·d/L + K_n inside the cushion (d = distance to the stop)."""
    ks = 4e-9
    for d in (0.75 * L, 0.25 * L):
        m, tr, _ = run(_machine(0.0, kv_spear=ks), 1e-3, n=3, x0={"piston.x": X_END - d})
        k = m.evaluate_along(tr.t[:1], tr.X[:1], np.zeros((1, 0)), m.p0)["cush.K"][0]
        assert k == pytest.approx(KN + ks * d / L, rel=1e-3)


def test_check_valve_lets_the_oil_back_in():
    """Chamber B below the line pressure (flow into the chamber) in the needle zone: the
    check valve adds its coefficient, K = K_n + Kv_check; out of the chamber (and at Δp = 0)
    it stays K_n."""
    kc = 1e-7
    m, tr, _ = run(_machine(0.0, kv_check=kc), 1e-3, n=3, x0={"piston.x": X_END + 2 * L})
    X = np.repeat(tr.X[:1], 2, axis=0)
    X[:, m.state_index("cb.p")] = [0.2e5, 3e5]            # line (tank) at 1 bar, cracks at 0.5 bar
    r = m.evaluate_along(tr.t[:2], X, np.zeros((2, 0)), m.p0)
    assert r["cush.K"][0] == pytest.approx(KN + kc, rel=1e-3)
    assert r["cush.q"][0] == pytest.approx(-(KN + kc) * np.sqrt(0.8e5), rel=1e-3)
    assert r["cush.K"][1] == pytest.approx(KN, rel=1e-3)
    X[:, m.state_index("cb.p")] = P_T
    assert m.evaluate_along(tr.t[:2], X, np.zeros((2, 0)), m.p0)["cush.K"][0] == pytest.approx(KN, rel=1e-3)


def _vane(torque, x_end=0.2, length=0.05):
    """A vane actuator turned by a constant torque towards its upper end; chamber 1 vented to
    tank, chamber 2 draining to tank through the rotary cushion (angles in rad)."""
    return f"""
name: rotary_cushion_test
components:
  tank: {{type: tank, ports: {{T: t}}, p: {P_T}}}
  vane: {{type: vane_actuator, ports: {{A: ca, B: cb, shaft: shaft, body: ground}}, D_v: 1.0e-5, V_1: 2.0e-5,
          V_2: 2.0e-5, R_v: 0.0}}
  vent: {{type: orifice, ports: {{A: t, B: ca}}, Kv: 1.0e-5, dp_lam: 100}}
  cush:
    type: end_cushion_rotary
    ports: {{chamber: cb, line: t, rod: shaft, body: ground}}
    Kv: {KV}
    Kv_needle: {KN}
    x_end: {x_end}
    direction: 1
    L: {length}
    w: 0.01
    eps: 0.001
    dp_lam: 100
  push: {{type: torque_source, ports: {{a: shaft}}, tau0: {torque}}}
  load: {{type: inertia, ports: {{r: shaft}}, J: 0.01}}
initial: {{ca.p: {P_T}, cb.p: {P_T}}}
"""


def test_a_rotary_cushion_holds_the_needle_law_in_rad():
    """The vane's torque balance in the needle zone: T = D_v·(p_2 − p_T), so the cushion
    pressure is Δp = T/D_v and the creep speed ω = K_n·sqrt(Δp)/D_v; far from the end the
    main outlet is open (K = Kv + K_n), within the cushion's length only the needle."""
    torque, d_v = 10.0, 1e-5
    m, tr, _ = run(_vane(torque), 1.5, x0={"shaft.theta": 0.3})
    dp = torque / d_v
    assert col(m, tr, "cb.p")[-1] - P_T == pytest.approx(dp, rel=2e-3)
    assert col(m, tr, "shaft.w")[-1] == pytest.approx(KN * np.sqrt(dp) / d_v, rel=2e-3)
    for th0, g in ((0.2 - 0.3, 1.0), (0.2 - 0.05 - 0.005, 0.5), (0.2 - 0.025, 0.0)):
        m, tr, _ = run(_vane(0.0), 1e-3, n=11, x0={"shaft.theta": th0})
        k = m.evaluate_along(tr.t[:1], tr.X[:1], np.zeros((1, 0)), m.p0)["cush.K"][0]
        assert k == pytest.approx(KV * g + KN, rel=1e-3)
