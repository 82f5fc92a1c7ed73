"""The family benchmark's scoring (tests/benchmarks/bench_diagnose_family.py) on hand-made rows."""
from __future__ import annotations

import importlib.util
import json
from types import SimpleNamespace
from pathlib import Path

import pytest

_spec = importlib.util.spec_from_file_location(
    "bench_family", Path(__file__).parents[1] / "benchmarks" / "bench_diagnose_family.py")
bench = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)


def _row(effect, named, machine="lift", size=2.0, closed=True):
    return {"effect": effect, "named": named, "machine": machine, "size": size, "gap_closed": closed,
            "seconds": 10.0, "error": None}


def test_top1_reads_effects_then_verdict():
    assert bench.top1({"effects": ["entrained_air", "sensor_lag"], "verdict": "missing_physics"}) == "entrained_air"
    assert bench.top1({"effects": ["none"], "verdict": "none"}) == "none"
    assert bench.top1({"effects": [], "verdict": "unexplained_mismatch"}) == "unexplained_mismatch"


def test_gap_closed_rule():
    noise = {"P1": 0.1}
    assert bench.gap_closed({"P1": 2.1}, {"P1": 0.5}, noise)          # 0.5 <= 0.1 + 0.2*2.0
    assert not bench.gap_closed({"P1": 2.1}, {"P1": 0.6}, noise)


def test_the_averaged_gap_rule_lets_an_output_at_the_noise_not_decide():
    """P2 barely shows the effect (before 3 % above its noise, after 1 % above): every output
    fails the per-output rule; the ESR averaged over P1 and P2 closes its gap."""
    noise, before, after = {"P1": 0.1, "P2": 0.1}, {"P1": 2.1, "P2": 0.103}, {"P1": 0.2, "P2": 0.101}
    assert not bench.gap_closed(before, after, noise)
    assert bench.gap_closed_mean(before, after, noise)            # 0.1505 <= 0.1 + 0.2 * 1.0015
    assert not bench.gap_closed_mean(before, {"P1": 0.6, "P2": 0.101}, noise)
    assert not bench.gap_closed_mean(before, after, {"v": 0.1})   # no common output: not closed


def test_the_gap_of_a_base_fit_finding_is_measured_without_it():
    """The base fit already contains what it found (c_el moved from 0, a chamber volume grown):
    its 'before' is the base with those parameters back at the file's values."""
    base, final = {"P1": 0.2}, {"P1": 0.2}
    found = {"accepted": [{"source": "base_fit", "esr_validation_before": {"P1": 0.9}}],
             "esr_validation_base": base, "esr_validation_final": final}
    assert bench.model_before(found) == {"P1": 0.9}
    assert bench.gap_closed(bench.model_before(found), final, {"P1": 0.15})
    assert not bench.gap_closed(base, final, {"P1": 0.15})            # against the base: nothing closed
    assert bench.model_before({"accepted": [], "esr_validation_base": base}) == base
    assert bench.model_before({"esr_validation_base": base}) == base


def test_aggregate_counts():
    rows = [_row("entrained_air", "entrained_air"), _row("entrained_air", "structural_flexibility", size=0.6),
            _row("structural_flexibility", "structural_flexibility", machine="rotary"),
            _row("none", "none"), _row("none", "sensor_lag", machine="rotary")]
    a = bench.aggregate(rows)
    assert a["confusion"]["entrained_air"] == {"entrained_air": 1, "structural_flexibility": 1}
    assert a["per_effect"]["entrained_air"]["recall"] == pytest.approx(0.5)
    assert a["per_effect"]["structural_flexibility"]["precision"] == pytest.approx(0.5)
    assert a["null_false_positive_rate"] == pytest.approx(0.5)
    assert a["esr_buckets"]["<1%"] == {"n": 1, "top1": 0}
    assert a["esr_buckets"][">=1%"] == {"n": 2, "top1": 2}
    assert a["per_machine"]["lift"]["top1_ge1"] == 1 and a["per_machine"]["rotary"]["nulls_none"] == 0
    rows[0]["seconds"] = 40.0
    a = bench.aggregate(rows)
    assert a["per_machine"]["lift"]["seconds_mean"] == pytest.approx(20.0)        # (40 + 10 + 10) / 3
    assert a["per_machine"]["lift"]["closed"] == 1 and a["per_machine"]["rotary"]["closed"] == 1
    rows[2]["gap_closed"] = False
    assert bench.aggregate(rows)["per_machine"]["rotary"]["closed"] == 0
    # the held-out gap, closed among the cases of each effect named right (aggregate, not per case)
    rows[0]["gap_closed"], rows[2]["gap_closed"] = True, False
    a = bench.aggregate(rows)
    assert a["per_effect"]["entrained_air"]["closed"] == 1 and a["per_effect"]["structural_flexibility"]["closed"] == 0
    assert a["per_effect"]["none"]["closed"] is None                 # a null has no gap to close
    assert a["gap_closed_among_right"] == {"n": 2, "closed": 1, "closed_mean": 0}   # effect cases named right only


def test_find_cases_filters_by_split(tmp_path):
    demo = Path(__file__).parents[2] / "experiments" / "family" / "demo"
    assert len(bench.find_cases(demo, "dev", None, None, None)) == 3
    assert bench.find_cases(demo, "heldout", None, None, None) == []
    assert len(bench.find_cases(demo, "dev", ["rotary"], None, None)) == 1


def test_acceptance_study_replays_the_band_and_keeps_every_other_reason():
    spec = importlib.util.spec_from_file_location(
        "acceptance_study", Path(__file__).parents[1] / "benchmarks" / "acceptance_study.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    row = {"effect": "sensor_lag", "esr_before": {"P1": 0.5, "v": 0.9}, "noise_validation": {"P1": 0.25, "v": 0.4},
           "candidates": [
               {"effect": "sensor_lag", "round": 1, "delta_bic": -900.0, "validation_gain": 0.3,
                "reasons": ["validation ESR gain 0.3 % is within the noise band (0.65 %)"]},
               {"effect": "input_delay", "round": 1, "delta_bic": -2000.0, "validation_gain": 0.5,
                "reasons": ["u_delay.T poorly determined (±80 % of its effect)"]}]}
    # band = max(kappa * 0.65, 0.15 * 0.75): the gain 0.3 passes below kappa ≈ 0.46 only
    assert study.named(row, 1.0) == "none"
    assert study.named(row, 0.25) == "sensor_lag"       # the better-BIC delay stays out: imprecise


def test_acceptance_study_replays_the_specific_gain_and_lists_the_margins_it_must_keep():
    """The replay passes a candidate below the band on a gain no other effect's comes near (as the
    engine does, accept.specific_need) and lists, for wrong effects and nulls judged on the band,
    how far their gain stood beyond the other effects' best."""
    spec = importlib.util.spec_from_file_location(
        "acceptance_study", Path(__file__).parents[1] / "benchmarks" / "acceptance_study.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    band = ["validation ESR gain is within the noise band (0.145 %)"]
    row = {"effect": "entrained_air", "case": "air", "esr_before": {"P1": 0.7}, "noise_validation": {"P1": 0.58},
           "candidates": [
               {"effect": "entrained_air", "round": 1, "delta_bic": -7000.0, "validation_gain": 0.11, "reasons": band},
               {"effect": "load_compliance", "round": 1, "delta_bic": -300.0, "validation_gain": 0.02, "reasons": band}]}
    assert study.named(row, 0.25) == "entrained_air"
    assert not study.passes(row["candidates"][0], row, 0.25, specific=False)
    (m, case, effect), = study.specific_margins([row])
    assert (case, effect) == ("air", "load_compliance") and m == pytest.approx((0.02 - 0.11) / 0.58)
    # the same gain shared with another effect is no specific gain
    row["candidates"][1]["validation_gain"] = 0.1
    assert study.named(row, 0.25) == "none"


def test_cases_alternate_between_machines_and_results_are_written_after_each(tmp_path):
    """A run stopped early has covered every machine alike and keeps what it measured."""
    folders = [tmp_path / m / f"{m}_{i}" for m in ("eha", "lift", "rotary") for i in range(3 if m == "eha" else 1)]
    order = bench._round_robin(folders)
    assert [f.parent.name for f in order] == ["eha", "lift", "rotary", "eha", "eha"]
    assert sorted(order) == sorted(folders)
    out = tmp_path / "r.json"
    row = {"effect": "none", "named": "none", "machine": "eha", "size": 0.0, "gap_closed": False,
           "seconds": 1.0, "error": None, "esr_before": {}, "esr_after": {}, "form": "a", "case": "c"}
    bench._write(out, SimpleNamespace(split="heldout", data=tmp_path), [row], blind=True, done=False)
    data = json.loads(out.read_text())
    assert data["complete"] is False and "cases" not in data and data["aggregate"]["n_cases"] == 1


def test_a_case_is_resolvable_when_the_base_fit_leaves_room_for_an_effect_to_pass():
    """``resolvable``: the engine's own reach test on the base fit. A base fit that predicts
    the held-out run at the noise floor (the file's free parameters absorbed the effect) leaves
    no effect anything to gain; one well above it does. Counted per machine beside the
    effect-ESR figures."""
    noise = {"P1": 0.2, "P2": 0.2}
    tests = {"noise_esr_validation": noise}
    assert not bench.resolvable({"esr_validation_base": {"P1": 0.21, "P2": 0.2}, "tests": tests})
    assert bench.resolvable({"esr_validation_base": {"P1": 0.9, "P2": 0.3}, "tests": tests})
    rows = [dict(_row("entrained_air", "none", machine="winch"), resolvable=False),
            dict(_row("entrained_air", "entrained_air", machine="winch"), resolvable=True),
            dict(_row("sensor_lag", "none", machine="winch"), resolvable=True)]
    m = bench.aggregate(rows)["per_machine"]["winch"]
    assert (m["top1_ge1"], m["effect_cases_ge1"]) == (1, 3)
    assert (m["top1_resolvable_ge1"], m["resolvable_ge1"]) == (1, 2)


def test_skip_names_results_files_and_a_machine_name_there_is_an_error(tmp_path, capsys):
    """``--skip rotary`` once ran every rotary case (a missing path was ignored): now exit 2."""
    with pytest.raises(SystemExit) as exc:
        bench.main(["--data", str(tmp_path), "--skip", "rotary"])
    assert exc.value.code == 2
    assert "not a file: rotary" in capsys.readouterr().err


def test_the_time_is_summed_by_kind_of_step_over_the_cases():
    rows = [_row("entrained_air", "entrained_air"), _row("none", "none")]
    rows[0]["timings"] = [{"step": "loading and the measurement model", "seconds": 1.0},
                          {"step": "base fit and the restrained base", "seconds": 9.0},
                          {"step": "round 1 from the restrained base", "seconds": 40.0},
                          {"step": "round 1: the earlier effects re-checked", "seconds": 5.0},
                          {"step": "round 2", "seconds": 30.0}]
    rows[1]["timings"] = [{"step": "base fit", "seconds": 4.0}, {"step": "round 1", "seconds": 20.0}]
    by = bench.aggregate(rows)["seconds_by_step"]
    assert by == {"rounds": 50.0, "rounds from a restrained base": 40.0, "base fit": 13.0,
                  "earlier effects re-checked": 5.0, "loading and the measurement model": 1.0}
    assert list(by)[0] == "rounds"                                   # largest first
