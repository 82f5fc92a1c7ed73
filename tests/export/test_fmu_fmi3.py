"""FMI 3.0 co-simulation FMU of the EHA: fmpy validates it, and with constant inputs (FMI 3.0
co-simulation has no input derivatives, so recorded inputs would be held between
communication points) it agrees with ``hydro simulate`` within 0.1 % of each output's range."""
from __future__ import annotations

from pathlib import Path

import pytest

from hydrocli.api import load_experiment, load_machine
from hydrocli.export import ExportOptions
from hydrocli.experiments.initial import initial_state

fmpy = pytest.importorskip("fmpy")

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "machines/eha_testbench.yaml"
CONSTANT = {"u": 0.05, "Ps": 100e5, "Fext": 200.0}


def test_fmi3_cosimulation_agrees_with_hydro_simulate(fmu_tools, tmp_path):
    from fmpy.validation import validate_fmu
    m = load_machine(MACHINE)
    fmu = m.export_fmu(tmp_path / "eha3.fmu", ExportOptions(fmi=3))
    assert validate_fmu(str(fmu)) == []
    exp_file = tmp_path / "constant.yaml"
    exp_file.write_text("name: constant\nduration: 1 s\nrate: 1 kHz\n"
                        "inputs: {u: '5 %', Ps: '100 bar', Fext: '200 N'}\n")
    ref = fmu_tools.hydro_simulate(MACHINE, str(exp_file), tmp_path / "ref.h5")
    exp = load_experiment(exp_file, m)
    starts = {s: float(v) for s, v in zip(m.model.state_names, initial_state(m.model, exp))} | CONSTANT
    res = fmpy.simulate_fmu(str(fmu), start_time=0.0, stop_time=1.0, output_interval=1e-3, start_values=starts,
                            output=m.model.output_names, relative_tolerance=fmu_tools.RTOL)
    err = fmu_tools.worst_error(res, ref, m.model.output_names)
    assert max(err.values()) < 1e-3, err
    assert ref.outputs["x"][-1] - ref.outputs["x"][0] > 5e-3      # the piston moved (> 5 mm)
