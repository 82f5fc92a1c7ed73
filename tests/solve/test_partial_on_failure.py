"""A model that leaves its valid range stops the solver; the error carries the trajectory up
to that point, and diagnose scores the model on it (outputs held after the stop) instead
of treating the experiment as missing (which had made a failed validation count as 0 %)."""
import numpy as np
import pytest

from hydrocli.diagnose.residuals import held_after_failure
from hydrocli.errors import SolverError
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, simulate

# 50 bar on chamber A, B open to tank through an orifice, no end stops: the piston runs out
# and chamber B (V_B0 = 10 cm³, A_B = 5 cm²) empties at x → 20 mm.
MACHINE = """
name: runaway
components:
  supply: {type: pressure_source, ports: {P: pa}, p: "50 bar"}
  tank: {type: tank, ports: {T: t}, p: "1 bar"}
  outlet: {type: orifice, ports: {A: pb, B: t}, Kv: 1.0e-7}
  cylinder:
    type: cylinder
    ports: {A: pa, B: pb, rod: rod, body: ground}
    A_A: "10 cm^2"
    A_B: "5 cm^2"
    V_A0: "10 cm^3"
    V_B0: "10 cm^3"
  load: {type: mass, ports: {m: rod}, m: "5 kg"}
outputs:
  x: {expr: rod.x, unit: mm}
"""


def test_solver_failure_carries_the_trajectory_up_to_the_stop(tmp_path, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "cache"))
    model = build_model(load_netlist_text(MACHINE))
    t = np.linspace(0.0, 5.0, 501)
    with pytest.raises(SolverError) as info:
        simulate(model, InputTable.constant(model), t)
    assert "chamber B collapsed" in str(info.value)
    part = info.value.partial
    assert part is not None and 1 < part.t.size < t.size
    x = part.Y[:, model.output_names.index("x")]
    # the piston ran out monotonically and stopped where chamber B is 99 % empty (19.8 mm)
    assert np.all(np.isfinite(x)) and np.all(np.diff(x) >= -1e-9)
    assert 0.015 < x[-1] <= 0.0199
    Y = held_after_failure(part, t.size, len(model.output_names))
    assert np.all(np.isfinite(Y)) and np.all(Y[part.t.size:] == part.Y[-1])


def test_nothing_computed_gives_nan_rows():
    assert np.isnan(held_after_failure(None, 4, 2)).all()
