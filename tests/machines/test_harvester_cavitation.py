"""Issue 13: with the cavitation floor (``fluid: {p_vap: 2 kPa}``) no chamber of the harvester
falls towards vacuum when a valve closes on a moving load: released gas fills the chamber
below p_vap (the floor's closed form is tested in tests/components/test_cavitation_floor.py)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrocli.experiments.experiment_file import load_experiment_file
from hydrocli.experiments.initial import initial_state
from hydrocli.runner import load_machine
from hydrocli.solve.simulate import simulate

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_harvester_chambers_stay_above_the_gas_release_pressure():
    net, model = load_machine(ROOT / "machines" / "harvester.yaml")
    assert net.fluid["p_vap"].value == pytest.approx(2e3)
    exp = load_experiment_file(ROOT / "experiments" / "harvester" / "swing_triangle.yaml", model)
    tr = simulate(model, exp.inputs, exp.t_out, x0=initial_state(model, exp))
    cols = [i for i, s in enumerate(model.states) if s.unit == "Pa"]
    assert cols
    p_min = float(np.min(tr.X[:, cols]))
    assert p_min > 0.25 * 2e3, f"a chamber fell to {p_min:.3g} Pa absolute"
