"""Seal friction loaded by the chamber pressures (seed 000 eq. 23), on a rod and on a vane
shaft, against the closed form of a body coasting to rest under a constant friction: with
the pressures held, F = size·(μ_s·(p_a + p_b) + μ_d·|p_a − p_b|) is constant while the speed
is far above the smoothing band, so v(t) = v0 − F·t/m (ω(t) = ω0 − τ·t/J). |Δp| is the
element's √(Δp² + Δp_ε²) with its default Δp_ε = 0.1 bar; the rod's element adds its rod seal,
μ_b·A·p_b, the vane's its hub seals on each side, (μ_a·p_a + μ_b·p_b)·D."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

PA, PB, MU_S, MU_D, MU_B, MU_A = 80e5, 30e5, 0.01, 0.05, 0.03, 0.02

COAST = """
name: coasting_{kind}
components:
  supply_a: {{type: pressure_source, ports: {{P: ca}}, p: {pa}}}
  supply_b: {{type: pressure_source, ports: {{P: cb}}, p: {pb}}}
  body: {{type: {load}, ports: {{{lport}: shaft}}, {lpar}: {mass}}}
  seals: {{type: {seal}, ports: {{a: shaft, b: ground, pa: ca, pb: cb}}, mu_s: {mu_s}, mu_d: {mu_d},
          {size}: {area}, eps: 1.0e-4{rod}}}
outputs:
  v: shaft.{across}
initial:
  shaft.{across}: {v0}
"""


@pytest.mark.parametrize("kind", ["translational", "rotary"])
def test_a_body_coasts_to_rest_at_the_seals_constant_deceleration(kind):
    rotary = kind == "rotary"
    mass, area, v0 = (0.5, 2.0e-5, 3.0) if rotary else (200.0, 5.0e-3, 0.4)
    text = COAST.format(kind=kind, pa=PA, pb=PB, mass=mass, mu_s=MU_S, mu_d=MU_D, area=area, v0=v0,
                        load="inertia" if rotary else "mass", lport="r" if rotary else "m",
                        lpar="J" if rotary else "m", seal="rotary_seal_friction" if rotary else "seal_friction",
                        size="D_p" if rotary else "A_p", across="w" if rotary else "v",
                        rod=f", mu_a: {MU_A}, mu_b: {MU_B}" if rotary else f", mu_b: {MU_B}")
    model = build_model(load_netlist_text(text, f"{kind}.yaml"))
    force = area * (MU_S * (PA + PB) + MU_D * np.hypot(PA - PB, 1e4) + MU_B * PB + (MU_A * PA if rotary else 0.0))
    t_stop = v0 * mass / force
    t = np.linspace(0.0, 0.8 * t_stop, 401)
    tr = simulate(model, InputTable(np.array([0.0]), np.zeros((1, 0))), t, opts=SolverOptions(rtol=1e-9))
    v = tr.Y[:, 0]
    assert np.abs(v - (v0 - force * t / mass)).max() < 1e-7 * v0
