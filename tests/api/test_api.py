"""The Python API: load with overrides, simulate, results as DataFrame and figure, identify
(recovering a known parameter from data the model itself generated), diagnose's wrapper,
and the CLI going through the same path."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import hydrocli as hy
from hydrocli.cli.main import app
from hydrocli.errors import NetlistError

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "machines/eha_testbench.yaml"


def _window(tmp_path: Path, t_end: str) -> Path:
    src = ROOT / "experiments/quickstart/validate.yaml"
    text = src.read_text().replace("data: validate.csv", f"data: {src.parent / 'validate.csv'}")
    out = tmp_path / "validate_window.yaml"
    out.write_text(text + f"\nwindow: [0 s, {t_end}]\n")
    return out


def test_top_level_names_and_overrides_with_units():
    assert {"load_machine", "diagnose", "load_experiment", "__version__"} <= set(dir(hy))
    m = hy.load_machine(MACHINE, set={"load.m": "80 kg", "cylinder.beta": "1.2 GPa"})
    assert m.parameters["load.m"] == 80.0 and m.parameters["cylinder.beta"] == pytest.approx(1.2e9)
    assert hy.load_machine(MACHINE, set=["load.m=0.1 t"]).parameters["load.m"] == pytest.approx(100.0)


def test_simulate_result_as_dataframe_and_figure(tmp_path):
    pd = pytest.importorskip("pandas")
    m = hy.load_machine(MACHINE)
    r = m.simulate(_window(tmp_path, "1 s"))
    df = r.to_pandas("outputs")
    assert list(df.columns) == m.model.output_names and df.index.name == "time"
    assert np.array_equal(df["P1"].to_numpy(), r.outputs["P1"])
    every = r.to_pandas()
    assert {"outputs/P1", "inputs/u", "states/piston.x", "measured/P1"} <= set(every.columns)
    assert isinstance(df, pd.DataFrame)
    import matplotlib
    matplotlib.use("Agg")
    fig = r.plot(["P1", "x"])
    assert len(fig.axes) == 2 and fig.axes[0].get_ylabel() == "P1 [bar]"


def test_to_pandas_says_how_to_get_pandas(monkeypatch, tmp_path):
    r = hy.load_machine(MACHINE).simulate(_window(tmp_path, "0.2 s"))
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        r.to_pandas()


def test_simulate_set_changes_a_parameter_for_one_run(tmp_path):
    m = hy.load_machine(MACHINE)
    exp = hy.load_experiment(_window(tmp_path, "1 s"), m)
    heavy = m.simulate(exp, set={"load.m": 150.0})
    rebuilt = hy.load_machine(MACHINE, set={"load.m": "150 kg"}).simulate(exp)
    np.testing.assert_allclose(heavy.outputs["x"], rebuilt.outputs["x"], rtol=0, atol=1e-12)
    assert m.parameters["load.m"] == pytest.approx(74.11)


@pytest.mark.slow
def test_identify_recovers_a_valve_gain_from_data_the_model_generated(tmp_path):
    truth = hy.load_machine(MACHINE)
    exp = hy.load_experiment(_window(tmp_path, "1 s"), truth)
    r = truth.simulate(exp, rtol=1e-9)
    cols = {"t": r.t, **r.inputs, **r.outputs}
    csv = tmp_path / "synthetic.csv"
    np.savetxt(csv, np.column_stack(list(cols.values())), delimiter=",", header=",".join(cols), comments="")
    (tmp_path / "synthetic.yaml").write_text(
        "name: synthetic\ndata: synthetic.csv\ninputs: {u: u, Ps: Ps, Fext: Fext}\n"
        "outputs: {P1: P1, P2: P2, x: x, v: v}\n")
    start = hy.load_machine(MACHINE, set={"valve.Kv": 6e-7})
    fit = start.identify([tmp_path / "synthetic.yaml"], free=["valve.Kv"], max_evals=40, rtol=1e-9)
    assert fit.parameters["valve.Kv"] == pytest.approx(4.68e-7, rel=1e-4)
    assert fit.machine.parameters["valve.Kv"] == fit.parameters["valve.Kv"]      # exact, not the 6-digit text
    assert "4.68" in fit.machine.netlist.text


def test_diagnose_wrapper_passes_the_machine_file_and_refuses_unsaved_overrides(monkeypatch):
    import hydrocli.diagnose as diag
    seen = {}
    monkeypatch.setattr(diag, "diagnose", lambda machine, train, validate, settings, progress=None:
                        seen.update(machine=machine, train=train, validate=validate) or "diagnosis")
    m = hy.load_machine(MACHINE)
    assert hy.diagnose(m, train=["a.yaml"], validate=[Path("b.yaml")]) == "diagnosis"
    assert seen == {"machine": MACHINE, "train": ["a.yaml"], "validate": ["b.yaml"]}
    with pytest.raises(NetlistError, match="overrides"):
        hy.diagnose(hy.load_machine(MACHINE, set={"load.m": 80.0}), train=[], validate=[])


def test_cli_simulate_goes_through_the_api(monkeypatch, tmp_path):
    import hydrocli.api as api
    calls = []
    orig = api.Machine.simulate
    monkeypatch.setattr(api.Machine, "simulate", lambda self, *a, **k: calls.append(a) or orig(self, *a, **k))
    out = tmp_path / "r.h5"
    res = CliRunner().invoke(app, ["simulate", str(MACHINE), "-e", str(_window(tmp_path, "0.5 s")), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert len(calls) == 1 and out.exists()
