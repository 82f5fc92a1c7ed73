"""A transducer at rest reads what it senses (``Equations.rest``): a recording that starts a
lagging sensor's state at its first sample starts the sensed chamber pressure or rod motion
there too, and without a sample the sensor starts on its node. Checked against closed forms:
a closed, leak-free chamber holds its pressure, so its lagged reading is constant when both
start alike and is p_file + (p_meas − p_file)·e^(−t/τ) when only the sensor starts from the
sample (the transient a machine file written with sensors used to show under
``hydro validate``); a free mass coasts, so its lagged position reads x0 + v0·(t − τ(1 − e^(−t/τ)))."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.experiments.experiment import Experiment
from hydrocli.experiments.initial import initial_state
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

TAU, P_FILE, P_MEAS = 0.003, 35e5, 57e5

CHAMBER = f"""
name: sensed_chamber
components:
  chamber: {{type: volume, ports: {{P: c}}, V: "1 L"}}
  c_sensor: {{type: pressure_sensor, ports: {{P: c}}, tau: {TAU}}}
  piston: {{type: mass, ports: {{m: rod}}, m: 10}}
  rod_sensor: {{type: motion_sensor, ports: {{a: rod}}, tau: {TAU}}}
outputs:
  P: {{expr: c_sensor.p, unit: bar}}
  x: {{expr: rod_sensor.x, unit: mm}}
  v: {{expr: rod_sensor.v, unit: mm/s}}
initial:
  c.p: "35 bar"
  rod.v: "20 mm/s"
"""


def _run(measured: dict, from_data: bool = True):
    model = build_model(load_netlist_text(CHAMBER, "sensed.yaml"))
    t = np.arange(0.0, 0.03, 1e-4)
    e = Experiment("e", "e.csv", InputTable(np.array([0.0]), np.zeros((1, 0))), t,
                   measured={k: np.full(t.size, v) for k, v in measured.items()}, initial_from_data=from_data)
    x0 = initial_state(model, e)
    tr = simulate(model, e.inputs, t, x0=x0, opts=SolverOptions(rtol=1e-9))
    return model, x0, t, {o: tr.Y[:, i] for i, o in enumerate(model.output_names)}


def test_a_sensed_chamber_starts_at_its_sensors_first_sample():
    model, x0, t, y = _run({"P": P_MEAS})
    assert x0[model.state_index("c.p")] == pytest.approx(P_MEAS)
    assert np.abs(y["P"] - P_MEAS).max() < 1e-6 * P_MEAS          # no lag transient


def test_a_sensor_without_a_sample_starts_on_its_node():
    model, x0, t, y = _run({"P": P_MEAS}, from_data=False)
    assert x0[model.state_index("c_sensor.y")] == pytest.approx(P_FILE)
    assert np.abs(y["P"] - P_FILE).max() < 1e-6 * P_FILE


def test_the_sensed_state_is_what_used_to_lag_behind_the_sample():
    """The closed form of the old behaviour, to show what the rule removes: a reading started
    at 57 bar on a chamber held at 35 bar decays with the sensor's time constant."""
    model = build_model(load_netlist_text(CHAMBER, "sensed.yaml"))
    t = np.arange(0.0, 0.03, 1e-4)
    e = Experiment("e", "e.csv", InputTable(np.array([0.0]), np.zeros((1, 0))), t, measured={})
    x0 = initial_state(model, e)
    x0[model.state_index("c_sensor.y")] = P_MEAS
    tr = simulate(model, e.inputs, t, x0=x0, opts=SolverOptions(rtol=1e-10))
    expected = P_FILE + (P_MEAS - P_FILE) * np.exp(-t / TAU)
    assert np.abs(tr.Y[:, model.output_names.index("P")] - expected).max() < 1e-5 * P_MEAS


def test_a_lagged_position_starts_the_rod_where_it_reads():
    x_meas, v0 = 0.125, 0.020
    model, x0, t, y = _run({"x": x_meas})
    assert x0[model.state_index("rod.x")] == pytest.approx(x_meas)
    # the rod coasts at v0 from x_meas; its reading lags: x_m = x_meas + v0·(t − τ(1 − e^(−t/τ)))
    expected = x_meas + v0 * (t - TAU * (1 - np.exp(-t / TAU)))
    assert np.abs(y["x"] - expected).max() < 1e-9
