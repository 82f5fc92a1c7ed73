"""A rope paid out by a drum (``shaft`` with ``wind`` = r/L₀): its stiffness EA/L with
L = L₀·(1 − wind·θ_a) is k/(1 − wind·θ_a). A drum on such a rope to ground (θ_a is the
deflection itself) has the closed forms τ = −(k/w)·ln(1 − w·θ) and the potential
U = (k/w²)·[(1 − w·θ)·ln(1 − w·θ) − (1 − w·θ) + 1]; energy ½J·ω² + U is conserved. Beyond
the shortest rope (``ROPE_MIN`` of L₀) the stiffness stays at k/ROPE_MIN."""
from __future__ import annotations

import numpy as np

from hydrocli.components.rotational.elements import ROPE_MIN
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

K, J = 2.0e4, 5.0                    # N·m/rad, kg·m²

DRUM = """
name: drum_rope
inputs: {{u: {{unit: "1"}}}}
components:
  drum: {{type: inertia, ports: {{r: n}}, J: {J}}}
  rope: {{type: shaft, ports: {{a: n, b: ground}}, k: {k}, wind: {w}}}
outputs: {{x: n.theta, v: n.w, F: rope.tau}}
initial: {{n.w: {v0}}}
"""


def _run(w: float, v0: float):
    model = build_model(load_netlist_text(DRUM.format(J=J, k=K, w=w, v0=v0)))
    t = np.linspace(0.0, 0.2, 4001)
    res = simulate(model, InputTable(np.array([0.0]), np.array([[0.0]])), t,
                   opts=SolverOptions(rtol=1e-10, atol_factor=1e-3))
    return {o: res.Y[:, i] for i, o in enumerate(model.output_names)}


def test_wound_rope_stiffens_as_eal():
    w, v0 = 1.0, 30.0                # swing ±0.4 rad: the rope from 0.6 to 1.4 of its length
    y = _run(w, v0)
    th, tau = y["x"], y["F"]
    assert th.max() > 0.3 and th.min() < -0.3
    law = -(K / w) * np.log(1.0 - w * th)
    assert np.max(np.abs(tau - law)) <= 1e-6 * np.max(np.abs(tau))
    # not a linear spring: hoisting (θ > 0) is stiffer than paying out
    assert tau.max() > 1.2 * abs(tau.min())
    u = 1.0 - w * th
    energy = 0.5 * J * y["v"] ** 2 + (K / w ** 2) * (u * np.log(u) - u + 1.0)
    assert np.max(np.abs(energy - 0.5 * J * v0 ** 2)) <= 1e-6 * 0.5 * J * v0 ** 2


def test_unwound_rope_is_the_shaft():
    y = _run(0.0, 30.0)
    assert np.max(np.abs(y["F"] - K * y["x"])) <= 1e-6 * np.max(np.abs(y["F"]))


def test_rope_never_shorter_than_its_floor():
    w, v0 = 1.0, 60.0                # hoisted past 1 − w·θ = ROPE_MIN
    y = _run(w, v0)
    th, tau = y["x"], y["F"]
    edge = (1.0 - ROPE_MIN) / w
    assert th.max() > edge + 0.02
    law = np.where(th <= edge, -(K / w) * np.log(np.maximum(1.0 - w * th, ROPE_MIN)),
                   -(K / w) * np.log(ROPE_MIN) + K / ROPE_MIN * (th - edge))
    assert np.max(np.abs(tau - law)) <= 1e-5 * np.max(np.abs(tau))
