"""Initial values given by a rule in the machine file's ``initial:`` section (same_as, output,
balance), resolved per experiment by experiments.initial; checked against closed forms: a mass
hung on a spring at t = 0 drops and rings with amplitude m·g/k about its rest position, and
starts AT rest when the spring's force is balanced."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.errors import NetlistError
from hydrocli.experiments.experiment import Experiment
from hydrocli.experiments.initial import initial_state
from hydrocli.identify.cost import Objective, make_targets
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

M, K, G = 20.0, 8.0e4, 9.81

HANG = f"""
name: hanging_mass
inputs: {{F: {{unit: N}}}}
components:
  mass: {{type: mass, ports: {{m: load}}, m: {{value: {M}, free: true}}, F_const: {{value: {-M * G}, free: true}}}}
  spring: {{type: spring, ports: {{a: load, b: ground}}, k: {K}}}
  push: {{type: force_source, ports: {{a: load, F: F}}}}
  frame: {{type: mass, ports: {{m: body}}, m: 5.0}}
  mount: {{type: spring, ports: {{a: body, b: ground}}, k: 1.0e6}}
outputs:
  x: load.x
  stroke: "load.x - body.x"
  f: spring.F
initial:
  body.x: "2 mm"
{{rules}}
"""


def _model(rules: str = ""):
    return build_model(load_netlist_text(HANG.replace("{rules}", rules), "hang.yaml"))


def _exp(model, measured=None, t_end=0.2):
    t = np.arange(0.0, t_end, 1e-4)
    return Experiment("e", "e.csv", InputTable(np.array([0.0]), np.zeros((1, 1))), t, measured=measured or {})


def test_a_mass_hung_on_a_relaxed_spring_drops_and_rings_by_mg_over_k():
    model = _model()
    e = _exp(model)
    tr = simulate(model, e.inputs, e.t_out, x0=initial_state(model, e), opts=SolverOptions(rtol=1e-8))
    x = tr.Y[:, model.output_names.index("x")]
    # undamped: x(t) = −(m g/k)(1 − cos ωt); the lowest point is 2 m g/k below the start
    assert x.min() == pytest.approx(-2 * M * G / K, rel=1e-3)
    w = np.sqrt(K / M)
    assert np.allclose(x, -(M * G / K) * (1 - np.cos(w * e.t_out)), atol=1e-6)


def test_a_balanced_spring_starts_the_mass_at_rest_for_every_parameter_value():
    model = _model("  spring.dF: {balance: load.v}\n")
    e = _exp(model)
    for m in (M, 3 * M):
        p = model.param_vector({"mass.m": m, "mass.F_const": -m * G})
        x0 = initial_state(model, e, p)
        assert x0[model.state_index("spring.dF")] == pytest.approx(-m * G, rel=1e-9)   # carries the weight (F_const)
        tr = simulate(model, e.inputs, e.t_out, p=p, x0=x0, opts=SolverOptions(rtol=1e-8))
        assert np.abs(tr.Y[:, model.output_names.index("x")]).max() < 1e-9


def test_same_as_and_output_rules_follow_the_measured_start():
    model = _model("  load.x: {same_as: body.x}\n")     # a rule on a state no output reads
    e = _exp(model)
    x0 = initial_state(model, e)
    assert x0[model.state_index("load.x")] == pytest.approx(0.002)
    # the stroke is read relative to the moving body: the load starts where the measured
    # stroke puts it, whatever the body's start
    model = _model("  load.x: {output: stroke}\n")
    e = _exp(model, measured={"stroke": np.full(2000, 0.050)})
    x0 = initial_state(model, e)
    assert x0[model.state_index("load.x")] - x0[model.state_index("body.x")] == pytest.approx(0.050)


def test_sensitivities_carry_the_balanced_start():
    """∂y/∂p through the balanced spring force: forward sensitivities with ∂x0/∂p equal
    finite differences of whole simulations (the spring force moves with the weight, the
    position with the mass once the force input shakes it)."""
    model = _model("  spring.dF: {balance: load.v}\n")
    t = np.arange(0.0, 0.05, 1e-3)
    u = InputTable(t, (50.0 * np.sin(2 * np.pi * 20 * t))[:, None])
    y = np.zeros_like(t)
    e = Experiment("e", "e.csv", u, t, measured={"x": y, "f": y})
    obj = Objective(model, make_targets(model, [e]), SolverOptions(rtol=1e-10))
    p = model.p0
    r, J = obj.residuals_jacobian(p, ["mass.F_const", "mass.m"])
    for c, name in enumerate(["mass.F_const", "mass.m"]):
        q = p.copy()
        k = model.param_index(name)
        h = 1e-2 * abs(p[k])
        q[k] += h
        r = p.copy()
        r[k] -= h
        fd = (obj.residuals(q) - obj.residuals(r)) / (2 * h)
        assert np.abs(fd).max() > 0
        assert np.allclose(J[:, c], fd, rtol=1e-3, atol=1e-4 * np.abs(fd).max())


def test_sensitivities_of_a_balance_hold_for_a_parameter_at_zero():
    """A constant force free from 0 (bounds given) beside a recorded 196 N pull: ∂(spring
    force)/∂F_const is the same at any value, so the finite-difference step of the balance
    must not shrink to nothing at 0 (a step of 1e-18 N is lost on a 196 N spring force)."""
    model = build_model(load_netlist_text(HANG.replace("{rules}", "  spring.dF: {balance: load.v}\n")
                                          .replace(f"F_const: {{value: {-M * G}, free: true}}",
                                                   "F_const: {value: 0.0, free: true, bounds: [-1000, 1000]}"),
                                          "hang.yaml"))
    t = np.arange(0.0, 0.02, 1e-3)
    e = Experiment("e", "e.csv", InputTable(t, np.full((t.size, 1), -M * G)), t, measured={"f": np.zeros_like(t)})
    obj = Objective(model, make_targets(model, [e]), SolverOptions(rtol=1e-10))
    p = model.p0
    assert p[model.param_index("mass.F_const")] == 0.0
    _, J = obj.residuals_jacobian(p, ["mass.F_const"])
    k = model.param_index("mass.F_const")
    q, r = p.copy(), p.copy()
    q[k], r[k] = 1.0, -1.0
    fd = (obj.residuals(q) - obj.residuals(r)) / 2.0
    assert np.abs(fd).min() > 0
    assert np.allclose(J[:, 0], fd, rtol=1e-6)


@pytest.mark.parametrize("rule, says", [("  spring.dF: {balance: lod.v}\n", "unknown state 'lod.v'"),
                                        ("  load.x: {output: strok}\n", "unknown output 'strok'"),
                                        ("  load.x: {equal: body.x}\n", "one rule")])
def test_a_bad_rule_names_the_entry_and_what_to_write(rule, says):
    with pytest.raises(NetlistError) as err:
        _model(rule)
    text = str(err.value)
    assert says in text and "hang.yaml" in text
