"""Dynamic (LuGre) friction (Canudas de Wit et al. 1995 eqs. 1–3) against closed forms.

1. Sliding: a body coasting on a Coulomb contact (k_s = 0) decelerates at k_c/m once its
   bristles are deflected to k_c/σ0, which takes τ = k_c/(σ0·v0) (ż = v − σ0·v·z/k_c at v ≈ v0):
   v(t) = v0 − (k_c/m)·(t − τ·(1 − e^(−t/τ))) while v stays near v0 over τ.
2. Pre-sliding: a force far below breakaway (F/k_c = 1e-4) makes the contact a spring σ0
   with damping σ1 (the term σ0·|v|·z/g is F/k_c of ż): the body rings about F/σ0 at
   ω_d = √(σ0/m − (σ1/2m)²), x(t) = F/σ0·(1 − e^(−ζω_n t)(cos ω_d t + ζ/√(1−ζ²)·sin ω_d t)).
   The same on a shaft (``rotary_friction_lugre``): ω(t) = ω0 − (τ_c/J)·(t − τ·(1 − e^(−t/τ))).
3. The static element's steady force is the sliding limit: at a constant speed the bristles
   settle at g(v)/σ0 and F = k_v·v + g(v), g(v) = k_c + k_s·e^(−|v|/v_s).
"""
from __future__ import annotations

import numpy as np

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

BODY = """
name: lugre_{tag}
components:
  body: {{type: mass, ports: {{m: rod}}, m: {m}, F_const: {force}}}
  contact: {{type: friction_lugre, ports: {{a: rod, b: ground}}, kc_p: {kc}, kc_m: {kc}, ks_p: {ks}, ks_m: {ks},
            kv_p: {kv}, kv_m: {kv}, vs_p: {vs}, vs_m: {vs}, sigma0: {s0}, sigma1: {s1}}}
outputs:
  x: rod.x
  v: rod.v
  z: contact.z
initial:
  rod.v: {v0}
"""


def _run(t, **kw):
    args = dict(tag="t", m=200.0, force=0.0, kc=500.0, ks=0.0, kv=0.0, vs=1e-3, s0=1e8, s1=0.0, v0=0.0)
    args.update(kw)
    model = build_model(load_netlist_text(BODY.format(**args), "lugre.yaml"))
    tr = simulate(model, InputTable(np.array([0.0]), np.zeros((1, 0))), t, opts=SolverOptions(rtol=1e-10))
    return {n: tr.Y[:, k] for k, n in enumerate(model.output_names)}


def test_a_sliding_body_decelerates_at_the_coulomb_force_once_its_bristles_are_deflected():
    m, kc, s0, v0 = 200.0, 500.0, 1e8, 0.4
    tau = kc / (s0 * v0)
    t = np.linspace(0.0, 0.05, 2001)
    y = _run(t, m=m, kc=kc, s0=s0, v0=v0)
    exact = v0 - kc / m * (t - tau * (1.0 - np.exp(-t / tau)))
    assert np.abs(y["v"] - exact).max() < 1e-5 * v0
    assert abs(y["z"][-1] - kc / s0) < 1e-3 * kc / s0          # deflected to the breakaway


def test_a_force_below_breakaway_rings_on_the_bristle_spring():
    m, kc, s0, s1, f = 200.0, 500.0, 1e8, 2.0e4, 0.05
    wn = np.sqrt(s0 / m)
    zeta = s1 / (2.0 * np.sqrt(s0 * m))
    wd = wn * np.sqrt(1.0 - zeta**2)
    t = np.linspace(0.0, 10 * 2 * np.pi / wn, 4001)
    y = _run(t, m=m, kc=kc, s0=s0, s1=s1, force=f)
    exact = f / s0 * (1.0 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / np.sqrt(1 - zeta**2) * np.sin(wd * t)))
    assert np.abs(y["x"] - exact).max() < 2e-3 * f / s0
    assert np.abs(y["x"]).max() < 2.0 * f / s0                 # it never slides


def test_the_steady_sliding_force_is_the_static_law():
    """A body pushed by a constant force F settles at the speed where the static law carries
    F: k_v·v + k_c + k_s·e^(−v/v_s) = F (solved by bisection here; g carries the element's
    floor G_MIN = 1 mN)."""
    from hydrocli.components.mechanical.lugre import G_MIN
    m, kc, ks, kv, vs, f = 50.0, 300.0, 200.0, 2000.0, 0.01, 700.0
    lo, hi = 0.0, f / kv
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if kv * mid + kc + ks * np.exp(-mid / vs) + G_MIN < f else (lo, mid)
    t = np.linspace(0.0, 1.0, 201)
    y = _run(t, m=m, kc=kc, ks=ks, kv=kv, vs=vs, force=f, s1=100.0, v0=0.05)
    assert abs(y["v"][-1] - lo) < 1e-6 * lo
    assert abs(y["z"][-1] - (kc + ks * np.exp(-lo / vs) + G_MIN) / 1e8) < 1e-6 * kc / 1e8


def test_a_coasting_shaft_decelerates_at_the_coulomb_torque_once_its_bristles_are_deflected():
    j, tc, s0, w0 = 0.5, 20.0, 1e6, 3.0
    text = f"""
name: lugre_shaft
components:
  arm: {{type: inertia, ports: {{r: shaft}}, J: {j}}}
  seals: {{type: rotary_friction_lugre, ports: {{a: shaft, b: ground}}, tau_c: {tc}, tau_s: 0.0, b: 0.0,
          sigma0: {s0}, sigma1: 0.0}}
outputs:
  w: shaft.w
  z: seals.z
initial:
  shaft.w: {w0}
"""
    model = build_model(load_netlist_text(text, "shaft.yaml"))
    from hydrocli.components.mechanical.lugre import G_MIN
    tc += G_MIN                   # the floor of g, 1 mN·m: 1e-4 rad/s after 0.05 s on this shaft
    tau = tc / (s0 * w0)
    t = np.linspace(0.0, 0.05, 2001)
    tr = simulate(model, InputTable(np.array([0.0]), np.zeros((1, 0))), t, opts=SolverOptions(rtol=1e-10))
    exact = w0 - tc / j * (t - tau * (1.0 - np.exp(-t / tau)))
    assert np.abs(tr.Y[:, 0] - exact).max() < 1e-5 * w0
    assert abs(tr.Y[-1, 1] - tc / s0) < 1e-3 * tc / s0
