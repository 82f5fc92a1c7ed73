"""The pressure-compensated pump's lagging control (pump_compensator): a flow demand switched
on at a node fed through it dips the node's pressure and the dip recovers to the set pressure
(no steady droop), against the linear system's exact solution (a matrix exponential) and the
stiff limit k·q₀·e^(−t/τ) of the source the element stands for (Manring 2005)."""
import numpy as np
import pytest
from scipy.linalg import expm

from simhelpers import col, run

PS, K, TAU, Q0, V, BETA = 2.0e7, 5e10, 0.05, 2e-4, 1e-4, 1.5e9


def _machine(v: float) -> str:
    return f"""
name: compensator_test
components:
  pump: {{type: pressure_source, ports: {{P: set}}, p: {PS}}}
  comp: {{type: pump_compensator, ports: {{A: set, B: out}}, k: {K}, tau: {TAU}}}
  line: {{type: volume, ports: {{P: out}}, V: {v}, beta: {BETA}}}
  demand: {{type: flow_source, ports: {{P: out}}, Q: {-Q0}}}
initial: {{out.p: {PS}}}
"""


def test_a_flow_demand_dips_the_outlet_and_the_set_pressure_returns():
    """States (Δp = p_set − p_out, z): C·Δp′ = q₀ − q, q = Δp/k + z, z′ = Δp/(k·τ) with
    C = V/β, from (0, 0): x′ = A·x + b, x(t) = ∫₀ᵗ e^(A s) ds·b, evaluated as one block matrix
    exponential. The dip's peak and shape match; at the end the outlet is back at the set
    pressure and the pump delivers q₀ (z = q₀)."""
    t_end = 0.5
    m, tr, _ = run(_machine(V), t_end, n=501, x0={"out.p": PS, "comp.z": 0.0})
    C = V / BETA
    A = np.array([[-1 / (C * K), -1 / C], [1 / (K * TAU), 0.0]])
    b = np.array([Q0 / C, 0.0])
    M = np.zeros((3, 3))
    M[:2, :2], M[:2, 2] = A, b
    t = np.linspace(0, t_end, 501)
    exact = np.array([expm(M * s)[:2, 2] for s in t])
    dp = PS - col(m, tr, "out.p")
    z = col(m, tr, "comp.z")
    assert dp == pytest.approx(exact[:, 0], abs=1e-6 * K * Q0)
    assert z == pytest.approx(exact[:, 1], abs=1e-6 * Q0)
    assert dp[-1] < 1e-3 * K * Q0 and z[-1] == pytest.approx(Q0, rel=1e-3)     # no steady droop


def test_with_a_small_outlet_volume_the_dip_is_k_q0_exp_minus_t_over_tau():
    """C·k ≪ τ: the outlet follows the pump at once and Δp = k·q₀·e^(−t/τ) (Manring's step
    response of the linearised compensated pump)."""
    v = 1e-7                                  # C·k = 3.3e-6 s
    m, tr, _ = run(_machine(v), 0.3, n=301, x0={"out.p": PS, "comp.z": 0.0})
    t = np.linspace(0, 0.3, 301)
    dp = PS - col(m, tr, "out.p")
    late = t > 0.01
    assert dp[late] == pytest.approx(K * Q0 * np.exp(-t[late] / TAU), rel=1e-3, abs=1e-4 * K * Q0)
