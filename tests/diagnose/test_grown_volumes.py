"""Grown chamber volumes (the base fit's fluid-compliance finding) are restrained to the
drawing's tolerance and tested like any implausible value: the catalogue's candidates that
could be that compliance (air, a hose) compete from the restrained base, and the finding gives
way to the one that beats the free base."""
from __future__ import annotations

from types import SimpleNamespace

from hydrocli.diagnose import engine, findings, restrain

BOUNDS = {"vane.V_1": (1e-6, 1e-3), "vane.V_2": (1e-6, 1e-3), "vane.beta": (5e8, 2.5e9)}


def _excess():
    vane = findings.Chambers("vane", ("vane.V_1", "vane.V_2"))
    rows = [{"name": "vane.V_1", "value": 6e-5 * 2.2, "initial": 6e-5, "stderr": 1e-6},
            {"name": "vane.V_2", "value": 6e-5 * 2.1, "initial": 6e-5, "stderr": 1e-6}]
    found = findings.fluid_compliance_excess(rows, [vane], lambda v: (3.0, 0.5))
    assert len(found) == 1 and found[0]["finding"] == findings.EXCESS_FINDING
    return found[0]


def test_grown_volumes_are_restrained_to_the_drawings_tolerance_and_nothing_else_is():
    lim = restrain.grown_volumes([_excess()], BOUNDS)
    assert lim == {"vane.V_1": (1e-6, findings.EXCESS * 6e-5), "vane.V_2": (1e-6, findings.EXCESS * 6e-5)}
    # a parameter finding (a leak moved from 0) or a one-sided volume is not restrained here
    leak = {"effect": "external_leakage", "source": "base_fit", "parameters": [{"name": "vane.V_1", "file_value": 6e-5}]}
    one_side = dict(_excess(), finding="undrawn_volume")
    assert restrain.grown_volumes([leak, one_side], BOUNDS) == {}


def _round(monkeypatch, accepted_effect):
    seen = {}

    def fake_round(su, stage, accepted, round_, st, pool, located, progress=None, floor=None, withdrawn=frozenset()):
        seen.update(stage=stage, accepted=[a["effect"] for a in accepted], floor=floor)
        acc = None if accepted_effect is None else {"effect": accepted_effect, "component": "valve"}
        return engine.Round([], accepted=acc)
    monkeypatch.setattr(engine, "round_step", fake_round)
    leak = {"effect": "external_leakage", "component": "vane", "source": "base_fit"}
    b = SimpleNamespace(restrained="restrained base", located={})
    free = "free base"
    said = []
    rnd, carried = engine._restrained_round(None, b, free, [leak, _excess()], engine.Settings(), None, said.append)
    return seen, rnd, carried, said


def test_the_volume_finding_steps_aside_and_gives_way_to_the_candidate_that_beats_the_free_base(monkeypatch):
    seen, rnd, carried, said = _round(monkeypatch, "line_dynamics")
    # the round runs from the restrained base, against the free base, with air not excluded
    assert seen == {"stage": "restrained base", "accepted": ["external_leakage"], "floor": "free base"}
    assert rnd.accepted["effect"] == "line_dynamics"
    assert [a["effect"] for a in carried] == ["external_leakage"]
    assert any("grown volumes are explained by line_dynamics" in m for m in said)


def test_the_volume_finding_stays_when_nothing_beats_the_free_base(monkeypatch):
    seen, rnd, carried, said = _round(monkeypatch, None)
    assert rnd.accepted is None
    assert [a["effect"] for a in carried] == ["external_leakage", "entrained_air"]


def _rows(air, line):
    return [{"effect": "entrained_air", "component": "vane", "fitted": True, "delta_bic": air},
            {"effect": "line_dynamics", "component": "valve", "fitted": True, "delta_bic": line},
            {"effect": "line_dynamics", "component": "valve", "fitted": False, "delta_bic": None}]


def test_grown_volumes_are_named_a_hose_when_only_the_hose_beats_them_on_the_training_data():
    """Held-out data at the noise cannot tell air from a hose; the training data can: from the
    drawn volumes the hose fits better than the grown volumes and air does not."""
    f = engine._labelled(_excess(), _rows(air=835.0, line=-1621.0))
    assert f["effect"] == "line_dynamics" and f["alternatives"] == ["entrained_air"]
    assert f["finding"] == findings.EXCESS_FINDING and "ΔBIC -1621" in f["description"]
    assert engine._finding_key(f) == (findings.EXCESS_FINDING, "vane")      # re-judged as what it is


def test_grown_volumes_stay_air_unless_the_training_data_decide_against_it():
    for air, line in ((-500.0, -1500.0), (835.0, 20.0), (-10.0, 400.0)):
        assert engine._labelled(_excess(), _rows(air, line))["effect"] == "entrained_air"
    unfitted = [r for r in _rows(835.0, -1621.0) if r["effect"] != "entrained_air"]
    assert engine._labelled(_excess(), unfitted)["effect"] == "entrained_air"
