"""Ambiguity end to end (issue 10): on a vane pendulum whose oil carries isothermal, partly
dissolving air (the family's independent truth, experiments/family), the training data let
entrained air and a compliant rod–load coupling explain the recordings nearly alike. The
diagnosis must say so and propose a discriminating experiment; that experiment is then
RECORDED on the truth (experiments/family/record.py: the independent simulator, sensor noise)
and the diagnosis is run again with it among the training data, restricted to the two
effects as the proposal says (--only A --only B): air must still come first. (It does not yet
DECIDE: re-fitted on the new record both models predict it alike — see the test's end.)

Slow (two diagnoses of a 20 s case plus generating it: a few minutes on two cores)."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    from experiments.family.generate import run_case
    out = tmp_path_factory.mktemp("family")
    os.environ.setdefault("HYDRO_CACHE_DIR", str(out / "cache"))
    run_case("rotary", "entrained_air", "isothermal_dissolving", 1, out)
    return out / "rotary" / "rotary__entrained_air__isothermal_dissolving__s1"


def test_air_against_a_compliant_coupling_is_ambiguous_and_a_recorded_proposal_keeps_air_first(case, tmp_path):
    from experiments.family.record import record
    from hydrocli.diagnose import Settings, diagnose
    from hydrocli.diagnose.summary import write_proposals

    d1 = diagnose(case / "base.yaml", [case / "train.csv"], [case / "validate.csv"], Settings(jobs=2))
    amb = d1.data.get("ambiguous") or []
    pair = next(a for a in amb if "entrained_air" in a["effects"])
    rival = next(e for e in pair["effects"] if e != "entrained_air")
    assert rival in ("load_compliance", "structural_flexibility")
    prop = pair["proposed_experiment"]
    assert prop["discrimination"] > 100.0                 # χ² the two fitted models predict on it
    paths = write_proposals(d1, tmp_path)
    text = paths[0].read_text()
    assert "--only entrained_air" in text and f"--only {rival}" in text

    rec = tmp_path / "proposed.csv"
    assert record(case, paths[0], rec)["ok"]
    d2 = diagnose(case / "base.yaml", [case / "train.csv", rec], [case / "validate.csv"],
                  Settings(jobs=2, only=("entrained_air", rival)))
    assert d2.data["effects"][0] == "entrained_air"
    # what the recorded experiment does NOT yet do: once both models are re-fitted with it,
    # they predict it alike (ESR 3.9 vs 4.0 %), so the pair stays reported as ambiguous. The
    # design scores a test with each model's parameters held at their fits (predicted
    # χ² ≈ 5000); a design that re-fits the rival to the winner's prediction (Atkinson–Fedorov
    # T-optimality) is the known next step (docs/diagnose.md). The rival still trails air:
    amb2 = next(a for a in d2.data.get("ambiguous", []) if "entrained_air" in a["effects"])
    air, other = (amb2["delta_bic"][amb2["effects"].index(e)] for e in ("entrained_air", rival))
    assert air < other < 0
    assert json.dumps(d2.data["ranking"], default=str)
