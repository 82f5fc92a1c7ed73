"""Issue 6 on real data: from the Festo TP511 machine WITHOUT end stops, diagnose finds
`end_stop` in the rig's recordings (../shared/real/festo_tp511), places the extended stop at
the rig's 200 mm stroke (its README) and cuts the held-out pressure error. Train: extension
to the stop at 2 and 3 V; validate: 4 and 5 V (experiments/festo/end_stop_*.yaml)."""
from pathlib import Path

import pytest

from hydrocli.diagnose import Settings, diagnose, residuals
from hydrocli.diagnose.summary import write_augmented
from hydrocli.netlist.loader import load_netlist

ROOT = Path(__file__).parents[2]
DATA = ROOT.parent / "shared" / "real" / "festo_tp511"
EXP = ROOT / "experiments" / "festo"


@pytest.mark.skipif(not DATA.is_dir(), reason="shared Festo recordings not available")
def test_diagnose_finds_the_end_stop_on_the_real_festo_rig(tmp_path, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "cache"))
    d = diagnose(ROOT / "machines" / "festo_tp511_no_endstops.yaml", [EXP / "end_stop_train.yaml"],
                 [EXP / "end_stop_validate.yaml"], Settings(max_effects=1, jobs=2))
    assert d.data["effects"] == ["end_stop"]
    acc = d.data["accepted"][0]
    x_max = next(p for p in acc["parameters"] if p["name"].endswith("x_max"))
    assert 0.19 < x_max["value"] < 0.21                         # the rig's 0.2 m stroke (± 5 %)
    before, after = acc["esr_validation_before"], acc["esr_validation_after"]
    assert all(v == v for v in before.values())                 # a runaway piston still scores (no NaN)
    # the base fit (nuisance areas and spool dynamics free) already tracks x to a few 0.01 %
    # ESR by bending the runaway piston's stroke; with the stop x stays a good fit (< 0.2 %)
    assert after["pA"] < 0.1 * before["pA"] and after["x"] < max(before["x"], 0.2)
    write_augmented(d, tmp_path / "augmented.yaml")
    cyl = load_netlist(tmp_path / "augmented.yaml").components["cylinder"]
    assert "x_max" in cyl.params and "k_stop" in cyl.params


def _chamber_b(src: Path, dest: Path) -> Path:
    """The same windows of the chamber-B recordings (the rig's one pressure sensor moved)."""
    text = src.read_text().replace("pA", "pB").replace("../../../shared", str(ROOT.parent / "shared"))
    dest.write_text(text)
    return dest


@pytest.mark.skipif(not DATA.is_dir(), reason="shared Festo recordings not available")
def test_diagnose_pools_recordings_that_measure_different_chambers(tmp_path, monkeypatch):
    """pA in some recordings, pB in others: each experiment is fitted and scored on what it
    measured, and both pressures improve."""
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "cache"))
    train = [EXP / "end_stop_train.yaml", _chamber_b(EXP / "end_stop_train.yaml", tmp_path / "train_b.yaml")]
    val = [EXP / "end_stop_validate.yaml", _chamber_b(EXP / "end_stop_validate.yaml", tmp_path / "val_b.yaml")]
    d = diagnose(ROOT / "machines" / "festo_tp511_no_endstops.yaml", train, val, Settings(max_effects=1, jobs=2))
    assert d.outputs == ["x", "pA", "pB"] and d.data["effects"] == ["end_stop"]
    before, after = d.data["esr_validation_base"], d.data["esr_validation_final"]
    assert after["pA"] < 0.2 * before["pA"] and after["pB"] < 0.2 * before["pB"]


@pytest.mark.slow
@pytest.mark.skipif(not DATA.is_dir(), reason="shared Festo recordings not available")
def test_full_festo_machine_no_missing_physics(tmp_path, monkeypatch):
    """Issue 10 item 4: the rig's FULL machine (end stops and end cushions) on the repeat-1
    step recordings, both pressures trained and held out (pA 1/3/5 V + pB 2/4 V against the
    rest). No PHYSICAL effect (hydraulic, mechanical, valve) passes: the base model already
    predicts the held-out recordings closely (docs/festo.md: x < 0.25 %, p < 1 % ESR). Since
    the base fit converges (session 5), the measurement model may be widened: the rig's
    pressure reading lags beyond a typical transducer's few ms (docs/festo.md: the one sensor
    is moved between the ports; its B-side reading lags ~12 ms, the measuring connection) —
    if so, it must be a lag beyond the typical range and improve EVERY held-out pressure
    recording (a measurement property acts in every run, not in one)."""
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path / "cache"))
    a, b = EXP / "steps_pA.yaml", EXP / "steps_pB.yaml"
    train = [f"{a}#festo_pA_1V", f"{a}#festo_pA_3V", f"{a}#festo_pA_5V", f"{b}#festo_pB_2V", f"{b}#festo_pB_4V"]
    validate = [f"{a}#festo_pA_2V", f"{a}#festo_pA_4V", f"{b}#festo_pB_1V", f"{b}#festo_pB_3V", f"{b}#festo_pB_5V"]
    d = diagnose(ROOT / "machines" / "festo_tp511.yaml", train, validate, Settings(max_effects=1, jobs=2))
    assert d.data["effects"] in (["none"], ["sensor_lag"])   # no physics is missing from the full machine
    esr = d.data["esr_validation_final"]
    assert esr["x"] < 0.25 and esr["pA"] < 1.0 and esr["pB"] < 1.0
    assert {"x", "pA", "pB"} <= set(esr)                        # both pressures judged, not just x
    if d.data["effects"] == ["sensor_lag"]:
        taus = [p["value"] for p in d.data["accepted"][0]["parameters"]]
        assert max(taus) > 5e-3                                  # beyond a typical transducer
        for e, y0, y1 in zip(d.validate, d.base.Y_validation, d.final.Y_validation):
            q = [o for o in ("pA", "pB") if o in e.measured]
            before = residuals.esr_table(d.base.model, [e], [y0], q)
            after = residuals.esr_table(d.final.model, [e], [y1], q)
            assert all(after[o] < before[o] for o in q), e.name
