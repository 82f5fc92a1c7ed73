"""Seed 002 eq. 2 modulated valve resistance and seed 000 eqs. 23/26 cylinder friction."""
import numpy as np
import pytest

from helpers import evaluate
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text


def _valve(extra):
    return build_model(load_netlist_text(f"""
name: mv
inputs: {{V: {{unit: V}}, pa: {{unit: Pa}}, pb: {{unit: Pa}}}}
components:
  valve:
    type: modulated_resistance
    ports: {{A: na, B: nb, cmd: V}}
    dp_lam: 1
{extra}
  sa: {{type: pressure_source, ports: {{P: na, ref: pa}}}}
  sb: {{type: pressure_source, ports: {{P: nb, ref: pb}}}}
"""))


def test_modulated_resistance_polynomial_and_deadband():
    """ΔP = C_R·Q|Q| with C_R^(−1/2) = c0 + c1(V − 1.2) outside the 0–1.2 V deadband."""
    m = _valve("    coeffs: [1.0e-8, 2.0e-8]")
    V = np.array([0.5, 1.0, 2.0, 3.2, -2.0])
    r = evaluate(m, {"V": V, "pa": np.full(5, 50e5), "pb": np.full(5, 10e5)})
    g = np.where(V > 1.2, 1e-8 + 2e-8 * (V - 1.2), 0.0)
    assert np.allclose(r["valve.g"], g, rtol=1e-6, atol=1e-15)
    q = r["valve.q"]
    with np.errstate(divide="ignore"):
        c_r = 40e5 / (q * np.abs(q))
    assert np.allclose(c_r[2:4], 1 / g[2:4] ** 2, rtol=1e-6)     # eq. 2a
    assert np.all(q[[0, 1, 4]] == 0.0)


def test_modulated_resistance_table_both_polarities():
    m = _valve("    table_V: [1.2, 2, 5]\n    table_g: [0, 1.0e-8, 4.0e-8]\n    polarity: 0")
    V = np.array([-3.5, 1.0, 1.6, 3.5])
    r = evaluate(m, {"V": V, "pa": np.full(4, 10e5), "pb": np.full(4, 20e5)})
    g = np.array([2.5e-8, 0.0, 0.5e-8, 2.5e-8])
    assert np.allclose(r["valve.g"], g, rtol=1e-9, atol=1e-16)
    assert np.allclose(r["valve.q"], -g * np.sqrt(10e5), rtol=1e-6)


@pytest.mark.parametrize("v, frac", [(0.01, 1.0), (-0.01, -1.0), (0.0005, 0.5)])
def test_cylinder_friction_eq23_eq26(v, frac):
    """F_fr = F_S + C_p·|p1·A_p − p2·φA_p| (eq. 26), full above v0, linear below (eq. 23)."""
    m = build_model(load_netlist_text("""
name: cf
inputs: {p1: {unit: Pa}, p2: {unit: Pa}}
components:
  fr: {type: cylinder_friction, ports: {a: rod, b: ground, pa: n1, pb: n2}, v0: 1e-3}
  rodmass: {type: mass, ports: {m: rod}, m: 100}
  s1: {type: pressure_source, ports: {P: n1, ref: p1}}
  s2: {type: pressure_source, ports: {P: n2, ref: p2}}
"""))
    x = np.zeros(len(m.state_names))
    x[m.state_index("rod.v")] = v
    r = evaluate(m, {"p1": [100e5], "p2": [20e5]}, x=x)
    a_p = np.pi / 4 * 0.25 ** 2
    phi = (0.25 ** 2 - 0.125 ** 2) / 0.25 ** 2
    f_p = 100e5 * a_p - 20e5 * phi * a_p
    assert r["fr.F"][0] == pytest.approx(frac * (6.4e3 + 0.029 * abs(f_p)), rel=1e-3)
