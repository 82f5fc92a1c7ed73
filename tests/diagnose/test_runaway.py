"""A base model that cannot simulate the training recordings at all (diagnose/runaway.py).

A vane drive with a stop at 0.3 rad that its machine file lacks, driven open into it: fed the
recorded command, the base vane swings on until a chamber empties and every trial fails. The
diagnosis places stops at the ends of the recorded travel, the base fit finds the stop where
the truth has it (between its 0.3 rad and the recorded maximum, where the vane rests on the
stop compressed by the net torque over its stiffness), the lower stop, which nothing presses, is withdrawn, and the end stop is
reported as a base-fit finding."""
import os
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose import Settings
from hydrocli.diagnose import engine
from hydrocli.diagnose.runaway import first_failure
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

ROOT = Path(__file__).parents[2]
BASE = (ROOT / "machines" / "rotary_drive.yaml").read_text()
THETA_STOP = 0.3


def _record(model, t, u, path, rng):
    U = np.column_stack([u, np.full(t.size, 1e7)])
    Y = simulate(model, InputTable(t, U), t, opts=SolverOptions(rtol=1e-7)).Y
    y = {o: Y[:, model.output_names.index(o)] for o in ("P1", "P2", "theta", "w")}
    y["P1"] = y["P1"] + 1e4 * rng.normal(size=t.size)
    y["P2"] = y["P2"] + 1e4 * rng.normal(size=t.size)
    y["w"] = y["w"] + 2e-3 * rng.normal(size=t.size)
    np.savetxt(path, np.column_stack([t, 100.0 * u, U[:, 1], y["P1"], y["P2"], y["theta"], y["w"]]), delimiter=",",
               header="t[s],u[%],Ps[Pa],P1[Pa],P2[Pa],theta[rad],w[rad/s]", comments="")
    return y


def _command(t, push, back, t_back):
    """Open towards +theta (onto the stop), back for a moment, then closed (SI: 1 = 100 %)."""
    return np.where(t < 0.3, 0.0, np.where(t < t_back, push, np.where(t < t_back + 0.25, back, 0.0)))


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    d = tmp_path_factory.mktemp("runaway")
    os.environ.setdefault("HYDRO_CACHE_DIR", str(d / "cache"))
    (d / "base.yaml").write_text(BASE)
    truth = build_model(load_netlist_text(BASE.replace(
        "    R_v: {value: 0.0, free: false}",
        f"    R_v: {{value: 0.0, free: false}}\n    theta_max: {THETA_STOP}\n    k_stop: \"5.0e4 N*m/rad\"\n"
        "    c_stop: 300.0"), str(d / "truth.yaml")))
    rng = np.random.default_rng(3)
    t = np.arange(0.0, 5.0005, 1e-3)
    # long enough open that the stop-less base swings past the 3 rad where a chamber empties
    y = _record(truth, t, _command(t, 0.5, -0.2, 3.8), d / "train.csv", rng)
    _record(truth, t, _command(t, 0.4, -0.15, 3.5), d / "validate.csv", rng)
    return d, y


def test_the_base_cannot_simulate_the_record_and_stops_at_the_recorded_ends_can(case):
    d, y = case
    assert y["theta"].max() > THETA_STOP                     # the truth rests on (and compresses) its stop
    su = engine.prepare(d / "base.yaml", [d / "train.csv"], [d / "validate.csv"], Settings(jobs=1))
    assert first_failure(su.model, su.train) is not None    # without stops: a chamber empties
    su2, run = engine.follow(su)
    assert run is not None and run.candidate.effect == "end_stop"
    assert first_failure(su2.model, su2.train) is None


def test_the_base_fit_places_the_stop_and_withdraws_the_one_never_pressed(case):
    d, y = case
    su, run = engine.follow(engine.prepare(d / "base.yaml", [d / "train.csv"], [d / "validate.csv"],
                                           Settings(jobs=1)))
    b = engine.baseline_step(su, Settings(jobs=1), run=run)
    f = b.found[0]
    assert (f["effect"], f["source"]) == ("end_stop", "base_fit")
    par = {p["name"]: p for p in f["parameters"]}
    # between where contact begins (the truth's 0.3 rad) and where the vane rests on the stop,
    # compressed by the net torque over its stiffness (the recorded maximum)
    assert THETA_STOP - 1e-3 < par["vane.theta_max"]["value"] < y["theta"].max() + 1e-3
    assert "withdrawn" in par["vane.theta_min"] and "withdrawn" not in par["vane.theta_max"]
    assert par["vane.theta_min"]["value"] < y["theta"].min() - 0.4 * np.ptp(y["theta"])   # out of reach
    # with the stop the base follows the held-out recording to within a few times its noise
    assert b.stage.esr_validation["P1"] < 1.0 and b.stage.esr_validation["theta"] < 0.1
