"""The identified Festo TP511 machine as an FMI 2.0 co-simulation FMU, driven by a real
recording's valve command: agrees with ``hydro simulate`` within 0.1 % of each output's range,
and its start values are the identified parameter values."""
from __future__ import annotations

from pathlib import Path

import pytest

from hydrocli.api import load_experiment, load_machine

fmpy = pytest.importorskip("fmpy")

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "reports/festo/festo_tp511_identified.yaml"
RECORDINGS = ROOT.parent / "shared/real/festo_tp511"
EXPERIMENT = str(ROOT / "experiments/festo/steps_pA.yaml") + "#festo_pA_3V"


@pytest.mark.slow
@pytest.mark.skipif(not RECORDINGS.is_dir(), reason="needs ../shared/real/festo_tp511 (real recordings)")
def test_festo_fmu_agrees_with_hydro_simulate(fmu_tools, tmp_path):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu
    m = load_machine(MACHINE)
    fmu = m.export_fmu(tmp_path / "festo.fmu")
    assert validate_fmu(str(fmu)) == []
    starts = {v.name: float(v.start) for v in read_model_description(str(fmu)).modelVariables
              if v.causality == "parameter"}
    assert starts == m.parameters                       # identified values are the start values, bit-exact
    ref = fmu_tools.hydro_simulate(MACHINE, EXPERIMENT, tmp_path / "ref.h5")
    res = fmu_tools.run_fmu(fmu, m.model, load_experiment(EXPERIMENT, m))
    err = fmu_tools.worst_error(res, ref, m.model.output_names)
    assert max(err.values()) < 1e-3, err
