"""Air-in-oil bulk modulus (components/hydraulic/fluid.py) against the closed forms of the
mixture: with the free-air fraction α' of the mixture at pressure p,
1/β_e = (1 − α')/β + α'/(n·p) (Merritt §2.2; Gholizadeh, Burton & Schoenau 2011)."""
import pytest

from hydrocli.components.hydraulic.fluid import effective_bulk_modulus

BETA = 1.5e9


def _value(*args):
    e = effective_bulk_modulus(*args)
    return e.value if hasattr(e, "value") else e


def _mixture(alpha0, p, n, dissolved=1.0):
    r = alpha0 * (1e5 / p) ** (1 / n) * dissolved      # free air at p, per unit oil volume
    a = r / (1 + r)
    return 1.0 / ((1 - a) / BETA + a / (n * p))


def test_no_air_is_the_oil():
    assert _value(BETA, 50e5, 0.0) == BETA


@pytest.mark.parametrize("p", [1e5, 10e5, 100e5])
@pytest.mark.parametrize("n", [1.0, 1.4])
def test_free_air_isothermal_and_isentropic(p, n):
    assert _value(BETA, p, 0.02, n) == pytest.approx(_mixture(0.02, p, n), rel=1e-9)


def test_at_one_bar_isothermal_air_is_softer_than_isentropic():
    """Same free air at p₀; the gas stiffness is n·p."""
    assert _value(BETA, 1e5, 0.02, 1.0) < _value(BETA, 1e5, 0.02, 1.4) < BETA


def test_henry_dissolution_is_linear_down_to_the_dissolution_pressure():
    p, p_d = 50e5, 150e5
    d = 1 - (p - 1e5) / (p_d - 1e5)
    assert _value(BETA, p, 0.05, 1.0, p_d) == pytest.approx(_mixture(0.05, p, 1.0, d), rel=1e-5)
    # above the dissolution pressure no free air is left: the oil's modulus (to the smoothing)
    assert _value(BETA, 200e5, 0.05, 1.0, p_d) == pytest.approx(BETA, rel=1e-4)


def test_vane_actuator_chambers_hold_air_like_a_cylinders():
    """A vane actuator's chamber with entrained air: at rest, a flow q into chamber 1 raises
    its pressure at dp/dt = q·β_e(p)/(V_1 + D_v·θ) with β_e the mixture's closed form."""
    import numpy as np
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist_text
    text = """
name: vane_air
fluid: {beta: "1.5 GPa", p_tank: "1 bar"}
components:
  pump: {type: flow_source, ports: {P: c1}, Q: 1.0e-5}
  vane: {type: vane_actuator, ports: {A: c1, B: c2, shaft: arm, body: ground}, D_v: 5.0e-6, V_1: 2.0e-5,
         V_2: 2.0e-5, R_v: 0.0, air: 0.1, air_n: 1.0}
  arm_inertia: {type: inertia, ports: {r: arm}, J: 0.05}
outputs: {p1: c1.p}
initial: {c1.p: "50 bar", c2.p: "50 bar", arm.theta: 0.2}
"""
    m = build_model(load_netlist_text(text, "vane_air.yaml"))
    x0 = np.array([{"c1.p": 50e5, "c2.p": 50e5, "arm.theta": 0.2}.get(s, 0.0) for s in m.state_names])
    dx, *_ = m.numpy_evaluate()(0.0, list(x0), m.p0, [])
    dp1 = float(np.asarray(dx[m.state_index("c1.p")]))
    beta_e = _mixture(0.1, 50e5, 1.0)
    assert dp1 == pytest.approx(1e-5 * beta_e / (2e-5 + 5e-6 * 0.2), rel=1e-6)
    assert beta_e < 0.7 * BETA      # the air matters at 50 bar


@pytest.mark.parametrize("air, n", [(0.0, 1.4), (0.1, 1.0), (0.05, 1.4)])
def test_motor_chambers_hold_air_like_the_vanes(air, n):
    """A motor's chamber volume V_A with entrained air (the same fraction in both chambers:
    the oil carries it): at rest, a flow q into chamber A raises its pressure at
    dp/dt = q·β_e(p)/V_A, β_e the mixture's closed form (the oil's β without air); chamber B,
    at a lower pressure, is softer by its own β_e."""
    import numpy as np
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist_text
    text = f"""
name: motor_air
fluid: {{beta: "1.5 GPa", p_tank: "1 bar"}}
components:
  pump: {{type: flow_source, ports: {{P: c1}}, Q: 1.0e-5}}
  pump_b: {{type: flow_source, ports: {{P: c2}}, Q: 1.0e-5}}
  motor: {{type: hydraulic_motor, ports: {{A: c1, B: c2, shaft: drum_node, body: ground}}, D_m: 8.0e-5,
          R_m: 1.0e30, R_ex: 1.0e30, V_A: 6.0e-4, V_B: 6.0e-4, air: {air}, air_n: {n}}}
  drum: {{type: inertia, ports: {{r: drum_node}}, J: 10.0}}
outputs: {{p1: c1.p}}
initial: {{c1.p: "120 bar", c2.p: "40 bar"}}
"""
    m = build_model(load_netlist_text(text, "motor_air.yaml"))
    x0 = np.array([{"c1.p": 120e5, "c2.p": 40e5}.get(s, 0.0) for s in m.state_names])
    dx, *_ = m.numpy_evaluate()(0.0, list(x0), m.p0, [])
    for node, p in (("c1.p", 120e5), ("c2.p", 40e5)):
        beta_e = _mixture(air, p, n) if air else BETA
        assert float(np.asarray(dx[m.state_index(node)])) == pytest.approx(1e-5 * beta_e / 6e-4, rel=1e-6)
    if air:
        assert _mixture(air, 40e5, n) < 0.8 * _mixture(air, 120e5, n)   # softer where the pressure is lower
