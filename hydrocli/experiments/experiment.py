"""An experiment: the inputs that drive a machine and the measurements to compare with —
plain data: nothing here simulates, and no caller mutates it (derive a changed copy with
``dataclasses.replace``). Its start state is ``experiments.initial.initial_state``.

Loading (an experiment YAML file, ``file.yaml#name``, or a plain recording) is
``experiments.experiment_file.load_experiment`` / ``load_all``; this module holds the data
and :func:`experiment_from_recording` (columns named like the machine's inputs/outputs).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError, Location, Problem
from ..model.model import Model
from ..solve.simulate import InputTable
from .recording import Recording
from .unit_check import check_recording_columns


@dataclass
class Experiment:
    name: str
    file: str
    inputs: InputTable                              # SI, model input order
    t_out: np.ndarray                               # where outputs are compared / written
    measured: dict[str, np.ndarray] = field(default_factory=dict)   # output → SI values on t_out
    mask: dict[str, np.ndarray] = field(default_factory=dict)       # output → bool (True = use)
    initial: dict[str, float] = field(default_factory=dict)         # state → SI value
    initial_from_data: bool = True
    thresholds: dict[str, float] = field(default_factory=dict)      # output → max ESR %
    description: str = ""
    fit_outputs: list[str] = field(default_factory=list)            # outputs to fit ([] = all measured)
    weights: dict[str, float] = field(default_factory=dict)         # output → weight (cost 'wls')
    settle: float = 0.0          # > 0: pre-roll [s] with inputs frozen at their first value (initial: steady)
    # the start state is computed by experiments.initial.initial_state(model, exp, p)


def experiment_from_recording(rec: Recording, model: Model, name: str) -> Experiment:
    """Map columns named like machine inputs/outputs automatically (units already SI)."""
    missing = [n for n in model.input_names if n not in rec.columns]
    if missing:
        raise DataError(Problem(
            f"recording has no column for machine input(s) {', '.join(missing)} "
            f"(columns: {', '.join(rec.columns)})", Location(rec.file, 1, 1),
            "name the CSV columns like the machine's inputs, or write an experiment file that maps them"))
    check_recording_columns(rec, model)
    U = np.column_stack([rec.columns[n] for n in model.input_names]) if model.input_names else np.zeros((rec.t.size, 0))
    measured = {o: rec.columns[o] for o in model.output_names if o in rec.columns}
    return Experiment(name=name, file=rec.file, inputs=InputTable(rec.t, U), t_out=rec.t.copy(), measured=measured)
