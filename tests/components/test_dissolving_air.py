"""Free air dissolving during the record (components/hydraulic/dissolving_air.py). In a closed
oil volume V (bulk modulus β) above the saturation pressure the free air G = G₀·e^(−t/τ_a)
goes back into solution, and with no flow in or out (V/β + G·p_atm/p²)·ṗ = p_atm·Ġ/p
integrates to the invariant V·p/β − G·p_atm/p = const (Zhou, Vacca & Manhartsgruber 2013):
the pressure falls as the gas dissolves and leaves its volume to the oil. Below the
saturation pressure air comes out of solution toward Henry's B·V·(p_sat − p)/p_sat with the fast release time constant."""
import numpy as np
import pytest

from simhelpers import col, run

V, BETA, G0, TAU_A, P_ATM = 1e-4, 1.5e9, 5e-6, 2.0, 1e5


def _closed(p0: float, G0_=G0, extra=""):
    text = f"""
name: closed
components:
  oil: {{type: volume, ports: {{P: c}}, V: {V}, beta: {BETA}}}
  air: {{type: dissolving_air, ports: {{P: c}}, G0: {G0_}, tau_a: {TAU_A}, V: {V}{extra}}}
"""
    return run(text, 6.0, n=601, x0={"c.p": p0})


def test_air_dissolves_at_its_absorption_rate_and_the_closed_volume_keeps_its_invariant():
    p0 = 2e6
    m, tr, _ = _closed(p0)
    t, p, s = tr.t, col(m, tr, "c.p"), col(m, tr, "air.s")
    assert s == pytest.approx(np.exp(-t / TAU_A), rel=1e-5, abs=1e-7)
    G = G0 * s
    inv = V * p / BETA - G * P_ATM / p
    assert inv == pytest.approx(inv[0], rel=1e-7, abs=1e-12)
    # 5 cm³ of free air at 1 bar is 0.25 cm³ of gas at 20 bar: dissolved, it leaves that volume
    # to the oil, which expands: the pressure falls by about β·0.25/100 ≈ 37 bar, to what the
    # remaining gas holds
    assert p[-1] < 0.2 * p0
    # the final pressure from the invariant with the air nearly gone
    g_end = G0 * np.exp(-t[-1] / TAU_A)
    lhs = V * p0 / BETA - G0 * P_ATM / p0
    p_end = (lhs + np.sqrt(lhs ** 2 + 4 * V / BETA * g_end * P_ATM)) / (2 * V / BETA)
    assert p[-1] == pytest.approx(p_end, rel=1e-5)


def test_below_saturation_air_comes_out_fast_toward_henrys_equilibrium():
    """At 0.5 bar absolute (below p_sat = 1 bar) Henry's law frees B·V·(p_sat − p)/p_sat of
    air; from less than that (1 cm³) it comes out over the release time constant, 0.2 s, not
    the absorption's 2 s."""
    G_LOW = 1e-6
    m, tr, _ = run(f"""
name: low
inputs:
  pin: {{unit: Pa}}
components:
  src: {{type: pressure_source, ports: {{P: c, ref: pin}}}}
  air: {{type: dissolving_air, ports: {{P: c}}, G0: {G_LOW}, tau_a: {TAU_A}, tau_r: 0.2, V: {V}, B: 0.09}}
""", 3.0, n=301, inputs={"pin": 5e4})
    G = G_LOW * col(m, tr, "air.s")
    G_eq = 0.09 * V * (1e5 - 5e4) / 1e5
    assert G[-1] == pytest.approx(G_eq, rel=1e-3)
    t = tr.t
    assert G[np.searchsorted(t, 0.2)] == pytest.approx(G_eq + (G_LOW - G_eq) * np.exp(-1.0), rel=2e-2)


@pytest.mark.parametrize("kind,load,state,swept", [("dissolving_air_chamber", "mass", "piston.x", -2e-3),
                                                    ("dissolving_air_chamber_rotary", "inertia", "piston.theta", 1e-4)])
@pytest.mark.parametrize("x0", [0.0, 0.02, -0.02])
def test_in_a_chamber_the_free_air_is_a_share_of_the_oil_the_piston_leaves_there(kind, load, state, swept, x0):
    """In an actuator's chamber the bubbles travel with the oil: with the rod (vane) held at x₀
    the chamber holds V(x₀) = V + A·x₀ of oil and G₀·V(x₀)/V of free air, so the closed volume
    keeps the invariant of the plain element with G₀ scaled by that share (Zhou et al. 2013);
    the rod only reads the position (it stays put with no force on it)."""
    p0, share = 2e6, 1.0 + swept * x0 / V
    mass = "m" if load == "mass" else "J"
    m, tr, _ = run(f"""
name: chamber
components:
  oil: {{type: volume, ports: {{P: c}}, V: {V}, beta: {BETA}}}
  air: {{type: {kind}, ports: {{P: c, rod: piston, body: ground}}, G0: {G0}, tau_a: {TAU_A}, V: {V}, A: {swept}}}
  load: {{type: {load}, ports: {{{'m' if load == 'mass' else 'r'}: piston}}, {mass}: 1.0}}
""", 6.0, n=601, x0={"c.p": p0, state: x0})
    assert np.allclose(col(m, tr, state), x0)
    t, p, s = tr.t, col(m, tr, "c.p"), col(m, tr, "air.s")
    assert s == pytest.approx(np.exp(-t / TAU_A), rel=1e-5, abs=1e-7)
    inv = V * p / BETA - G0 * share * s * P_ATM / p
    assert inv == pytest.approx(inv[0], rel=1e-7, abs=1e-12)
    m_plain, tr_plain, _ = _closed(p0, G0_=G0 * share)
    assert p == pytest.approx(col(m_plain, tr_plain, "c.p"), rel=1e-5)
