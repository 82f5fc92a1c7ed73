"""FMI 2.0 FMUs of the EHA test bench: fmpy validates them, and they simulate the recorded
validation inputs like ``hydro simulate`` (within 0.1 % of each output's range), in
co-simulation (the FMU's own Rosenbrock integrator) and in model exchange (fmpy's CVode,
an independent integrator, on the FMU's derivatives)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from hydrocli.api import load_experiment, load_machine
from hydrocli.export import ExportOptions

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "machines/eha_testbench.yaml"


@pytest.fixture(scope="module")
def eha(tmp_path_factory):
    d = tmp_path_factory.mktemp("eha_fmu")
    m = load_machine(MACHINE)
    return m, {k: m.export_fmu(d / f"eha_{k}.fmu", ExportOptions(kind=k)) for k in ("cs", "me")}


@pytest.mark.parametrize("kind", ["cs", "me"])
def test_fmpy_validation_finds_no_problem(eha, kind):
    assert validate_fmu(str(eha[1][kind])) == []


@pytest.mark.parametrize("kind", ["cs", "me"])
def test_fmu_agrees_with_hydro_simulate(eha, kind, fmu_tools, tmp_path):
    m, fmus = eha
    exp_file = fmu_tools.windowed_experiment(tmp_path, ROOT / "experiments/quickstart/validate.yaml", "3 s")
    ref = fmu_tools.hydro_simulate(MACHINE, str(exp_file), tmp_path / "ref.h5")
    res = fmu_tools.run_fmu(fmus[kind], m.model, load_experiment(exp_file, m), kind=kind)
    err = fmu_tools.worst_error(res, ref, m.model.output_names)
    assert max(err.values()) < 1e-3, err
    assert np.ptp(ref.outputs["P1"]) > 5e5                   # a real transient was compared (> 5 bar)


def test_parameter_changed_through_the_fmu_takes_effect(eha, fmu_tools, tmp_path):
    m, fmus = eha
    exp_file = fmu_tools.windowed_experiment(tmp_path, ROOT / "experiments/quickstart/validate.yaml", "1.5 s")
    exp = load_experiment(exp_file, m)
    new = {"load.m": 150.0, "cylinder.beta": 0.9e9}
    ref = fmu_tools.hydro_simulate(MACHINE, str(exp_file), tmp_path / "ref.h5",
                                   sets=["load.m=150 kg", "cylinder.beta=0.9 GPa"])
    changed = fmu_tools.run_fmu(fmus["cs"], m.model, exp, start_values=new)
    base = fmu_tools.run_fmu(fmus["cs"], m.model, exp)
    names = m.model.output_names
    assert max(fmu_tools.worst_error(changed, ref, names).values()) < 1e-3
    assert fmu_tools.worst_error(base, ref, ["P1"])["P1"] > 1e-2   # the change matters: > 1 % of P1's range


@pytest.mark.parametrize("analytic_jacobian", [True, False])
def test_directional_derivatives_match_difference_quotients(eha, tmp_path, analytic_jacobian):
    """∂(der)/∂(states, inputs) and ∂(outputs)/∂(states, inputs) from
    fmi2GetDirectionalDerivative against central differences of fmi2GetDerivatives/GetReal,
    with the analytic Jacobian and without it (large models: hy_jac is not generated)."""
    if analytic_jacobian:
        m, fmu_path = eha[0], eha[1]["me"]
    else:
        from hydrocli.model.codegen import generate_c
        m = load_machine(MACHINE)
        m.model._c_source = generate_c(m.model.equations, m.model.name, analytic_jacobian=False)
        fmu_path = m.export_fmu(tmp_path / "nojac.fmu", ExportOptions(kind="me"))
    assert ("#define HY_HAS_JAC" in m.model.c_source) == analytic_jacobian
    _check_directional(m, fmu_path, tmp_path)


def _check_directional(m, fmu_path, tmp_path):
    from ctypes import c_double

    from fmpy import extract, read_model_description

    from fmpy.fmi2 import FMU2Model
    md = read_model_description(str(fmu_path))
    unzipped = extract(str(fmu_path), unzipdir=str(tmp_path / "me"))
    fmu = FMU2Model(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.modelExchange.modelIdentifier,
                    instanceName="jac")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    by_name = {v.name: v.valueReference for v in md.modelVariables}
    x = {"valve.xr": 0.3, "valve.xv": 0.25, "valve.xv_dot": 2.0, "chamber_1.p": 80e5, "chamber_2.p": 40e5,
         "piston.v": 0.02, "piston.x": 0.05}
    u = {"u": 0.3, "Ps": 150e5, "Fext": 500.0}
    fmu.enterInitializationMode()
    fmu.setReal([by_name[k] for k in x], list(x.values()))
    fmu.setReal([by_name[k] for k in u], list(u.values()))
    fmu.exitInitializationMode()
    fmu.enterContinuousTimeMode()
    knowns = list(x) + list(u)
    unknowns = [f"der({s})" for s in m.model.state_names] + m.model.output_names
    vr_unk = [by_name[n] for n in unknowns]
    nominal = {**{s.name: s.nominal for s in m.model.states}, "u": 0.01, "Ps": 1e5, "Fext": 10.0}
    base = {**x, **u}

    def evaluate(point):
        fmu.setReal([by_name[k] for k in u], [point[k] for k in u])
        fmu.setContinuousStates((c_double * len(x))(*[point[s] for s in m.model.state_names]), len(x))
        return np.array(fmu.getReal(vr_unk))

    for k in knowns:
        evaluate(base)
        dd = np.array(fmu.getDirectionalDerivative(vr_unk, [by_name[k]], [1.0]))
        h = 1e-6 * max(abs(base[k]), nominal[k])
        fd = (evaluate({**base, k: base[k] + h}) - evaluate({**base, k: base[k] - h})) / (2 * h)
        tol = 1e-4 * np.abs(fd) + 1e-7 * np.max(np.abs(fd))
        assert np.all(np.abs(dd - fd) <= tol), (k, dd, fd)
    fmu.terminate()
    fmu.freeInstance()


def test_model_guard_stops_the_fmu_with_the_machines_message(tmp_path, capsys):
    """A stroke overrun (full retract command, small chamber A) is the same located error
    in the FMU as in hydro simulate: fmi2DoStep fails and logs the guard's message."""
    m = load_machine(MACHINE, set={"cylinder.V_A0": 6e-5})
    fmu = m.export_fmu(tmp_path / "overrun.fmu")
    with pytest.raises(Exception, match="fmi2DoStep"):
        fmpy.simulate_fmu(str(fmu), stop_time=3.0, output_interval=1e-3,
                          start_values={"u": -1.0, "Ps": 200e5, "Fext": 0.0})
    assert "chamber A collapsed" in capsys.readouterr().out


def test_fmu_state_restores_and_serialises(eha, tmp_path):
    """canGetAndSetFMUstate: stepping on from a saved (or serialised and restored) state
    repeats the same trajectory bit for bit."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    md = read_model_description(str(eha[1]["cs"]))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(eha[1]["cs"]), unzipdir=str(tmp_path / "cs")),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="state")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["u"], vr["Ps"], vr["Fext"]], [0.2, 100e5, 0.0])
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.05)
    at_save = fmu.getReal([vr["P1"], vr["x"]])
    saved = fmu.getFMUstate()
    blob = fmu.serializeFMUstate(saved)

    def run_on():
        for k in range(5):
            fmu.doStep(0.05 + 0.01 * k, 0.01)
        return fmu.getReal([vr["P1"], vr["x"]])

    first = run_on()
    fmu.setFMUstate(saved)
    again = run_on()
    fmu.setFMUstate(fmu.deSerializeFMUstate(blob))
    third = run_on()
    assert first == again == third and first != at_save       # the machine moved after the save
    fmu.freeFMUstate(saved)
    fmu.terminate()
    fmu.freeInstance()
