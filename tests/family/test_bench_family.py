"""The family benchmark's scoring (tests/benchmarks/bench_diagnose_family.py) on hand-made rows."""
from __future__ import annotations

import importlib.util
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


def test_find_cases_filters_by_split(tmp_path):
    demo = Path(__file__).parents[2] / "experiments" / "family" / "demo"
    assert len(bench.find_cases(demo, "dev", None, None, None)) == 3
    assert bench.find_cases(demo, "heldout", None, None, None) == []
    assert len(bench.find_cases(demo, "dev", ["rotary"], None, None)) == 1
