"""A sliding seal's film leak (film_leak, film_leak_rotary): two closed oil volumes joined by
the leak equalise as the closed form of a laminar leak says, at the conductance c·φ(v) the
rod's speed gives, φ(v) = v²/(v² + v_ε²)·(√(v² + v_ε²)/v_ref)ⁿ: fully at the reference speed, by
the power law at another, not at all at standstill; the oil is conserved and the rod is not pushed."""
import numpy as np
import pytest

from simhelpers import col, run

V1, V2, BETA, C = 1e-4, 2e-4, 1.5e9, 2e-12


def _machine(kind: str, domain: str, n: float, v_ref: float, v_eps: float) -> str:
    load = "{type: mass, ports: {m: piston}, m: 1.0}" if domain == "mass" else \
        "{type: inertia, ports: {r: piston}, J: 1.0}"
    return f"""
name: film_test
components:
  v1: {{type: volume, ports: {{P: a}}, V: {V1}, beta: {BETA}}}
  v2: {{type: volume, ports: {{P: b}}, V: {V2}, beta: {BETA}}}
  leak: {{type: {kind}, ports: {{A: a, B: b, rod: piston, body: ground}}, c: {C}, n: {n}, v_ref: {v_ref}, v_eps: {v_eps}}}
  load: {load}
initial: {{a.p: 1.0e7, b.p: 1.0e6}}
"""


CASES = [("film_leak", "mass", "piston.v", 0.1, 1e-3), ("film_leak_rotary", "inertia", "piston.w", 1.0, 1e-2)]


@pytest.mark.parametrize("kind,domain,speed,v_ref,v_eps", CASES)
@pytest.mark.parametrize("n", [0.5, 1.5])
def test_two_volumes_equalise_at_the_conductance_the_speed_gives(kind, domain, speed, v_ref, v_eps, n):
    """Δp' = −c·φ·(1/C₁ + 1/C₂)·Δp, C = V/β: Δp decays as exp(−t/τ), τ = C₁C₂/((C₁+C₂)·c·φ),
    with the rod coasting at a constant speed (nothing pushes it: the leak only reads it).
    At v_ref φ = 1 (to (v_ε/v_ref)² = 10⁻⁴); at 3·v_ref φ = 3ⁿ; at rest φ = 0: the seal holds.
    V₁p₁ + V₂p₂ is conserved (β equal)."""
    c1, c2 = V1 / BETA, V2 / BETA
    machine = _machine(kind, domain, n, v_ref, v_eps)
    for v in (v_ref, -v_ref, 3 * v_ref, 0.0):
        m, tr, _ = run(machine, 0.2, n=201, x0={speed: v})
        assert np.allclose(col(m, tr, speed), v, atol=1e-12)      # no force on the rod
        s2 = v * v + v_eps * v_eps
        phi = v * v / s2 * (s2 / v_ref ** 2) ** (0.5 * n)
        assert phi == pytest.approx(abs(v / v_ref) ** n, rel=2e-4)   # the power law, to (v_ε/v)²
        rate = (c1 + c2) * C * phi / (c1 * c2)          # 1/τ
        dp = col(m, tr, "a.p") - col(m, tr, "b.p")
        assert dp[-1] / dp[0] == pytest.approx(np.exp(-0.2 * rate), rel=1e-4, abs=1e-8)
        mass = col(m, tr, "a.p")[-1] * V1 + col(m, tr, "b.p")[-1] * V2
        assert mass == pytest.approx(1e7 * V1 + 1e6 * V2, rel=1e-7)


def test_the_film_leak_offers_its_role_with_real_ports_and_parameters():
    from hydrocli.components import registry, roles
    for t in ("film_leak", "film_leak_rotary"):
        cls = registry.get(t)
        r = cls.role(roles.FILM_RESTRICTION)
        assert {r.port(s) for s in ("a", "b", "motion", "reference")} <= {p.name for p in cls.ports}
        assert {r.param(s) for s in ("conductance", "exponent", "speed")} <= {p.name for p in cls.parameters}
