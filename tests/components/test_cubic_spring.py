"""The cubic (Duffing) hardening of the spring and the torsion shaft (``hc``): a mass on the
spring, launched from rest length, against the closed forms F = k·d + k₃·d³ (k₃ = hc·k³/3)
and conservation of ½m·v² + ½k·d² + ¼k₃·d⁴; and the force-carried hardening ``h`` against
its own closed form d = atan(√h·F)/(√h·k)."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

K, M, V0 = 2.0e4, 5.0, 1.5           # N/m, kg, m/s: a swing of ~2.4 cm
HC = 40.0 / (K * 0.024) ** 2        # hc·(k·d)² = 40 at the swing's end: strongly hardening

LINEAR = """
name: duffing
inputs: {{u: {{unit: "1"}}}}
components:
  body: {{type: mass, ports: {{m: n}}, m: {m}}}
  link: {{type: spring, ports: {{a: n, b: ground}}, k: {k}, {law}}}
outputs: {{x: n.x, v: n.v, F: link.F}}
initial: {{n.v: {v0}}}
"""

ROTARY = """
name: duffing_rotary
inputs: {{u: {{unit: "1"}}}}
components:
  arm: {{type: inertia, ports: {{r: n}}, J: {m}}}
  link: {{type: shaft, ports: {{a: n, b: ground}}, k: {k}, {law}}}
outputs: {{x: n.theta, v: n.w, F: link.tau}}
initial: {{n.w: {v0}}}
"""


def _run(template: str, law: str):
    text = template.format(m=M, k=K, v0=V0, law=law)
    model = build_model(load_netlist_text(text))
    t = np.linspace(0.0, 0.2, 2001)
    res = simulate(model, InputTable(np.array([0.0]), np.array([[0.0]])), t,
                   opts=SolverOptions(rtol=1e-10, atol_factor=1e-3))
    y = {o: res.Y[:, i] for i, o in enumerate(model.output_names)}
    return y


@pytest.mark.parametrize("template", [LINEAR, ROTARY], ids=["spring", "shaft"])
def test_cubic_hardening_is_the_duffing_spring(template):
    y = _run(template, f"hc: {HC!r}")
    k3 = HC * K ** 3 / 3.0
    d = y["x"]                       # deflection x_a − x_b, b on ground (dF/dt = k_t·(v_a − v_b))
    F = y["F"]
    # the spring's force follows its deflection by F = k·d + k₃·d³
    law = K * d + k3 * d ** 3
    assert np.max(np.abs(F - law)) <= 1e-6 * np.max(np.abs(F))
    assert np.max(np.abs(d)) > 0.005
    # strongly hardening: the force at the end of the swing is far above the linear spring's
    assert np.max(np.abs(F)) > 5.0 * K * np.max(np.abs(d))
    # conservation of ½m·v² + ½k·d² + ¼k₃·d⁴
    E = 0.5 * M * y["v"] ** 2 + 0.5 * K * d ** 2 + 0.25 * k3 * d ** 4
    assert np.max(np.abs(E - 0.5 * M * V0 ** 2)) <= 1e-6 * 0.5 * M * V0 ** 2


def test_force_hardening_follows_its_own_law():
    """dF/dd = k·(1 + h·F²) integrates to F = tan(√h·k·d)/√h."""
    h = 40.0 / (K * 0.024) ** 2 / 10.0
    y = _run(LINEAR, f"h: {h!r}")
    d = y["x"]
    law = np.tan(np.sqrt(h) * K * d) / np.sqrt(h)
    assert np.max(np.abs(y["F"] - law)) <= 1e-6 * np.max(np.abs(y["F"]))


def test_small_cubic_hardening_uses_the_series_without_loss():
    """Far below the series switch (hc·F² < 1e-3) the spring is the linear one plus k₃·d³."""
    hc = 1e-6 / (K * 0.024) ** 2
    y = _run(LINEAR, f"hc: {hc!r}")
    d = y["x"]
    k3 = hc * K ** 3 / 3.0
    assert np.max(np.abs(y["F"] - (K * d + k3 * d ** 3))) <= 1e-8 * np.max(np.abs(y["F"]))


def test_cubic_law_holds_across_the_series_switch():
    """A swing whose hc·F² crosses the series switch (10⁻³) on the way up to ~10⁻²: the force
    follows F = k·d + k₃·d³ on both branches, and through the switch."""
    hc = 1e-2 / (K * 0.024) ** 2
    y = _run(LINEAR, f"hc: {hc!r}")
    d, F = y["x"], y["F"]
    z = hc * F ** 2
    assert z.max() > 3e-3 and np.any((z > 0) & (z < 1e-3))
    k3 = hc * K ** 3 / 3.0
    assert np.max(np.abs(F - (K * d + k3 * d ** 3))) <= 1e-7 * np.max(np.abs(F))
