"""Core physics against closed forms (issue 2): hydraulic natural frequency, valve-controlled
steady velocity, second-order spool step, spring-mass-damper, volume continuity."""
import math

import numpy as np
import pytest

from simhelpers import col, oscillation_frequency, run

BETA = 1.5e9


def test_hydraulic_natural_frequency_single_rod():
    """ω_h² = β(A_A²/V1 + A_B²/V2)/m for a mass on a cylinder with blocked ports (closed,
    overlapped valve); the pressure offset starts the oscillation."""
    A_A, A_B, V1, V2, m = 3.117e-3, 2.099e-3, 5e-4, 3e-4, 100.0
    text = f"""
name: blocked
fluid: {{beta: {BETA}}}
inputs: {{u: {{unit: "1"}}}}
components:
  supply: {{type: pressure_source, ports: {{P: ps}}, p: 100e5}}
  tank: {{type: tank, ports: {{T: pt}}}}
  valve:
    type: valve_4_3
    ports: {{P: ps, T: pt, A: ca, B: cb, cmd: u}}
    overlap_PA: 0.1
    overlap_PB: 0.1
    overlap_AT: 0.1
    overlap_BT: 0.1
  cyl: {{type: cylinder, ports: {{A: ca, B: cb, rod: piston, body: ground}}, A_A: {A_A}, A_B: {A_B},
         V_A0: {V1}, V_B0: {V2}}}
  load: {{type: mass, ports: {{m: piston}}, m: {m}}}
initial: {{ca.p: 50e5, cb.p: 50e5}}
"""
    mdl, tr, _ = run(text, 0.08, n=8001)
    w = oscillation_frequency(tr.t, col(mdl, tr, "piston.v"))
    w_ref = math.sqrt(BETA * (A_A ** 2 / V1 + A_B ** 2 / V2) / m)
    assert w == pytest.approx(w_ref, rel=0.02)


def test_hydraulic_natural_frequency_symmetric():
    """Double-rod cylinder: ω_h = sqrt(β A²(1/V1 + 1/V2)/m)."""
    A, V1, V2, m = 2.0994e-3, 4e-4, 6e-4, 50.0
    text = f"""
name: blocked_sym
fluid: {{beta: {BETA}}}
components:
  cyl: {{type: cylinder_double_rod, ports: {{A: ca, B: cb, rod: piston, body: ground}}, A: {A},
         V_A0: {V1}, V_B0: {V2}}}
  load: {{type: mass, ports: {{m: piston}}, m: {m}}}
initial: {{ca.p: 60e5, cb.p: 40e5}}
"""
    mdl, tr, _ = run(text, 0.05, n=8001)
    w = oscillation_frequency(tr.t, col(mdl, tr, "piston.v"))
    assert w == pytest.approx(math.sqrt(BETA * A ** 2 * (1 / V1 + 1 / V2) / m), rel=0.02)


def test_steady_velocity_constant_opening():
    """Symmetric cylinder, no load: each metering edge drops (Ps − Pt)/2, so
    v = Kv·x·sqrt((Ps − Pt)/2)/A."""
    Kv, x, A, Ps, Pt = 4.68e-7, 0.2, 2.0994e-3, 100e5, 1e5
    text = f"""
name: open_valve
fluid: {{beta: {BETA}, p_tank: {Pt}}}
inputs: {{u: {{unit: "1"}}}}
components:
  supply: {{type: pressure_source, ports: {{P: ps}}, p: {Ps}}}
  tank: {{type: tank, ports: {{T: pt}}}}
  valve: {{type: valve_4_3, ports: {{P: ps, T: pt, A: ca, B: cb, cmd: u}}, Kv: {Kv}, dp_lam: 1000}}
  cyl: {{type: cylinder_double_rod, ports: {{A: ca, B: cb, rod: piston, body: ground}}, A: {A},
         V_A0: 5e-4, V_B0: 5e-4}}
  load: {{type: mass, ports: {{m: piston}}, m: 20}}
initial: {{ca.p: 50e5, cb.p: 50e5}}
"""
    mdl, tr, _ = run(text, 0.3, n=301, inputs={"u": x})
    v_ref = Kv * x * math.sqrt((Ps - Pt) / 2) / A
    assert col(mdl, tr, "piston.v")[-1] == pytest.approx(v_ref, rel=0.01)


def test_second_order_spool_step():
    """Spool step with ζ = 0.8, ω = 250 rad/s (seed 000 Table 4, inner jib):
    overshoot exp(−ζπ/sqrt(1−ζ²)) and time to peak π/(ω sqrt(1−ζ²))."""
    zeta, omega, step = 0.8, 250.0, 0.5
    text = f"""
name: spool
inputs: {{u: {{unit: "1"}}}}
components:
  supply: {{type: pressure_source, ports: {{P: ps}}, p: 100e5}}
  tank: {{type: tank, ports: {{T: pt}}}}
  la: {{type: pressure_source, ports: {{P: na}}, p: 30e5}}
  lb: {{type: pressure_source, ports: {{P: nb}}, p: 30e5}}
  valve: {{type: valve_4_3, ports: {{P: ps, T: pt, A: na, B: nb, cmd: u}}, tau: {1 / omega}, zeta: {zeta},
           s_max: 1.0e5, tau_rl: 1.0e-6}}
"""
    mdl, tr, _ = run(text, 0.06, n=60001, inputs={"u": step})
    xv = col(mdl, tr, "valve.xv")
    k = int(np.argmax(xv))
    wd = omega * math.sqrt(1 - zeta ** 2)
    assert xv[k] / step - 1 == pytest.approx(math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2)), rel=0.03)
    assert tr.t[k] == pytest.approx(math.pi / wd, rel=0.01)
    assert xv[-1] == pytest.approx(step, rel=1e-4)


def test_spring_mass_damper_step():
    """m ẍ + c ẋ + k x = F: x(t) = F/k·(1 − e^(−ζωt)(cos ω_d t + ζ/sqrt(1−ζ²) sin ω_d t))."""
    m, k, c, F = 2.0, 800.0, 8.0, 10.0
    text = f"""
name: smd
components:
  body: {{type: mass, ports: {{m: n}}, m: {m}, F_const: {F}}}
  spring: {{type: spring, ports: {{a: n, b: ground}}, k: {k}}}
  damper: {{type: damper, ports: {{a: n, b: ground}}, c: {c}}}
"""
    mdl, tr, _ = run(text, 2.0, n=2001)
    w = math.sqrt(k / m)
    z = c / (2 * math.sqrt(k * m))
    wd = w * math.sqrt(1 - z * z)
    t = tr.t
    ref = F / k * (1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / math.sqrt(1 - z * z) * np.sin(wd * t)))
    assert np.max(np.abs(col(mdl, tr, "n.x") - ref)) < 1e-4 * F / k * 2


@pytest.mark.parametrize("rotary", [False, True])
def test_a_hardening_spring_settles_where_its_force_law_puts_it(rotary):
    """dF/dt = k·(1 + h·F²)·v, so the deflection under a force F is
    ∫₀^F dF'/(k(1 + h·F'²)) = arctan(√h·F)/(k·√h) (linear limit F/k); the same law for a
    torsion shaft. A constant force on a damped mass settles there."""
    k, h, F = 800.0, 4e-3, 25.0                     # h·F² = 2.5: the stiffness 3.5× at the end
    if rotary:
        body = f"body: {{type: inertia, ports: {{r: n}}, J: 2.0, tau_const: {F}}}"
        spring = f"spring: {{type: shaft, ports: {{a: n, b: ground}}, k: {k}, h: {h}}}"
        damper = "damper: {type: rotary_damper, ports: {a: n, b: ground}, b: 200.0}"
        pos = "n.theta"
    else:
        body = f"body: {{type: mass, ports: {{m: n}}, m: 2.0, F_const: {F}}}"
        spring = f"spring: {{type: spring, ports: {{a: n, b: ground}}, k: {k}, h: {h}}}"
        damper = "damper: {type: damper, ports: {a: n, b: ground}, c: 200.0}"
        pos = "n.x"
    text = f"""
name: hardening
components:
  {body}
  {spring}
  {damper}
"""
    mdl, tr, _ = run(text, 6.0, n=601)
    x = col(mdl, tr, pos)
    settled = math.atan(math.sqrt(h) * F) / (k * math.sqrt(h))
    assert x[-1] == pytest.approx(settled, rel=1e-4)
    assert settled < 0.7 * F / k                     # well away from the linear spring's F/k (0.64)


def test_volume_continuity_flow_source():
    """∫q dt = (V/β)·Δp for a volume fed by a time-varying flow source."""
    V = 2e-4
    text = f"""
name: fill
fluid: {{beta: {BETA}}}
inputs: {{Q: {{unit: m^3/s}}}}
components:
  pump: {{type: flow_source, ports: {{P: n, ref: Q}}}}
  vol: {{type: volume, ports: {{P: n}}, V: {V}}}
"""
    q = lambda t: {"Q": 1e-5 * (1 + np.sin(20 * t))}
    mdl, tr, tab = run(text, 0.5, n=5001, inputs=q)
    qs = q(tr.t)["Q"]
    vol_in = np.concatenate([[0], np.cumsum(0.5 * (qs[1:] + qs[:-1]) * np.diff(tr.t))])
    dp = col(mdl, tr, "n.p") - col(mdl, tr, "n.p")[0]
    assert np.allclose(vol_in, V / BETA * dp, rtol=1e-4, atol=1e-10)


def test_orifice_between_volumes_conserves_mass():
    """Two volumes joined by an orifice: V1·Δp1 + V2·Δp2 = 0 at all times, the pressures
    equalise at (V1 p1 + V2 p2)/(V1 + V2), and ∫q dt = −(V1/β)·Δp1."""
    V1, V2, p1, p2 = 1e-4, 3e-4, 80e5, 10e5
    text = f"""
name: two_volumes
fluid: {{beta: {BETA}}}
components:
  v1: {{type: volume, ports: {{P: n1}}, V: {V1}}}
  v2: {{type: volume, ports: {{P: n2}}, V: {V2}}}
  orif: {{type: orifice, ports: {{A: n1, B: n2}}, Kv: 1e-8}}
initial: {{n1.p: {p1}, n2.p: {p2}}}
"""
    mdl, tr, tab = run(text, 0.2, n=4001)
    P1, P2 = col(mdl, tr, "n1.p"), col(mdl, tr, "n2.p")
    assert np.max(np.abs(V1 * (P1 - p1) + V2 * (P2 - p2))) < 1e-6 * V1 * (p1 - p2)
    assert P1[-1] == pytest.approx((V1 * p1 + V2 * p2) / (V1 + V2), rel=1e-4)
    q = mdl.evaluate_along(tr.t, tr.X, np.zeros((len(tr.t), 0)), mdl.p0)["orif.q"]
    moved = np.concatenate([[0], np.cumsum(0.5 * (q[1:] + q[:-1]) * np.diff(tr.t))])
    assert np.allclose(moved, -V1 / BETA * (P1 - p1), rtol=2e-3, atol=1e-3 * V1 / BETA * (p1 - p2))
