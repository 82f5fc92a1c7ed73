"""FMU test support: export once per module, drive FMUs with fmpy.simulate_fmu, and compare
with ``hydro simulate`` run through the CLI.

Two fmpy (0.3.32) limitations are patched for the tests, both about *how the master feeds
recorded inputs*, not about the FMU:
- ``Input`` allocates exactly 9 input-derivative slots, so ``set_input_derivatives=True``
  fails for any other number of inputs; the patch sizes them to the inputs;
- the CVode right-hand side used for model exchange does not apply the inputs at the solver's
  time (only at communication points: a zero-order hold), while ``hydro simulate`` interpolates
  recorded inputs linearly; the patch applies them at every right-hand-side call.
Without them the FMU sees zero-order-held inputs and differs from ``hydro simulate`` by the
hold, not by the model (about 12 % of the EHA pressure range at a 1 ms recording).
"""
from __future__ import annotations

from ctypes import c_double
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from hydrocli.experiments.initial import initial_state

try:
    import fmpy
except ImportError:  # the test modules skip themselves
    fmpy = None

ROOT = Path(__file__).resolve().parents[2]
RTOL = 1e-8   # both sides: at 1e-6 hydro simulate itself is 1.6 % of P1's range off its converged solution


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than ~10 s")


@pytest.fixture
def fmpy_inputs(monkeypatch):
    import fmpy.simulation as sim
    import fmpy.sundials as sundials

    orig_init = sim.Input.__init__

    def init(self, *a, **k):
        orig_init(self, *a, **k)
        self.continuous = [c._replace(derivatives=(c_double * len(c.vrs))()) for c in getattr(self, "continuous", [])]

    orig_f = sundials.CVodeSolver.f

    def f(self, t, y, ydot, user_data):
        self.input.apply(t, discrete=False)
        return orig_f(self, t, y, ydot, user_data)

    monkeypatch.setattr(sim.Input, "__init__", init)
    monkeypatch.setattr(sundials.CVodeSolver, "f", f)


def hydro_simulate(machine: Path, experiment: str, out: Path, sets=()):
    """Run the ``hydro simulate`` command and read its HDF5 result."""
    from hydrocli.cli.main import app
    from hydrocli.results import read_result
    args = ["simulate", str(machine), "-e", experiment, "-o", str(out), "--rtol", str(RTOL)]
    for s in sets:
        args += ["--set", s]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    return read_result(out)


def run_fmu(fmu: Path, model, exp, start_values=None, kind="cs"):
    """fmpy.simulate_fmu over the experiment's (preprocessed) input table, states starting
    where the experiment starts them, communication grid = the input samples."""
    t_in, U = exp.inputs.t, exp.inputs.U
    sig = np.zeros(len(t_in), dtype=[("time", float)] + [(n, float) for n in model.input_names])
    sig["time"] = t_in
    for j, n in enumerate(model.input_names):
        sig[n] = U[:, j]
    starts = {s: float(v) for s, v in zip(model.state_names, initial_state(model, exp))}
    starts.update(start_values or {})
    kw = dict(set_input_derivatives=True) if kind == "cs" else dict(solver="CVode")
    return fmpy.simulate_fmu(str(fmu), start_time=float(exp.t_out[0]), stop_time=float(exp.t_out[-1]),
                             input=sig if model.input_names else None, output_interval=float(np.median(np.diff(t_in))),
                             output=model.output_names, start_values=starts, relative_tolerance=RTOL, **kw)


def worst_error(fmu_res, ref, names) -> dict[str, float]:
    """Largest |FMU − hydro simulate| per output, as a fraction of the output's range."""
    out = {}
    for n in names:
        y_ref = ref.outputs[n]
        y = np.interp(ref.t, fmu_res["time"], fmu_res[n])
        out[n] = float(np.max(np.abs(y - y_ref)) / np.ptp(y_ref))
    return out


@pytest.fixture
def fmu_tools(fmpy_inputs):
    """The helpers above, with fmpy patched for recorded inputs."""
    from types import SimpleNamespace
    return SimpleNamespace(hydro_simulate=hydro_simulate, run_fmu=run_fmu, worst_error=worst_error,
                           windowed_experiment=windowed_experiment, ROOT=ROOT, RTOL=RTOL)


def windowed_experiment(tmp_path: Path, src: Path, t_end: str) -> Path:
    """A copy of an experiment file that reads the same data, cut to [0, t_end]."""
    text = src.read_text()
    lines = []
    for line in text.splitlines():
        if line.startswith("data:"):
            line = f"data: {(src.parent / line.split(':', 1)[1].strip()).resolve()}"
        lines.append(line)
    lines.append(f"window: [0 s, {t_end}]")
    out = tmp_path / src.name
    out.write_text("\n".join(lines) + "\n")
    return out
