"""Hydraulic motor, gearbox and leakages (seed 002 Fig. 3, eqs. 5, 8, 9)."""
import numpy as np
import pytest

from simhelpers import col, run
from helpers import evaluate, pinned_model


def test_leakage_flows_eq8_eq9():
    """Q_in = ΔP/R_m and Q_ex = P/R_ex with seed 002's R_m = 8e11, R_ex = 2.2e12 N·s/m⁵."""
    m = pinned_model("""  motor:
    type: hydraulic_motor
    ports: {A: n1, B: n2, shaft: ground, body: ground}""", {"n1": "p1", "n2": "p2"})
    r = evaluate(m, {"p1": np.array([150e5]), "p2": np.array([20e5])})
    assert r["motor.q_in"][0] == pytest.approx(130e5 / 8e11)
    assert r["motor.q_exA"][0] == pytest.approx(150e5 / 2.2e12)
    assert r["motor.q_exB"][0] == pytest.approx(20e5 / 2.2e12)
    assert r["motor.tau"][0] == pytest.approx(1e-5 * 130e5)


@pytest.mark.parametrize("leaky", [False, True])
def test_motor_steady_speed_through_gearbox(leaky):
    """Flow Q into the motor, gearbox N with viscous B_sw on the output. Without leakage
    ω_out = Q/(D_m N); with leakage the torque balance gives p_A = B_sw ω_m/(N² D_m) and
    Q = D_m ω_m + p_A/R_m + p_A/R_ex."""
    Q, D, N, B, Rm, Rex = 1e-4, 1e-5, 10.0, 100.0, 8e11, 2.2e12
    leak = f"R_m: {Rm}\n    R_ex: {Rex}" if leaky else "R_m: 1e30\n    R_ex: 1e30"
    text = f"""
name: swing
fluid: {{p_tank: 0}}
components:
  pump: {{type: flow_source, ports: {{P: a}}, Q: {Q}}}
  vol: {{type: volume, ports: {{P: a}}, V: 1e-4}}
  tank: {{type: tank, ports: {{T: t}}}}
  motor:
    type: hydraulic_motor
    ports: {{A: a, B: t, shaft: m_shaft, body: ground}}
    D_m: {D}
    {leak}
  gear: {{type: gearbox, ports: {{in: m_shaft, out: load}}, N: {N}, B_sw: {B}}}
  J: {{type: inertia, ports: {{r: load}}, J: 0.5}}
"""
    m, tr, _ = run(text, 0.5, n=101)
    w_out = col(m, tr, "load.w")[-1]
    if leaky:
        w_m = Q / (D + B / (N ** 2 * D) * (1 / Rm + 1 / Rex))
    else:
        w_m = Q / D
    assert w_out == pytest.approx(w_m / N, rel=1e-4)
    if leaky:
        assert abs(w_m - Q / D) / (Q / D) > 0.01      # the leakage is visible
