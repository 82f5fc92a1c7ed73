"""Check valve (seed 000 eq. 12), counterbalance valve (eqs. 13–22, 29; Tables 5, 8) and the
pressure compensator of the load-sensing DCV (eqs. 10–11), against the paper's formulas."""
import math

import numpy as np
import pytest

from helpers import evaluate, pinned_model

LPM = 1 / 60000.0


def cbv_model(vented=1, **params):
    extra = "".join(f"\n    {k}: {v}" for k, v in params.items())
    return pinned_model(f"""  cbv:
    type: counterbalance_valve
    ports: {{L: nl, V: nv, X: nx}}
    vented: {vented}
    p_ref: 0
    Cv_check: 0{extra}""", {"nl": "pl", "nv": "pv", "nx": "px"})


def test_cracking_line_eq18_matches_eq13():
    """With C1 = ψ, C2 = 0 the line is eq. 18, μ_L,cr = 1/(1 + ψμ_x); it is the cracking
    condition of eq. 13, p_L + ψ·p_x = p_cr: just above it flows, on and below it does not."""
    psi, p_cr = 3.0, 250e5
    m = cbv_model(C1=psi, C2=0.0)
    px = np.array([10e5, 30e5, 50e5])
    pl_crack = p_cr - psi * px                        # eq. 13
    r = evaluate(m, {"pl": pl_crack, "pv": 0 * px, "px": px})
    mu_x = px / pl_crack
    assert np.allclose(r["cbv.mu_L_cr"], 1 / (1 + psi * mu_x), rtol=1e-12)
    assert np.allclose(r["cbv.s"], 0.0, atol=1e-12)
    assert np.all(r["cbv.q"] == 0.0)
    below = evaluate(m, {"pl": pl_crack - 5e5, "pv": 0 * px, "px": px})
    assert np.all(below["cbv.q"] == 0.0)
    above = evaluate(m, {"pl": pl_crack + 5e5, "pv": 0 * px, "px": px})
    assert np.all(above["cbv.q"] > 0.0)


def test_corrected_cracking_line_and_flow_table8():
    """Eq. 29 with Table 8 (C1 = 1.6267, C2 = 0.2452) and the flow map eqs. 20–22 with
    A0 = 27.84, A1 = 146.2 L/min, n0 = 0.4707, n1 = 0.0359 (non-vented, eqs. 17, 30–31)."""
    m = cbv_model(vented=0)                            # Table 8 values are the defaults
    p3, p4, p1 = np.array([150e5, 120e5, 100e5]), np.array([10e5, 5e5, 20e5]), np.array([100e5, 40e5, 60e5])
    r = evaluate(m, {"pl": p3, "pv": p4, "px": p1})
    mu_x = p1 / p3                                     # eq. 31
    mu_l = (p3 - p4) / 250e5                           # eq. 30
    mu_cr = 1 / (1 + 1.6267 * mu_x + 0.2452 * mu_x ** 2)
    s = mu_l - mu_cr
    q_ref = np.where(s > 0, (27.84 + 146.2 * mu_x) * np.maximum(s, 0) ** (0.4707 + 0.0359 * mu_x), 0) * LPM
    assert np.allclose(r["cbv.mu_L_cr"], mu_cr, rtol=1e-12)
    assert s[0] > 0.05 and s[2] < 0                   # one point well above, one below the line
    assert r["cbv.q"][2] == 0.0
    # s^n is regularised within eps_s = 1e-3 of the line only
    assert r["cbv.q"][0] == pytest.approx(q_ref[0], rel=0.01)


def test_vented_mu_L_is_load_over_cracking_pressure():
    m = cbv_model(vented=1)
    r = evaluate(m, {"pl": np.array([100e5]), "pv": np.array([40e5]), "px": np.array([20e5])})
    assert r["cbv.mu_L"][0] == pytest.approx(100 / 250)   # eq. 16 ignores p1


def test_cbv_check_valve_passes_reverse_flow_only():
    m = pinned_model("""  cbv:
    type: counterbalance_valve
    ports: {L: nl, V: nv, X: nx}""", {"nl": "pl", "nv": "pv", "nx": "px"})
    r = evaluate(m, {"pl": np.array([50e5]), "pv": np.array([60e5]), "px": np.array([1e5])})
    cv = 63.2 * LPM / math.sqrt(1e5)                  # Table 5, fully open (Δp − p_cr ≫ k_s)
    assert -r["cbv.q"][0] == pytest.approx(cv * math.sqrt(10e5), rel=0.01)


@pytest.mark.parametrize("dp, xi_ref", [(0.5e5, 0.0), (1.5e5, 0.5), (3e5, 1.0), (-5e5, 0.0)])
def test_check_valve_opening_eq12(dp, xi_ref):
    """ξ = clamp((p1 − p2 − p_cr)/k_s, 0, 1), p_cr = k_s = 1 bar (Table 5); Q = ξ·C_V·sqrt(Δp)."""
    m = pinned_model("""  cv:
    type: check_valve
    ports: {A: n1, B: n2}
    Cv: "89.4 L/min/bar^0.5"
    dp_lam: 100""", {"n1": "p1", "n2": "p2"})
    r = evaluate(m, {"p1": np.array([10e5 + dp]), "p2": np.array([10e5])})
    assert r["cv.xi"][0] == pytest.approx(xi_ref, abs=2e-3)
    q_ref = xi_ref * 89.4 * LPM / math.sqrt(1e5) * math.sqrt(max(dp, 0))
    assert r["cv.q"][0] == pytest.approx(q_ref, rel=0.01, abs=1e-8)



@pytest.mark.parametrize("pA, dp_ref", [
    (100e5, 7e5),        # case 1: p0 ≤ pS − pLS → compensator holds p0
    (197e5, 3e5),        # case 2: 0 < pS − pLS < p0 → drop pS − pLS
    (210e5, 0.0),        # case 3: pS − pLS ≤ 0 → built-in check, no flow
])
def test_compensator_three_cases_eq10(pA, dp_ref):
    """Seed 000 eq. 10 with Table 4 (C_V = 37.8 L/min/bar^0.5, p0 = 7 bar, overlap 10 %):
    meter-in flow Q = ξ·C_V·sqrt(Δp_c), ξ = (u − 0.1)/(1 − 0.1), p_LS = p_A for u > 0 (eq. 11)."""
    text = """name: pc
inputs:
  u: {unit: "1"}
  Ps: {unit: Pa}
  Pt: {unit: Pa}
  PA: {unit: Pa}
  PB: {unit: Pa}
components:
  dcv:
    type: valve_pc_ls
    ports: {P: ps, T: pt, A: na, B: nb, cmd: u}
    Kv: "37.8 L/min/bar^0.5"
    p0: "7 bar"
    overlap_PA: 0.1
    overlap_PB: 0.1
    overlap_AT: -0.05
    overlap_BT: -0.05
    dp_lam: 100
    order: 0
  s1: {type: pressure_source, ports: {P: ps, ref: Ps}}
  s2: {type: pressure_source, ports: {P: pt, ref: Pt}}
  s3: {type: pressure_source, ports: {P: na, ref: PA}}
  s4: {type: pressure_source, ports: {P: nb, ref: PB}}
"""
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist_text
    m = build_model(load_netlist_text(text))
    u = 0.6
    x = np.zeros(len(m.state_names))
    x[m.state_index("dcv.xr")] = u
    vals = {"u": [u], "Ps": [200e5], "Pt": [1e5], "PA": [pA], "PB": [5e5]}
    r = evaluate(m, vals, x=x)
    xi = (u - 0.1) / 0.9
    q_pa = xi * 37.8 * LPM / math.sqrt(1e5) * math.sqrt(dp_ref)
    assert r["dcv.p_LS"][0] == pytest.approx(pA, rel=1e-6)
    assert r["dcv.dp_comp"][0] == pytest.approx(dp_ref, abs=0.01e5)
    assert r["dcv.qA"][0] == pytest.approx(q_pa, rel=0.01, abs=1e-7)
    # load-independence in case 1: the return edge B→T (underlap 5 %) is an ordinary orifice
    xi_bt = (u + 0.05) / 1.05
    assert -r["dcv.qB"][0] == pytest.approx(xi_bt * 37.8 * LPM / math.sqrt(1e5) * math.sqrt(4e5), rel=0.01)
