"""An experiment: the inputs that drive a machine and the measurements to compare with.

``load_experiment(path, model)`` accepts an experiment YAML file (``file.yaml#name`` picks
one of several; format in experiment_file.py and docs/experiments.md) or a plain recording
(.csv/.h5/.mat whose columns are named like the machine's inputs and outputs).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DataError, Location, Problem
from ..model.model import Model
from ..solve.simulate import InputTable
from .recording import Recording, read_csv
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

    def x0(self, model: Model, p: np.ndarray | None = None) -> np.ndarray:
        """Initial state: the model's, then states measured directly (first sample), then
        the experiment's explicit values; with ``settle`` > 0 the machine then runs that long
        with the inputs frozen at their first value (parameters ``p``) and starts from there."""
        x0 = self._x0_given(model)
        if self.settle > 0:
            from ..solve.simulate import SolverOptions, simulate
            frozen = InputTable(np.array([0.0]), self.inputs.U[:1].copy())
            traj = simulate(model, frozen, np.array([0.0, self.settle]), p=p, x0=x0, opts=SolverOptions(rtol=1e-6))
            x0 = traj.X[-1].copy()
        return x0

    def _x0_given(self, model: Model) -> np.ndarray:
        x0 = model.x0.copy()
        if self.initial_from_data:
            for out, values in self.measured.items():
                e = model.equations.output_exprs.get(out)
                state = _direct_state(model, e)
                finite = values[np.isfinite(values)] if state is not None else values[:0]
                if finite.size:
                    x0[model.state_index(state)] = finite[0]
        for name, v in self.initial.items():
            x0[model.state_index(name)] = v
        return x0


def _direct_state(model: Model, e) -> str | None:
    """The state an output reads directly (through variable aliases), if any."""
    seen = 0
    while e is not None and e.op == "sym" and seen < 20:
        kind, name = e.args
        if kind == "state":
            return name
        if kind != "var":
            return None
        e = model.equations.variables.get(name)
        seen += 1
    return None


def load_experiment(path: str | Path, model: Model) -> Experiment:
    """One experiment; ``file.yaml#name`` picks one of several in an experiment file."""
    text = str(path)
    if "#" in text and text.split("#", 1)[0].lower().endswith((".yaml", ".yml")):
        from .experiment_file import load_experiment_file
        file, name = text.split("#", 1)
        return load_experiment_file(file, model, name=name)
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return experiment_from_recording(read_csv(path), model, name=path.stem)
    if suffix in (".yaml", ".yml"):
        from .experiment_file import load_experiment_file
        return load_experiment_file(path, model)
    if suffix in (".h5", ".hdf5", ".mat"):
        from .experiment_file import recording_from_file
        return experiment_from_recording(recording_from_file(path), model, name=path.stem)
    raise DataError(Problem(f"unknown experiment format '{suffix}' for {path}", Location(str(path)),
                            "give an experiment .yaml, or a recording .csv/.h5/.mat"))


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
