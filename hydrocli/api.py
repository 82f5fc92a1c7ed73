"""The Python API: the same operations as the ``hydro`` commands, for notebooks and scripts.

>>> import hydrocli as hy
>>> m = hy.load_machine("machines/eha_testbench.yaml", set={"load.m": "80 kg"})
>>> r = m.simulate("experiments/quickstart/validate.yaml")
>>> r.to_pandas("outputs").head(); r.plot()
>>> fit = m.identify(["experiments/quickstart/train.yaml"], free=["valve.Kv"])
>>> fit.parameters, fit.machine.simulate("experiments/quickstart/validate.yaml")
>>> d = hy.diagnose(m, train=[...], validate=[...]); d.data["verdict"]
>>> m.export_fmu("eha.fmu")

Thin typed wrappers over the library (netlist loader, builder, experiments, solver,
identification, diagnosis, FMU export); ``hydro simulate`` and ``hydro export`` call them,
so the CLI and the API are one path. Values are SI floats; parameter overrides may be
numbers (SI) or strings with units ("80 kg", "1.6 GPa").
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .experiments.experiment import Experiment
from .experiments.experiment_file import load_experiment as _load_experiment
from .model.model import Model
from .netlist.model import Netlist
from .results import RunResult
from .runfiles import write_run

__all__ = ["Machine", "SimulationResult", "Fit", "load_machine", "load_experiment", "diagnose"]

Overrides = Mapping[str, float | str] | Sequence[str] | None


def _override_items(set: Overrides) -> list[str]:
    if not set:
        return []
    if isinstance(set, Mapping):
        return [f"{k}={v}" for k, v in set.items()]
    return [str(s) for s in set]


def load_machine(path: str | Path, set: Overrides = None) -> "Machine":
    """Load and build a machine YAML file; ``set`` overrides parameters, as ``--set`` does:
    ``{"load.m": "80 kg"}`` or ``["load.m=80 kg"]``."""
    from .runner import load_machine as _load
    items = _override_items(set)
    net, model = _load(path, items)
    return Machine(Path(path), net, model, tuple(items))


def load_experiment(path: str | Path, machine: "Machine") -> Experiment:
    """An experiment YAML (``file.yaml#name`` picks one of several) or a recording file."""
    return _load_experiment(path, machine.model)


@dataclass
class SimulationResult:
    """One simulated experiment: time, inputs, outputs, states (and measurements), SI."""

    run: RunResult

    @property
    def t(self) -> np.ndarray:
        return self.run.t

    @property
    def outputs(self) -> dict[str, np.ndarray]:
        return self.run.outputs

    @property
    def inputs(self) -> dict[str, np.ndarray]:
        return self.run.inputs

    @property
    def states(self) -> dict[str, np.ndarray]:
        return self.run.states

    @property
    def measured(self) -> dict[str, np.ndarray]:
        return self.run.measured

    def to_pandas(self, group: str | None = None):
        """A DataFrame indexed by time [s]. ``group`` = "outputs" | "inputs" | "states" |
        "measured" gives that group's signals by name; None gives all, as "outputs/P1", …
        (the HDF5 layout). Values are SI (units in ``self.run.units``)."""
        try:
            import pandas as pd
        except ImportError:  # pandas is optional
            raise ImportError("SimulationResult.to_pandas needs pandas: pip install pandas") from None
        groups = ("outputs", "inputs", "states", "measured")
        if group is not None and group not in groups:
            raise ValueError(f"group must be one of {', '.join(groups)} or None, not {group!r}")
        cols: dict[str, np.ndarray] = {}
        for g in ([group] if group else groups):
            for name, v in getattr(self.run, g).items():
                cols[name if group else f"{g}/{name}"] = v
        return pd.DataFrame(cols, index=pd.Index(self.t, name="time"))

    def plot(self, outputs: Sequence[str] | None = None):
        """One panel per output in its display unit, measurement dashed; returns the Figure."""
        import matplotlib.pyplot as plt
        from .units import from_si
        names = list(outputs or self.outputs)
        fig, axes = plt.subplots(len(names), 1, sharex=True, squeeze=False, figsize=(8, 2.2 * len(names) + 0.6))
        for ax, name in zip(axes[:, 0], names):
            disp = self.run.display_units.get(f"outputs/{name}")
            conv = (lambda v: from_si(v, disp)) if disp else (lambda v: v)
            ax.plot(self.t, conv(self.outputs[name]), label="model")
            if name in self.measured:
                ax.plot(self.t, conv(self.measured[name]), "--", label="measured")
                ax.legend(loc="best", fontsize="small")
            ax.set_ylabel(f"{name} [{disp or self.run.units.get(f'outputs/{name}', '')}]")
            ax.grid(True, alpha=0.3)
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(f"{self.run.machine} · {self.run.experiment}")
        fig.tight_layout()
        return fig

    def save(self, path: str | Path) -> Path:
        """Write the run (HDF5 in the DESIGN.md layout, or CSV by suffix), atomically."""
        write_run(path, self.run)
        return Path(path)


@dataclass
class Fit:
    """An identification: estimates with standard errors, and the machine with them (its
    model carries the exact estimates; its netlist text 6 digits, like ``hydro identify --out``)."""

    result: object                  # identify.fit.FitResult
    machine: "Machine"

    @property
    def parameters(self) -> dict[str, float]:
        return dict(zip(self.result.names, map(float, self.result.estimates)))

    @property
    def stderr(self) -> dict[str, float]:
        return dict(zip(self.result.names, map(float, self.result.stderr)))


@dataclass
class Machine:
    """A loaded and built machine: the netlist, the compiled-on-demand model, overrides."""

    path: Path
    netlist: Netlist
    model: Model
    overrides: tuple[str, ...] = field(default_factory=tuple)

    @property
    def name(self) -> str:
        return self.model.name

    @property
    def parameters(self) -> dict[str, float]:
        """Current parameter values (SI) by dotted name."""
        return {p.name: p.value for p in self.model.params}

    def simulate(self, experiment: str | Path | Experiment, *, set: Mapping[str, float] | None = None,
                 rtol: float | None = None, backend: str = "auto", command: str = "",
                 error_control: str = "scaled") -> SimulationResult:
        """Simulate against an experiment (path or loaded). ``set`` changes SI parameter values
        for this run only (no rebuild). The default tolerance means an accuracy:
        ``error_control="scaled"`` at rtol 1.5e-5 (``solve.simulate.simulate_options``); pass
        ``error_control="nominal"`` (and e.g. rtol 1e-6) for the fitting commands' control.
        Raises SolverError on divergence."""
        from .runner import simulate_experiment
        from .solve.simulate import simulate_options
        exp = experiment if isinstance(experiment, Experiment) else _load_experiment(experiment, self.model)
        p = self.model.param_vector(dict(set or {}))
        opts = simulate_options(rtol, backend=backend, error_control=error_control)
        run = simulate_experiment(self.model, exp, p=p, opts=opts, command=command)
        return SimulationResult(run)

    def identify(self, experiments: Sequence[str | Path | Experiment], free: Sequence[str] | None = None, *,
                 method: str = "least-squares", cost: str = "esr", outputs: Sequence[str] | None = None,
                 max_evals: int = 400, rtol: float = 1e-6, workers: int = 1) -> Fit:
        """Fit the free parameters (default: those marked free in the machine) to the
        experiments, as ``hydro identify``; ``Fit.machine`` carries the estimates."""
        from .experiments.experiment_file import load_all
        from .identify.fit import fit
        from .solve.simulate import SolverOptions
        exps = [e for x in experiments for e in ([x] if isinstance(x, Experiment) else load_all(x, self.model))]
        res = fit(self.model, exps, list(free) if free else None, method=method, cost=cost,
                  outputs=list(outputs) if outputs else None, max_evals=max_evals,
                  opts=SolverOptions(rtol=rtol), workers=workers)
        return Fit(res, self._with_values(res.p, res.names))

    def _with_values(self, p: np.ndarray, changed: Sequence[str]) -> "Machine":
        """This machine with parameter vector ``p``: the netlist text gets the changed and the
        overridden parameters (6 digits, as ``hydro identify --out`` writes), the model the
        exact values."""
        from .model.builder import build_model
        from .netlist.loader import load_netlist_text
        from .netlist.overrides import parse_assignment
        from .netlist.writer import set_parameters
        overridden = (parse_assignment(i)[0] for i in self.overrides)
        names = [n for n in dict.fromkeys([*changed, *overridden]) if n in self.model.param_names]
        values = {n: float(p[self.model.param_index(n)]) for n in names}
        net = load_netlist_text(set_parameters(self.netlist, values), file=str(self.path))
        model = build_model(net)
        for info, v in zip(model.params, p):
            info.value = float(v)
        return Machine(self.path, net, model)

    def export_fmu(self, path: str | Path, opts=None, *, x0: np.ndarray | None = None) -> Path:
        """Write an FMU (default FMI 2.0 co-simulation; ``opts`` an export.ExportOptions)."""
        from .export import export_fmu
        return export_fmu(self.model, path, opts, x0=x0)


def diagnose(machine: Machine | str | Path, train: Sequence[str | Path], validate: Sequence[str | Path],
             settings=None, progress=None):
    """Look for missing physics, as ``hydro diagnose``; returns diagnose.engine.Diagnosis
    (``.data`` is the JSON summary with ``verdict``)."""
    from .diagnose import Settings, diagnose as _diagnose
    from .errors import NetlistError, Problem
    if isinstance(machine, Machine):
        if machine.overrides:
            raise NetlistError(Problem("diagnose works on the machine file as written, but this machine was "
                                       f"loaded with overrides ({', '.join(machine.overrides)})",
                                       hint="write the values into the machine file, or load it without set="))
        machine = machine.path
    return _diagnose(machine, [str(p) for p in train], [str(p) for p in validate], settings or Settings(),
                     progress=progress)
