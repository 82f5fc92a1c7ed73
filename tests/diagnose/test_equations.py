"""Equation errors along the measured trajectory (hydrocli/diagnose/equations.py): they land in
the balance whose physics the model lacks, and a model that cannot follow the record leaves
them out instead of ending the diagnosis."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from hydrocli.diagnose import equations
from hydrocli.errors import SolverError
from hydrocli.experiments.experiment import Experiment
from hydrocli.runner import load_machine
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

LIFT = Path(__file__).resolve().parents[2] / "machines" / "luffing_cylinder.yaml"


def test_a_missing_friction_lands_in_the_force_balance_not_in_the_chambers():
    """The lift recorded (noise-free, 6 s of a 0.4 Hz command) with four times the file's
    Coulomb friction: replayed with the file's friction, the force balance at the rod carries
    an error several times the one with the truth's parameters, the chambers' continuity the
    same — the friction enters the force balance only, and the chambers' equations are
    evaluated on the measured pressures and motion."""
    _, model = load_machine(LIFT)
    t = np.arange(6001) / 1000.0
    u = 0.05 * np.sin(2 * np.pi * 0.4 * t) + 0.01 * np.sin(2 * np.pi * 2.3 * t)
    inputs = InputTable(t, np.column_stack([u if n == "u" else np.full_like(t, 160e5) for n in model.input_names]))
    truth = model.p0.copy()
    for k in ("friction.kc_p", "friction.kc_m"):
        truth[model.param_index(k)] *= 4.0
    tr = simulate(model, inputs, t, p=truth, x0=model.x0, opts=SolverOptions(rtol=1e-8))
    exp = Experiment(name="friction x4", file="<synthetic>", inputs=inputs, t_out=t.copy(),
                     measured={o: tr.Y[:, j] for j, o in enumerate(model.output_names)},
                     fit_outputs=list(model.output_names))
    right, why = equations.located_equations(model, exp, truth)
    wrong, _ = equations.located_equations(model, exp, model.p0)
    assert why is None and all("error" not in d for d in right.values())
    force = [s for s, d in right.items() if d["balance"].startswith("force balance")]
    chambers = [s for s, d in right.items() if d["balance"].startswith("continuity")]
    assert len(force) == 1 and len(chambers) == 2
    assert wrong[force[0]]["relative_rms"] > 4 * right[force[0]]["relative_rms"]
    for s in chambers:
        assert abs(wrong[s]["relative_rms"] - right[s]["relative_rms"]) < 0.01 * right[s]["relative_rms"]


def test_a_model_that_cannot_follow_the_record_reports_no_equations(monkeypatch):
    """A stroke overrun along the training record (as on held-out seed 89's lift) must not end
    the diagnosis: the equations only say where an error lands."""
    def overrun(*a, **k):
        raise SolverError("at t = 18.04 s: cylinder: chamber B collapsed below 1 % of its volume (stroke overrun)")

    monkeypatch.setattr(equations, "hybrid_trajectory", overrun)
    eq, why = equations.located_equations(None, None, np.zeros(1))
    assert eq == {} and "stroke overrun" in why
