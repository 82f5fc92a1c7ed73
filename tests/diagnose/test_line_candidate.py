"""The line_dynamics candidate (hoses between a valve's work ports and the actuator) starts as
"no effect": a 5 cm hose inserted into a machine whose load hangs still at t = 0 must leave
the recording's start at rest, and the hose's own bulk modulus is its own parameter."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.experiments.experiment import Experiment
from hydrocli.experiments.initial import initial_state
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

ROOT = Path(__file__).parents[2]


def _held(model, p):
    """0.3 s with the valve commanded shut (the load held by the spool offset the file
    balances on chamber 1's pressure; chamber 2 settles from the file's start) and 160 bar
    supply: (P1 [Pa], theta [rad])."""
    t = np.arange(0.0, 0.3, 1e-3)
    u = np.zeros((1, len(model.input_names)))
    u[0, model.input_names.index("Ps")] = 1.6e7
    e = Experiment("held", "held.csv", InputTable(np.array([0.0]), u), t, measured={})
    tr = simulate(model, e.inputs, t, p=p, x0=initial_state(model, e, p), opts=SolverOptions(rtol=1e-8))
    return tr.Y[:, model.output_names.index("P1")], tr.Y[:, model.output_names.index("theta")]


def test_a_short_hose_added_to_a_held_winch_leaves_it_held():
    net = load_netlist(ROOT / "machines" / "hoist_winch.yaml")
    base = build_model(net)
    line = next(c for c in catalogue(Context(net, set(base.free_params)))[0] if c.effect == "line_dynamics")
    aug = line.build(net)
    model = build_model(aug)
    rules = {(r.state, r.kind, r.ref) for r in model.initial_rules}
    # the spool's offset now makes up for the leakage at the node the valve feeds, and each
    # hose's flow is what keeps its chamber's pressure still
    assert ("valve.xr", "balance", "chamber_1_valve.p") in rules
    assert {("valve_line_A.q0", "balance", "chamber_1.p"), ("valve_line_B.q0", "balance", "chamber_2.p")} <= rules
    p = model.param_vector({q.name: q.start for q in line.params})
    P1, theta = _held(model, p)
    P1_0, theta_0 = _held(base, base.p0)
    # the hose at its start is no effect: the same held load within 0.3 bar and 0.3 mrad
    # (measured 0.10 bar, 0.06 mrad; before, its flow started at zero while the motor's
    # chamber fed the load: 3.4 bar and 5.6 mrad apart)
    assert np.abs(P1 - P1_0).max() < 0.3e5
    assert np.abs(theta - theta_0).max() < 3e-4


def test_the_hoses_bulk_modulus_is_their_own_not_the_machines_fluid():
    """Freeing an inherited hose modulus would rewrite ``fluid.beta``: every chamber's start
    and bounds (and a restrained chamber modulus would reject the hose's start)."""
    net = load_netlist(ROOT / "machines" / "hoist_winch.yaml")
    line = next(c for c in catalogue(Context(net, set(build_model(net).free_params)))[0]
                if c.effect == "line_dynamics")
    aug = line.build(net)
    assert aug.doc["fluid"]["beta"] == net.doc["fluid"]["beta"]
    model = build_model(aug)
    assert model.p0[model.param_index("motor.beta")] == pytest.approx(1.5e9)
    assert model.p0[model.param_index("valve_line_A.beta")] == pytest.approx(1.0e9)
