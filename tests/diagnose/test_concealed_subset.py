"""Diagnose on a fast subset of the project's concealed recordings (experiments/concealed:
an independent truth simulator, effect in a form unlike the candidate's). The first 10 s of
the coulomb_friction case, from its base machine without Coulomb friction: the diagnosis
must name the effect and improve held-out ESR. The sidecar is read only to score."""
import json
from pathlib import Path

import pytest

from hydrocli.diagnose import Settings, diagnose

CASE = Path(__file__).parents[2] / "experiments" / "concealed" / "coulomb_friction"


def _windowed(tmp_path: Path, which: str) -> Path:
    p = tmp_path / f"{which}.yaml"
    p.write_text(f"name: {which}\ndata: {CASE / (which + '.csv')}\ninputs: {{u: u, Ps: Ps, Fext: Fext}}\n"
                 "outputs: {P1: P1, P2: P2, x: x, v: v}\nwindow: [0 s, 10 s]\n")
    return p


@pytest.mark.skipif(not CASE.exists(), reason="concealed recordings not generated")
def test_names_coulomb_friction_on_concealed_recording(tmp_path, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "cache"))
    truth = json.loads((CASE / "train.json").read_text())["effect"]
    d = diagnose(CASE / "base.yaml", [_windowed(tmp_path, "train")], [_windowed(tmp_path, "validate")],
                 Settings(max_effects=1, jobs=2))
    assert d.data["effects"][0] == truth == "coulomb_friction"
    # the free base imitates most of it with Stribeck velocities widened ×15 to their bound;
    # the diagnosis restrains them (restrain.py) and the plausible model predicts better than
    # both bases: half the restrained one's held-out error, below the free one's
    before, after = d.data["esr_validation_base"], d.data["esr_validation_final"]
    restrained = d.data["restrained_base"]["esr_validation"]
    assert {p["name"] for p in d.data["restrained_base"]["parameters"]} == {"friction.vs_p", "friction.vs_m"}
    assert sum(after.values()) < sum(before.values()) - 0.1
    assert sum(after.values()) < 0.5 * sum(restrained.values())
    # the force found against the truth's (arctan law, Fc+ 380 N, Fc- 480 N in the sidecar)
    fc = json.loads((CASE / "train.json").read_text())["effect_params"]
    kc = {p["name"]: p["value"] for p in d.data["accepted"][0]["parameters"]}
    assert 0.6 * fc["Fc_p"] < kc["friction.kc_p"] < 1.4 * fc["Fc_p"]
    assert 0.6 * fc["Fc_m"] < kc["friction.kc_m"] < 1.4 * fc["Fc_m"]
