"""The vapour-pressure / gas-release floor of volumes and cylinder chambers, against its
closed form, and unchanged equations well above the vapour pressure.

A volume V (bulk modulus β, capacitance C = V/β) drained by a constant flow q from p0:
    p(t) = p0 − k t,  k = q/C,                        until p = p_vap at t1 = (p0 − p_vap)/k
    p(t) = p_vap − k τ + k τ · exp(−(t − t1)/τ),        after (C dp/dt = −q + C (p_vap − p)/τ)
so the pressure settles at p_vap − q τ/C instead of falling through zero."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

V, BETA, Q, P0 = 1e-4, 1.5e9, 1e-7, 10e5


def _drained(p_vap: str | None = "2 kPa", tau: str = "1 ms", extra: str = ""):
    """The floor set once for the machine (fluid: p_vap), or left at its default (None: off)."""
    fluid_vap = f", p_vap: {p_vap}" if p_vap is not None else ""
    text = f"""
name: drained
fluid: {{beta: {BETA}, p_tank: 1 bar{fluid_vap}}}
components:
  vol: {{type: volume, ports: {{P: a}}, V: {V}, tau_cav: "{tau}"}}
  drain: {{type: flow_source, ports: {{P: a}}, Q: {-Q}}}
{extra}
initial: {{a.p: {P0}}}
"""
    return build_model(load_netlist_text(text, "drained.yaml"))


def _run(model, t):
    u = InputTable(np.array([0.0]), np.zeros((1, 0)))
    tr = simulate(model, u, t, opts=SolverOptions(rtol=1e-8))
    return tr.X[:, model.state_index("a.p")]


def _closed_form(t, p_vap, tau):
    C = V / BETA
    k = Q / C
    t1 = (P0 - p_vap) / k
    return np.where(t < t1, P0 - k * t, p_vap - k * tau + k * tau * np.exp(-(t - t1) / tau))


def test_volume_drained_below_vapour_pressure_follows_the_closed_form():
    p_vap, tau = 2e3, 1e-3
    k = Q / (V / BETA)                                   # 15 bar/s: p_vap reached after ~0.67 s
    t = np.linspace(0, 1.0, 2001)
    p = _run(_drained(), t)
    ref = _closed_form(t, p_vap, tau)
    assert np.max(np.abs(p - ref)) < 0.01 * k * tau + 1.0     # within 1 % of the sag k·τ (+1 Pa)
    assert p[-1] == pytest.approx(p_vap - k * tau, abs=5.0)   # settles at p_vap − qτ/C = 500 Pa
    assert p.min() > 0                                         # never below absolute zero


@pytest.mark.parametrize("p_vap", ["0 Pa", None])
def test_without_the_floor_the_pressure_falls_through_zero(p_vap):
    t = np.linspace(0, 1.0, 201)
    p = _run(_drained(p_vap=p_vap), t)          # the default (None) is off: machines keep their numbers
    assert p[-1] == pytest.approx(P0 - Q / (V / BETA) * t[-1], rel=1e-6)   # p0 − k t, negative
    assert p[-1] < 0


def test_above_the_vapour_pressure_the_floor_changes_nothing():
    t = np.linspace(0, 0.5, 101)                         # stays above 2.5 bar (15 bar/s from 10 bar)
    with_floor, without = _run(_drained(), t), _run(_drained(p_vap="0 Pa"), t)
    assert np.array_equal(with_floor, without)


def test_cylinder_chamber_has_the_floor():
    text = """
name: cyl_floor
fluid: {beta: 1.5e9, p_tank: 1 bar}
components:
  cyl: {type: cylinder, ports: {A: a, B: b, rod: piston, body: ground}, V_A0: 1e-4, V_B0: 1e-4, A_A: 1e-3, A_B: 1e-3,
        p_vap: 2 kPa}
  drain: {type: flow_source, ports: {P: a}, Q: -1e-7}
  fill: {type: flow_source, ports: {P: b}, Q: 1e-7}
  load: {type: mass, ports: {m: piston}, m: 100}
  lock: {type: spring, ports: {a: piston, b: ground}, k: 1e10}
  damp: {type: damper, ports: {a: piston, b: ground}, c: 1e6}
initial: {a.p: 10 bar, b.p: 10 bar}
"""
    model = build_model(load_netlist_text(text, "cyl.yaml"))
    u = InputTable(np.array([0.0]), np.zeros((1, 0)))
    tr = simulate(model, u, np.linspace(0, 1.0, 201), opts=SolverOptions(rtol=1e-8))
    pa = tr.X[:, model.state_index("a.p")]
    assert pa.min() > 0 and pa[-1] == pytest.approx(2e3 - 1e-7 * 1e-3 / (1e-4 / 1.5e9), rel=0.05)
