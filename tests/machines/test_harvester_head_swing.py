"""Seed 002 §4: the processing head swings freely on its Hooke joint once released off its
hanging pose (experiments/harvester/head_swing_offset.yaml, arm held by the closed valves).
Reference: the compound pendulum ω = sqrt(m g d / (I_G + m d²)) of the head (900 kg, COG 0.7 m
below the pivot, I_G = 250 kg·m², harvester_payload.yaml), with the 10° amplitude correction."""
from hydrocli.experiments.initial import initial_state
from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_experiment_file
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import SolverOptions, simulate
from simhelpers import oscillation_frequency

ROOT = Path(__file__).resolve().parents[2]


def test_released_head_swings_at_the_compound_pendulum_frequency():
    model = build_model(load_netlist(ROOT / "machines" / "harvester_payload.yaml"))
    exp = load_experiment_file(ROOT / "experiments" / "harvester" / "head_swing_offset.yaml", model)
    tr = simulate(model, exp.inputs, exp.t_out, x0=initial_state(model, exp), opts=SolverOptions(rtol=1e-7))
    m, d, g = 900.0, 0.7, 9.81
    amp = np.radians(10.0)
    for out, i_g, i_cross in (("q_head_roll", 250.0, 0.0), ("q_head_pitch", 250.0, 1.0)):
        y = tr.Y[:, model.output_names.index(out)]
        assert np.ptp(y) > np.radians(15)                       # it swings (±10° released)
        w0 = np.sqrt(m * g * d / (i_g + i_cross + m * d * d))
        w = w0 / (1 + amp ** 2 / 16)                            # finite-amplitude pendulum period
        assert oscillation_frequency(exp.t_out, y) == pytest.approx(w, rel=0.03), out
