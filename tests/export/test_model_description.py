"""modelDescription.xml of the EHA FMU: every parameter tunable with its unit, bounds and
value; units with SI base-unit exponents and display units; ModelStructure dependencies
that follow the equations; the export command's exit codes."""
from __future__ import annotations

from pathlib import Path

import zipfile

import pytest
from typer.testing import CliRunner

from hydrocli.api import load_machine
from hydrocli.cli.main import app
from hydrocli.export import ExportOptions

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "machines/eha_testbench.yaml"


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    m = load_machine(MACHINE)
    fmu = m.export_fmu(tmp_path_factory.mktemp("md") / "eha.fmu", ExportOptions(kind="both"))
    return m, fmu, read_model_description(str(fmu))


def test_every_parameter_is_tunable_with_unit_bounds_and_start(exported):
    m, _, md = exported
    params = {v.name: v for v in md.modelVariables if v.causality == "parameter"}
    assert set(params) == {p.name for p in m.model.params}
    for p in m.model.params:
        v = params[p.name]
        assert v.variability == "tunable" and v.initial == "exact"
        assert float(v.start) == p.value
        if p.bounds:
            assert float(v.min) <= p.bounds[0] and float(v.max) >= p.bounds[1]
    beta = params["cylinder.beta"]
    assert beta.unit == "Pa" and beta.displayUnit == "GPa"


def test_units_carry_si_base_exponents_and_display_conversions(exported):
    _, _, md = exported
    units = {u.name: u for u in md.unitDefinitions}
    pa = units["Pa"].baseUnit                          # Pa = kg·m⁻¹·s⁻²
    assert (pa.kg, pa.m, pa.s) == (1, -1, -2)
    bar = {d.name: d for d in units["Pa"].displayUnits}["bar"]
    assert bar.factor == pytest.approx(1e-5)           # 1 Pa = 1e-5 bar
    mm = {d.name: d for d in units["m"].displayUnits}["mm"]
    assert mm.factor == pytest.approx(1e3)
    flow = units["m^3/s/Pa"].baseUnit                  # leakage coefficient: m⁴·s·kg⁻¹
    assert (flow.m, flow.s, flow.kg) == (4, 1, -1)
    inputs = {v.name: v for v in md.modelVariables if v.causality == "input"}
    assert inputs["u"].displayUnit == "%" and inputs["Ps"].unit == "Pa"


def test_model_structure_follows_the_equations(exported):
    m, _, md = exported
    deps = {u.variable.name: {d.name for d in u.dependencies} for u in md.outputs}
    assert deps["P1"] == {"chamber_1.p"}                # P1 is chamber 1's pressure
    assert deps["dp"] == {"chamber_1.p", "chamber_2.p"}
    der = {u.variable.name: {d.name for d in u.dependencies} for u in md.derivatives}
    assert der["der(piston.x)"] == {"piston.v"}         # dx/dt = v
    assert "Fext" in der["der(piston.v)"] and "u" not in der["der(piston.v)"]
    assert {"u"} <= der["der(valve.xr)"]                # the command drives the spool reference
    assert md.modelExchange.providesDirectionalDerivative and md.coSimulation.canInterpolateInputs


def test_fmu_holds_sources_and_a_linux_binary(exported):
    from fmpy.validation import validate_fmu
    _, fmu, md = exported
    assert validate_fmu(str(fmu)) == []                 # model exchange and co-simulation in one FMU
    names = set(zipfile.ZipFile(fmu).namelist())
    ident = md.coSimulation.modelIdentifier
    assert f"binaries/linux64/{ident}.so" in names
    assert {"sources/model.c", "sources/hy_integrator.c", "sources/hydro_fmi2.c", "sources/fmi2Functions.h",
            "sources/FMI_HEADERS_LICENSE.txt"} <= names


def test_export_command_writes_an_fmu_and_rejects_bad_options(tmp_path):
    out = tmp_path / "eha_me.fmu"
    res = CliRunner().invoke(app, ["export", str(MACHINE), "--fmu", str(out), "--kind", "me",
                                   "--set", "load.m=90 kg"])
    assert res.exit_code == 0, res.output
    md = read_model_description(str(out))
    assert md.modelExchange is not None and md.coSimulation is None
    assert {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter"}["load.m"] == 90.0
    bad = CliRunner().invoke(app, ["export", str(MACHINE), "--fmu", str(tmp_path / "x.fmu"), "--kind", "xx"])
    assert bad.exit_code == 2 and "--kind xx" in bad.output
    same = CliRunner().invoke(app, ["export", str(MACHINE), "--fmu", str(MACHINE)])
    assert same.exit_code == 2


@pytest.mark.parametrize("fmi", [2, 3])
def test_sources_in_the_fmu_build_a_library_with_every_fmi_function(tmp_path, fmi):
    """The FMU's sources/ alone compile (one file includes the rest) into a library that
    exports every function the FMI header declares."""
    import ctypes
    import re
    import shutil
    import subprocess
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    m = load_machine(MACHINE)
    fmu = m.export_fmu(tmp_path / f"eha{fmi}.fmu", ExportOptions(fmi=fmi))
    zipfile.ZipFile(fmu).extractall(tmp_path / "x")
    src = tmp_path / "x" / "sources"
    so = tmp_path / "rebuilt.so"
    subprocess.run(["cc", "-O1", "-fPIC", "-shared", f"-I{src}", "-o", str(so), str(src / f"hydro_fmi{fmi}.c"), "-lm"],
                   check=True, capture_output=True)
    header = (src / f"fmi{fmi}Functions.h").read_text()
    names = re.findall(rf"FMI{fmi}_Export\s+fmi{fmi}\w+TYPE\s+(fmi{fmi}\w+);", header)
    assert len(names) > 40
    lib = ctypes.CDLL(str(so))
    assert [n for n in names if not hasattr(lib, n)] == []
