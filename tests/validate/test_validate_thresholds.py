"""Threshold sources, precedence, verdict rows, derived measurements."""
import numpy as np
import pytest

from hydrocli.errors import DataError
from hydrocli.results import RunResult
from hydrocli.validate import Row, check_outputs, load_thresholds, parse_max_esr, score


def test_row_pass_fail_and_nan():
    assert Row("e", "dp", 1.0, 0.1, 90, threshold=2.0).passed is True
    assert Row("e", "dp", 3.0, 0.1, 90, threshold=2.0).passed is False
    assert Row("e", "dp", float("nan"), 0.1, 90, threshold=2.0).passed is False
    assert Row("e", "dp", 3.0, 0.1, 90).passed is None


def test_precedence_experiment_file_cli(tmp_path):
    f = tmp_path / "v.yaml"
    f.write_text("max_esr: {dp: 10, v: 5}\nexperiments:\n  run2: {max_esr: {dp: 3, x: '4 %'}}\n")
    file_th = load_thresholds(f)
    assert file_th.for_experiment("run1", {"dp": 50, "P1": 7}) == {"dp": 10, "v": 5, "P1": 7}
    assert file_th.for_experiment("run2") == {"dp": 3, "v": 5, "x": 4}
    both = file_th.overridden_by(parse_max_esr(["v=1", "run2:x=2"]))
    assert both.for_experiment("run1") == {"dp": 10, "v": 1}
    assert both.for_experiment("run2") == {"dp": 3, "v": 1, "x": 2}


@pytest.mark.parametrize("text,where", [("max_esr: {dp: -1}\n", 1), ("max_esr: {dp: 1}\nmax_err: {v: 2}\n", 2),
                                         ("max_esr: {dp: lots}\n", 1)])
def test_bad_validation_file_is_located(tmp_path, text, where):
    f = tmp_path / "v.yaml"
    f.write_text(text)
    with pytest.raises(DataError) as exc:
        load_thresholds(f)
    assert exc.value.problems[0].location.line == where
    assert exc.value.problems[0].hint


def test_bad_max_esr_and_unknown_output():
    with pytest.raises(DataError):
        parse_max_esr(["dp"])
    with pytest.raises(DataError, match="did you mean 'dp'"):
        check_outputs(parse_max_esr(["dpp=3"]), ["dp", "v"])


def test_score_rows_and_missing_measurement():
    t = np.arange(4.0)
    res = RunResult("m", "", "", "e1", t, {}, {"a": np.array([1.0, 2, 3, 5]), "b": t}, {},
                    measured={"a": np.array([1.0, 2, 3, 4])})
    rows = score(res, {"a": 20.0, "b": 1.0})
    assert [(r.output, r.passed) for r in rows] == [("a", True), ("b", False)]
    assert rows[0].esr == pytest.approx(15.0)
    assert rows[1].note == "not measured"


def test_validate_scores_derived_outputs_without_mutating_the_experiments(monkeypatch):
    """dp = P1 − P2 is derived into a copy: the loaded experiment keeps only what it recorded."""
    from pathlib import Path

    import hydrocli.experiments.experiment_file as ef
    from hydrocli.validate import Thresholds, validate_machine
    root = Path(__file__).resolve().parents[2]
    kept = []
    real = ef.load_all
    monkeypatch.setattr(ef, "load_all", lambda path, m: kept.extend(real(path, m)) or kept)
    verdict = validate_machine(root / "machines" / "eha_testbench.yaml",
                               [root.parent / "shared" / "recordings" / "eha_none" / "validate.csv"], Thresholds())
    assert "dp" in verdict.results[0].measured
    assert "dp" not in kept[0].measured and {"P1", "P2"} <= set(kept[0].measured)
