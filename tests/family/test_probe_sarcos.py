"""The SARCOS generality probe's generator (experiments/probe/sarcos.py): each concealed effect
is really in the truth, the null carries only the fixed-parameter perturbations, and a case is
written in the family's layout that the family benchmark reads."""
import json

import numpy as np
import pandas as pd
import pytest

from experiments.probe import sarcos
from hydrocli.runner import load_machine


@pytest.mark.parametrize("effect", sorted(sarcos.CASES))
def test_every_truth_builds_and_only_the_effect_differs_from_the_null(tmp_path, effect):
    doc, drawn = sarcos.truth_doc(effect, 3)
    null, drawn0 = sarcos.truth_doc("none", 3)
    assert drawn["fixed_parameters"] == drawn0["fixed_parameters"]
    for name, v in drawn["fixed_parameters"].items():
        comp, par = name.split(".")
        v0 = {"vane_inertia.J": 1e-3, "servovalve.zeta": 1.0, "vane_friction.b": 0.5}[name]
        assert 0.85 <= v / v0 <= 1.15 and doc["components"][comp][par] == v
    f = tmp_path / "truth.yaml"
    f.write_text(sarcos.yaml.safe_dump(doc))
    load_machine(str(f))                    # builds: every added component is wired
    added = set(doc["components"]) - set(null["components"])
    assert bool(added) == (effect != "none")


def test_a_case_carries_its_effect_and_the_familys_sidecars(tmp_path):
    folder = sarcos.make_case(tmp_path, "external_leakage", 1)
    assert (folder / "base.yaml").read_text() == sarcos.BASE.read_text()
    for kind in ("train", "validate"):
        side = json.loads((folder / f"{kind}.json").read_text())
        assert side["effect"] == "external_leakage" and side["machine"] == "sarcos"
        assert side["split"] in ("dev", "heldout")
        # a 2e13 Pa·s/m³ leak from a 20 cm³ chamber at ~100 bar: far above the sensors' noise
        assert side["effect_esr_percent"]["size"] > 0.5
        assert max(side["noise_esr_percent"].values()) < 0.1
        df = pd.read_csv(folder / f"{kind}.csv")
        assert list(df.columns) == ["t[s]", "i[A]", "P1[Pa]", "P2[Pa]", "theta[rad]"]
        assert np.allclose(np.diff(df["t[s]"]), 1e-3)
    # the truth starts settled: the first samples sit within the noise of each other
    p1 = pd.read_csv(folder / "train.csv")["P1[Pa]"].to_numpy()
    assert abs(p1[:20].mean() - p1[20:40].mean()) < 5 * sarcos.SENSORS["P1"]
