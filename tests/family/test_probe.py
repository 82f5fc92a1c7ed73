"""The generality probe's generator (experiments/probe): each concealed effect is really in
its truth, the null carries only the fixed-parameter perturbations, and a case is written in
the family's layout (with the machine's included files) that the family benchmark reads."""
import json

import numpy as np
import pandas as pd
import pytest
import yaml

from experiments.probe import generate as G
from experiments.probe.machines import SPECS
from hydrocli.runner import load_machine

CASES = [(m, e) for m, spec in sorted(SPECS.items()) for e in sorted(spec.cases)]


@pytest.mark.parametrize("machine, effect", CASES)
def test_every_truth_builds_and_only_the_effect_differs_from_the_null(tmp_path, machine, effect):
    spec = SPECS[machine]
    doc, drawn = G.truth_doc(spec, effect, 3)
    null, drawn0 = G.truth_doc(spec, "none", 3)
    assert drawn["fixed_parameters"] == drawn0["fixed_parameters"]
    for name, v in drawn["fixed_parameters"].items():
        assert 0.85 <= v / spec.fixed[name] <= 1.15
    assert (doc != null) == (effect != "none")
    G._copy_includes(spec, tmp_path)
    f = tmp_path / "truth.yaml"
    f.write_text(yaml.safe_dump(doc))
    net, _ = load_machine(str(f))                 # builds: every added component is wired
    for name, v in drawn["fixed_parameters"].items():
        comp, par = name.rsplit(".", 1)
        assert net.components[comp].params[par].value == pytest.approx(v)


@pytest.mark.parametrize("machine, effect", [("sarcos", "external_leakage"), ("crane", "input_delay")])
def test_a_case_carries_its_effect_and_the_familys_sidecars(tmp_path, machine, effect):
    spec = SPECS[machine]
    folder = G.make_case(spec, tmp_path, effect, 1)
    assert (folder / "base.yaml").read_text() == spec.base.read_text()
    load_machine(str(folder / "base.yaml"))        # its includes came along
    for kind in ("train", "validate"):
        side = json.loads((folder / f"{kind}.json").read_text())
        assert side["effect"] == effect and side["machine"] == machine
        assert side["split"] in ("dev", "heldout")
        # a 2e13 Pa·s/m³ leak from a 20 cm³ chamber at ~100 bar; a 40–80 ms joystick delay
        # on a jib swept at up to 1 Hz (the held-out steps show less of it): above the noise
        assert side["effect_esr_percent"]["size"] > (0.5 if kind == "train" else 0.1)
        assert max(side["noise_esr_percent"].values()) < 1.0
        df = pd.read_csv(folder / f"{kind}.csv")
        assert [c.split("[")[0] for c in df.columns] == ["t", *spec.inputs, *spec.sensors]
    # the truth starts settled: the first samples sit within the noise of each other
    first = list(spec.sensors)[1]
    y = pd.read_csv(folder / "train.csv").filter(like=f"{first}[").to_numpy()[:, 0]
    assert abs(y[:10].mean() - y[10:20].mean()) < 5 * spec.sensors[first][0]
    assert np.all(np.diff(pd.read_csv(folder / "train.csv")["t[s]"]) > 0)
