"""Finite-segment flexibility against Euler–Bernoulli, seed 000 eqs. 2–5, and the cylinder
Jacobian (seed 002 eqs. 4a–4b) against power balance and finite differences."""
import numpy as np
import pytest

from _chain_util import build, jacobian, run, state
from hydrocli.components.multibody.flexible import connection_stiffness, damping_multiplier, segment_stiffness


def _cantilever(n_seg, EI, rho_a, length, beta=0.0):
    ls = length / n_seg
    ms = rho_a * ls
    lst = lambda v: "[" + ", ".join(str(x) for x in v) + "]"
    ports = ", ".join(f"j{i}: n{i}" for i in range(1, n_seg + 1))
    cports = ", ".join(f"c{i}: n{i}" for i in range(1, n_seg + 1))
    return f"""
name: cantilever
components:
  beam:
    type: serial_chain
    ports: {{{ports}}}
    g: 0
    m: {lst([ms] * n_seg)}
    jx: {lst([0.0] + [ls] * (n_seg - 1))}
    jz: {lst([0.0] * n_seg)}
    cx: {lst([ls / 2] * n_seg)}
    cz: {lst([0.0] * n_seg)}
    Iyy: {lst([ms * ls * ls / 12] * n_seg)}
  flex:
    type: flexible_member
    ports: {{{cports}}}
    EI: {lst([0.0] + [EI] * n_seg)}      # segment 1 is the rigid wall
    L: {lst([1.0] + [ls] * n_seg)}
    beta_k: {beta}
"""


@pytest.mark.parametrize("n_seg", [5, 8])
def test_cantilever_first_frequency_matches_euler_bernoulli(n_seg):
    EI, rho_a, length = 2.1e11 * 8.0e-6, 7850 * 0.01, 4.0
    model = build(_cantilever(n_seg, EI, rho_a, length))
    lam = np.linalg.eigvals(jacobian(model, model.x0.copy()))
    f1 = np.min(np.abs(lam.imag[lam.imag > 1e-6])) / (2 * np.pi)
    f_eb = 1.875104 ** 2 * np.sqrt(EI / (rho_a * length ** 4)) / (2 * np.pi)
    assert f1 == pytest.approx(f_eb, rel=0.05)


def test_cantilever_stiffness_damping_gives_expected_decay():
    # c = β_k·k (eq. 4) with β_k = 2ζ/ω (eq. 5) gives mode damping ratio ζ at ω
    EI, rho_a, length = 2.1e11 * 8.0e-6, 7850 * 0.01, 4.0
    w_eb = 1.875104 ** 2 * np.sqrt(EI / (rho_a * length ** 4))
    model = build(_cantilever(6, EI, rho_a, length, beta=damping_multiplier(0.05, w_eb)))
    lam = np.linalg.eigvals(jacobian(model, model.x0.copy()))
    first = lam[np.argmin(np.where(lam.imag > 1e-6, np.abs(lam), np.inf))]
    assert -first.real / abs(first) == pytest.approx(0.05, rel=0.1)


def test_segment_and_connection_stiffness_formulas():
    # eq. 3 and eq. 2; seed 000 Table 2 pedestal: two 5.75e9 segments → 2.88e9 N·m/rad
    assert segment_stiffness(3.0, 2.0) == 3.0
    assert connection_stiffness(5.75e9, 5.75e9) == pytest.approx(2.88e9, rel=2e-3)
    assert connection_stiffness(None, 2.08e8) == 2.08e8
    assert connection_stiffness(2.08e8, 1.39e8) == pytest.approx(8.33e7, rel=2e-3)


ARM_WITH_CYLINDERS = """
name: arm_cylinders
fluid: {beta: "1.2 GPa"}
components:
  arm:
    type: serial_chain
    ports: {a1: lift_rod, a2: fold_rod}
    m: [300.0, 120.0]
    jx: [0, 3.0]
    jz: [1.0, 0]
    cx: [1.4, 1.0]
    cz: [0.1, 0]
    Iyy: [250.0, 40.0]
    act_a_body: [0, 1]
    act_ax: [0.4, 1.2]
    act_az: [0.0, 0.5]
    act_b_body: [1, 2]
    act_bx: [1.2, -0.4]
    act_bz: [-0.1, 0.5]
    act_L0: [0.9, 1.6]
  lift:
    type: cylinder
    ports: {A: lift_a, B: lift_b, rod: lift_rod, body: ground}
    A_A: 3.0e-3
    A_B: 1.8e-3
    V_A0: 4.0e-4
    V_B0: 1.5e-3
  fold:
    type: cylinder
    ports: {A: fold_a, B: fold_b, rod: fold_rod, body: ground}
    A_A: 2.0e-3
    A_B: 1.2e-3
    V_A0: 3.0e-4
    V_B0: 1.5e-3
initial: {arm.q1: 0.3, arm.q2: -0.6, lift_a.p: "50 bar", lift_b.p: "10 bar", fold_a.p: "20 bar", fold_b.p: "20 bar"}
"""


def test_cylinder_jacobian_power_balance_and_length_rate():
    model = build(ARM_WITH_CYLINDERS)
    t, tr = run(model, 1.0, n=2001, rtol=1e-9)
    vs = model.evaluate_along(t, tr.X, np.zeros((t.size, 0)))
    w = {j: state(model, tr, f"arm.w{j}") for j in (1, 2)}
    assert np.ptp(w[1]) > 0.05 and np.ptp(w[2]) > 0.05     # the arm bounces on the oil springs
    p_cyl = sum(vs[f"{c}.F"] * vs[f"{c}.v"] for c in ("lift", "fold"))
    p_joint = vs["arm.tau_act1"] * w[1] + vs["arm.tau_act2"] * w[2]
    scale = np.max(np.abs(p_cyl))
    assert scale > 100.0
    assert np.max(np.abs(p_cyl - p_joint)) < 1e-9 * scale
    # cylinder x = pin-to-pin length − act_L0, and its velocity is the length's time derivative
    assert np.allclose(vs["lift.x"], vs["arm.L1"] - 0.9, atol=1e-12)
    ldot_fd = np.gradient(vs["arm.L2"], t)
    assert np.max(np.abs(ldot_fd - vs["fold.v"])[2:-2]) < 1e-2 * np.max(np.abs(vs["fold.v"]))  # O(dt²) of np.gradient
