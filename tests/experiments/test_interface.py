"""Experiments load against a machine's interface (names and units), not a built model:
the same Experiment either way, and from an interface written by hand."""
from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np

from hydrocli.experiments.experiment_file import load_all
from hydrocli.experiments.interface import MachineInterface, StateUnit

ROOT = Path(__file__).resolve().parents[2]


def _same(a, b):
    assert a.name == b.name and np.array_equal(a.t_out, b.t_out) and np.array_equal(a.inputs.U, b.inputs.U)
    assert a.measured.keys() == b.measured.keys()
    assert all(np.array_equal(a.measured[k], b.measured[k], equal_nan=True) for k in a.measured)
    assert a.initial == b.initial and a.settle == b.settle and a.fit_outputs == b.fit_outputs


def test_loading_through_the_interface_gives_the_same_experiments(eha):
    _, model = eha
    iface = MachineInterface.of(model)
    assert pickle.loads(pickle.dumps(iface)) == iface
    for path in ("eha/none_train.yaml", "eha/none_validate.yaml"):
        for a, b in zip(load_all(ROOT / "experiments" / path, model), load_all(ROOT / "experiments" / path, iface)):
            _same(a, b)


def test_a_hand_written_interface_loads_a_designed_experiment(tmp_path):
    iface = MachineInterface("bench", input_names=["u"], output_names=["x"], states=(StateUnit("load.x", "m"),),
                             input_units={"u": "%"}, output_si={"x": "m"})
    (tmp_path / "e.yaml").write_text("duration: 1 s\nrate: 100 Hz\ninputs: {u: {step: {at: 0.5 s, to: 20}}}\n"
                                     "initial: {load.x: 70 mm}\n")
    exp, = load_all(tmp_path / "e.yaml", iface)
    assert exp.t_out.size == 101 and exp.inputs.U[-1, 0] == 0.2          # 20 % in SI
    assert exp.initial == {"load.x": 0.07}
