"""Leakage over a band of the stroke (band_leak, band_leak_rotary): two closed oil volumes
joined by the band leak equalise as the closed form of a laminar leak says, c·w(x) with the
logistic window — fully inside the band, half at an edge, not at all outside."""
import numpy as np
import pytest

from simhelpers import col, run

V1, V2, BETA, C = 1e-4, 2e-4, 1.5e9, 2e-12
X1, X2, D = 0.10, 0.20, 0.002


def _machine(kind="band_leak", domain="mass"):
    return f"""
name: band_test
components:
  v1: {{type: volume, ports: {{P: a}}, V: {V1}, beta: {BETA}}}
  v2: {{type: volume, ports: {{P: b}}, V: {V2}, beta: {BETA}}}
  leak:
    type: {kind}
    ports: {{A: a, B: b, rod: piston, body: ground}}
    c: {C}
    x1: {X1}
    x2: {X2}
    d: {D}
  load: {{type: {domain}, ports: {{{'m' if domain == 'mass' else 'r'}: piston}}, {'m' if domain == 'mass' else 'J'}: 1.0}}
initial: {{a.p: 1.0e7, b.p: 1.0e6}}
"""


def _decay(machine, state, x0):
    """Δp(t)/Δp(0) after 0.2 s with the rod (shaft) held at x0 (no force on it)."""
    m, tr, _ = run(machine, 0.2, n=201, x0={state: x0})
    dp = col(m, tr, "a.p") - col(m, tr, "b.p")
    assert np.allclose(col(m, tr, state), x0)            # the leak reads the position, pushes nothing
    return dp[-1] / dp[0], col(m, tr, "a.p")[-1] * V1 + col(m, tr, "b.p")[-1] * V2


@pytest.mark.parametrize("kind,domain,state", [("band_leak", "mass", "piston.x"),
                                               ("band_leak_rotary", "inertia", "piston.theta")])
def test_two_volumes_equalise_through_the_band_only_while_the_seal_is_over_it(kind, domain, state):
    """Δp' = −c·w·(1/C₁ + 1/C₂)·Δp, C = V/β: Δp decays as exp(−t/τ), τ = C₁C₂/((C₁+C₂)·c·w).
    Inside the band (w = 1) the full rate; at an edge (w = ½) half; a tenth of the band
    beyond it (w = e^(−5)) nothing measurable. The oil is conserved: V₁p₁ + V₂p₂ is constant
    (β equal)."""
    c1, c2 = V1 / BETA, V2 / BETA
    tau = c1 * c2 / ((c1 + c2) * C)
    machine = _machine(kind, domain)
    for x0, w in ((0.15, 1.0), (X1, 0.5), (X2, 0.5), (0.25, 0.0), (0.05, 0.0)):
        ratio, mass = _decay(machine, state, x0)
        w_exact = 1 / (1 + np.exp(-(x0 - X1) / D)) / (1 + np.exp(-(X2 - x0) / D))
        assert w_exact == pytest.approx(w, abs=1e-6)
        assert ratio == pytest.approx(np.exp(-0.2 * w_exact / tau), rel=1e-4, abs=1e-8)
        assert mass == pytest.approx(1e7 * V1 + 1e6 * V2, rel=1e-7)
