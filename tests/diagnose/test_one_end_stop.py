"""A machine that presses ONE end of its travel: the concealed end-stop bench
(experiments/concealed/end_stop, the independent truth simulator's Hunt–Crossley head stop at
x = 0.128 m; the bottom of the record, 0.0546 m, is only where the motion turned).

Started with stops at both recorded ends, the fit costs more than with both far beyond the
record, and from there it never meets the head stop (session 10's regression: x_max ended
6 mm beyond the record, was withdrawn as never pressed, verdict unexplained_mismatch). The
candidate is also started with each stop alone at its probe (workers._one_end_probes)."""
import json
from pathlib import Path

from hydrocli.diagnose import Settings, diagnose
from hydrocli.diagnose.candidates.base import NewParam
from hydrocli.diagnose.workers import _one_end_probes

CASE = Path(__file__).resolve().parents[2] / "experiments" / "concealed" / "end_stop"


def test_each_stop_is_also_started_alone_at_its_probe():
    lo = NewParam("c.x_min", -0.2, (-0.5, 0.02), (-0.5, 0.02), -0.005, scale=1.0, seen=(0.0, 1.0))
    hi = NewParam("c.x_max", 1.2, (0.98, 1.5), (0.98, 1.5), 1.005, scale=1.0, seen=(0.0, 1.0))
    k = NewParam("c.k_stop", 1e8, (1e5, 1e11), (1e5, 1e11), 3e8, True, primary=False)
    starts = _one_end_probes([lo, hi, k])
    assert starts == [{"c.x_min": -0.005, "c.x_max": 1.2, "c.k_stop": 3e8},
                      {"c.x_min": -0.2, "c.x_max": 1.005, "c.k_stop": 3e8}]
    assert _one_end_probes([k]) == []


def test_the_head_stop_pressed_alone_is_found_where_the_truth_has_it():
    truth = json.loads((CASE / "train.json").read_text())["effect_params"]["x_stop"]
    d = diagnose(CASE / "base.yaml", [CASE / "train.csv"], [CASE / "validate.csv"],
                 Settings(jobs=1, only=("end_stop",)))
    assert d.data["effects"][0] == "end_stop"
    params = {p["name"]: p for p in d.data["accepted"][0]["parameters"]}
    assert abs(params["cylinder.x_max"]["value"] - truth) < 2e-3      # within 2 mm of the truth's stop
    assert "withdrawn" not in params["cylinder.x_max"]
    # the bottom is never pressed: withdrawn (the stop candidate), or out of reach from the start
    # (a cushion's candidate, which brings the stop of its own end only)
    assert "withdrawn" in params["cylinder.x_min"] if "cylinder.x_min" in params else \
        any(n.startswith("cylinder_cushion_max.") for n in params)
