"""Seed 002 eq. 7: the turbulent resistance of a hose of another length and diameter, scaled
from the measured 4 m, 3/4 in SAE 100R12 hose (C_R = 3.125e11 Pa/(m³/s)², §3b)."""
import numpy as np
import pytest

from simhelpers import col, run

C_REF, L_REF, D_REF = 3.125e11, 4.0, 0.01905
MU, RHO = 0.04, 870.0


def _eq7(length, diameter):
    """C_R(L, D) = a·μ^0.25·ρ^0.75·L/D^4.75 with a calibrated on the reference hose."""
    a = C_REF / (MU ** 0.25 * RHO ** 0.75 * L_REF / D_REF ** 4.75)
    return a * MU ** 0.25 * RHO ** 0.75 * length / diameter ** 4.75


@pytest.mark.parametrize("length, diameter", [(4.0, 0.01905), (2.0, 0.0127), (7.5, 0.0254)])
def test_steady_flow_through_a_scaled_hose(length, diameter):
    """Steady turbulent flow between two pressures: Δp = C_R(L, D)·Q|Q| (laminar part off)."""
    dp = 20e5
    text = f"""
name: hs
components:
  sa: {{type: pressure_source, ports: {{P: a}}, p: {1e5 + dp}}}
  sb: {{type: pressure_source, ports: {{P: b}}, p: 1e5}}
  hose:
    type: hose
    ports: {{A: a, B: b}}
    l: {length}
    d: {diameter}
    laminar: 0
    C_R_ref: {C_REF}
    I: 3.06e7
"""
    m, tr, _ = run(text, 2.0, n=201)
    q = col(m, tr, "hose.q0")[-1]
    assert q == pytest.approx(np.sqrt(dp / _eq7(length, diameter)), rel=1e-4)
