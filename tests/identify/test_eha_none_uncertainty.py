"""Issue 12's acceptance on the eha_none recording (independent simulator, true parameters in
its sidecar): the fit names valve.tau among the fixed parameters its estimates depend on; with
valve.tau freed and the recordings' 1 ms pressure transducers modelled, the true values lie
inside the reported 95 % intervals, except where the model-error check names the estimate."""
from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from synth import EHA, ROOT

TRAIN = ROOT / "experiments" / "eha" / "none_train.yaml"
SIDECAR = ROOT.parent / "shared" / "recordings" / "eha_none" / "train.json"
SENSED = ROOT / "tests" / "identify" / "data" / "eha_sensed.yaml"
# machine parameter → the sidecar's name
TRUE_NAMES = {"valve.Kv": "Kv", "valve.tau": "tau_v", "cylinder.V_A0": "V10", "cylinder.V_B0": "V20",
              "cylinder.beta": "beta", "cylinder.c_il": "c_il", "cylinder.c_el": "c_el", "load.m": "m",
              "friction.kv_p": "kv_p", "friction.kv_m": "kv_m", "friction.kc_p": "kc_p", "friction.kc_m": "kc_m",
              "friction.ks_p": "ks_p", "friction.ks_m": "ks_m", "friction.vs_p": "taus_p", "friction.vs_m": "taus_m"}

pytestmark = [pytest.mark.slow, pytest.mark.skipif(not SIDECAR.exists(), reason="needs ../shared/recordings")]


def _invoke(*args):
    from hydrocli.cli.main import app
    return CliRunner().invoke(app, [str(a) for a in args])


def _block(output: str, title: str) -> str:
    part = output.split(title, 1)[1] if title in output else ""
    return part.split("\nidentified machine", 1)[0]


def test_identify_names_valve_tau_among_the_fixed_parameters(tmp_path):
    r = _invoke("identify", EHA, "-e", TRAIN, "-o", tmp_path / "id.yaml")
    assert r.exit_code == 0, r.output
    fixed = _block(r.output, "fixed parameters the estimates are sensitive to:")
    assert "a 10 % error in valve.tau moves" in fixed, r.output


def test_with_valve_tau_free_the_truth_lies_inside_the_intervals():
    from hydrocli.experiments.experiment_file import load_experiment
    from hydrocli.identify.fit import fit
    from hydrocli.runner import load_machine
    _, model = load_machine(SENSED)
    res = fit(model, [load_experiment(TRAIN, model)], model.free_params + ["valve.tau"], assess=True)
    truth = json.loads(SIDECAR.read_text())["true_base_params"]
    names, est, lo, hi = res.names, res.estimates, res.uncertainty.ci_lower, res.uncertainty.ci_upper
    assert "valve.tau" in names and len(names) == 16 and res.gradient == "sensitivities"
    outside = []
    for n, e, a, b in zip(names, est, lo, hi):
        t = truth[TRUE_NAMES[n]]
        if not a <= t <= b:
            outside.append(n)
    # The simulator's spool is not ours: valve.tau lands 1.2 % from the truth, far outside its
    # ±0.2 % interval, and cylinder.beta follows it. No interval built from the residuals can
    # bound such a model error, but the model-error check must name every estimate whose
    # interval misses the truth (and valve.tau among them).
    flagged = {m.split(":", 1)[0] for m in res.uncertainty.window_messages}
    assert len(outside) <= 2, outside
    assert set(outside) <= flagged, (outside, res.uncertainty.window_messages)
    assert "valve.tau" in flagged
    i = names.index("valve.tau")
    assert abs(est[i] / truth["tau_v"] - 1) < 0.03
    m = names.index("load.m")
    assert abs(est[m] / truth["m"] - 1) < 0.01          # 9 % off when the transducers' lag is not modelled
