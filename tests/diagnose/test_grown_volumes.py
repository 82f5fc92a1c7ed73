"""Grown chamber volumes (the base fit's fluid-compliance finding) are restrained to the
drawing's tolerance and tested like any implausible value: the catalogue's candidates that
could be that compliance (air, a hose) compete from the restrained base, and the finding gives
way to the one that beats the free base."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from hydrocli.diagnose import base_findings, engine, findings, restrain, restrained

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
    assert lim == {"vane.V_1": (1e-6, restrain.DRAWN * 6e-5), "vane.V_2": (1e-6, restrain.DRAWN * 6e-5)}
    # a drawing's tolerance, well inside the growth the finding needs
    assert 1.0 < restrain.DRAWN < findings.EXCESS
    # a parameter finding (a leak moved from 0) or a one-sided volume is not restrained here
    leak = {"effect": "external_leakage", "source": "base_fit", "parameters": [{"name": "vane.V_1", "file_value": 6e-5}]}
    one_side = dict(_excess(), finding="undrawn_volume")
    assert restrain.grown_volumes([leak, one_side], BOUNDS) == {}


def _round(monkeypatch, accepted_effect):
    seen = {}

    def fake_round(su, stage, accepted, round_, st, pool, located, progress=None, floor=None, withdrawn=frozenset(),
                   readings=frozenset()):
        seen.update(stage=stage, accepted=[a["effect"] for a in accepted], floor=floor, readings=readings)
        acc = None if accepted_effect is None else {"effect": accepted_effect, "component": "valve"}
        return engine.Round([], accepted=acc, stage="restrained fit")
    monkeypatch.setattr(engine, "round_step", fake_round)
    monkeypatch.setattr(engine, "_bounds", lambda model, fit: (BOUNDS, set()))

    def fake_released(su, stage, bounds, st, progress, also_from=None):
        seen["released"], seen["also_from"] = bounds, also_from
        return SimpleNamespace(esr_train={"P1": 0.2}, esr_validation={"P1": 0.1})
    monkeypatch.setattr(restrained, "released", fake_released)
    leak = {"effect": "external_leakage", "component": "vane", "source": "base_fit"}
    b = SimpleNamespace(restrained="restrained base", located={}, stage=SimpleNamespace(model=None), fit=None,
                        grown=frozenset({"vane.V_1", "vane.V_2", "vane.beta"}))
    free = "free base"
    said = []
    rnd, carried = engine._restrained_round(None, b, free, [leak, _excess()], engine.Settings(), None, said.append)
    return seen, rnd, carried, said


def test_the_volume_finding_steps_aside_and_gives_way_to_the_candidate_that_beats_the_free_base(monkeypatch):
    seen, rnd, carried, said = _round(monkeypatch, "line_dynamics")
    # the round runs from the restrained base, against the free base, with air not excluded;
    # once named, the volumes get the file's bounds back and the model is re-identified
    released = seen.pop("released")
    assert seen.pop("also_from") == "free base"          # its grown volumes are a start too
    # both readings of the grown volumes are fitted, whatever they screen, and at the noise floor too
    # (round_step stops at the floor only without readings)
    assert seen.pop("readings") == {"entrained_air", "line_dynamics"}
    assert seen == {"stage": "restrained base", "accepted": ["external_leakage"], "floor": "free base"}
    # the volumes and their oil's modulus get the file's bounds back
    assert released == {n: BOUNDS[n] for n in ("vane.V_1", "vane.V_2", "vane.beta")}
    assert rnd.accepted["effect"] == "line_dynamics" and rnd.accepted["esr_validation_after"] == {"P1": 0.1}
    assert [a["effect"] for a in carried] == ["external_leakage"]
    assert any("grown volumes are explained by line_dynamics" in m for m in said)


def test_the_volume_finding_stays_when_nothing_beats_the_free_base(monkeypatch):
    seen, rnd, carried, said = _round(monkeypatch, None)
    assert rnd.accepted is None and "released" not in seen
    assert [a["effect"] for a in carried] == ["external_leakage", "entrained_air"]


def _rows(air, line):
    return [{"effect": "entrained_air", "component": "vane", "fitted": True, "delta_bic": air},
            {"effect": "line_dynamics", "component": "valve", "fitted": True, "delta_bic": line},
            {"effect": "line_dynamics", "component": "valve", "fitted": False, "delta_bic": None}]


def test_grown_volumes_are_named_a_hose_when_only_the_hose_beats_them_on_the_training_data():
    """Held-out data at the noise cannot tell air from a hose; the training data can: from the
    drawn volumes the hose fits better than the grown volumes and air does not."""
    f = base_findings.labelled(_excess(), _rows(air=835.0, line=-1621.0))
    assert f["effect"] == "line_dynamics" and f["alternatives"] == ["entrained_air"]
    assert f["finding"] == findings.EXCESS_FINDING and "ΔBIC -1621" in f["description"]
    assert base_findings.finding_key(f) == (findings.EXCESS_FINDING, "vane")      # re-judged as what it is


def test_grown_volumes_stay_air_unless_the_training_data_decide_against_it():
    on_top = _rows(-80.0, 30.0)       # (air improves on top: the drawn volumes' margin says nothing)
    for air, line in ((-500.0, -1500.0), (-10.0, 400.0), (835.0, 20.0)):
        assert base_findings.labelled(_excess(), _rows(air, line), on_top=on_top)["effect"] == "entrained_air"
    unfitted = [r for r in _rows(835.0, -1621.0) if r["effect"] != "entrained_air"]
    assert base_findings.labelled(_excess(), unfitted)["effect"] == "entrained_air"
    # both fitted, neither improves on the grown volumes: the name stays, the finding says why
    f = base_findings.labelled(_excess(), _rows(41.0, 42.0))
    assert f["effect"] == "entrained_air" and "do not tell them apart either" in f["description"]
    assert "entrained_air ΔBIC +41, line_dynamics +42" in f["description"]
    assert "tell them apart" not in base_findings.labelled(_excess(), _rows(-500.0, -1500.0))["description"]


def test_released_volumes_are_kept_only_when_they_fit_better_and_predict_no_worse(monkeypatch):
    """The restraint served the test; lifted, the re-fit is kept when it lowers the training
    cost without predicting the held-out data worse (as a polish)."""
    import numpy as np
    from pathlib import Path
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist
    net = load_netlist(Path(__file__).parents[2] / "machines" / "rotary_drive.yaml")
    model = build_model(net)
    stage = SimpleNamespace(net=net, model=model, p=np.array(model.param_vector({})), cost=1.0,
                            esr_validation={"P1": 1.0}, Y_train=None)
    name = next(n for n in model.param_names if n.endswith("V_1"))
    fitted = {}

    def fake_identify(m, train, p_start, iterations, progress, threads=1):
        fitted["free"] = name in m.free_params
        fitted.setdefault("starts", []).append(float(p_start[m.param_index(name)]))
        return SimpleNamespace(cost=fitted["cost"], names=[name], estimates=[2e-4], p=p_start)
    monkeypatch.setattr(engine.baseline, "identify", fake_identify)
    monkeypatch.setattr(engine.baseline, "inflated_stderr", lambda res, n: np.zeros(1))
    monkeypatch.setattr(engine.residuals, "effective_n", lambda *a: 1000.0)
    monkeypatch.setattr(restrained, "make_stage", lambda *a, **k: SimpleNamespace(esr_validation={"P1": fitted["val"]}))
    su = SimpleNamespace(train=None, validate=None, outputs=None)
    for cost, val, kept in ((0.5, 0.8, True), (0.5, 1.2, False), (1.5, 0.8, False)):
        fitted.update(cost=cost, val=val)
        out = restrained.released(su, stage, {name: (1e-6, 1e-3)}, engine.Settings(), None)
        assert fitted["free"] and (out is not stage) == kept
    assert restrained.released(su, stage, {}, engine.Settings(), None) is stage
    # from the free base too: its grown volume (within the file's bounds) is the second start
    grown = stage.p.copy()
    grown[model.param_index(name)] = 5e-4
    free = SimpleNamespace(model=model, p=grown, free=[name])
    fitted.update(cost=0.5, val=0.8, starts=[])
    restrained.released(su, stage, {name: (1e-6, 1e-3)}, engine.Settings(), None, also_from=free)
    assert fitted["starts"] == [pytest.approx(stage.p[model.param_index(name)]), pytest.approx(5e-4)]


def test_the_oil_behind_grown_volumes_may_not_soften_to_take_their_place():
    """Both halves of the chambers' compliance V/β are restrained: the volumes to the drawing's
    tolerance and the actuator's bulk modulus (role slot ``bulk_modulus``) to no softer than
    the free fit had it — else the restrained base puts the excess into β and leaves the
    candidates nothing to explain."""
    from hydrocli.components import roles as R
    from hydrocli.diagnose.candidates import Context
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist
    from pathlib import Path
    net = load_netlist(Path(__file__).parents[2] / "machines" / "rotary_drive.yaml")
    ctx = Context(net, set(build_model(net).free_params))
    vane = ctx.parts(R.ACTUATOR)[0]
    beta = vane.param("bulk_modulus")
    excess = dict(_excess(), component=vane.name)
    lim = restrain.grown_volumes([excess], {**BOUNDS, beta: (3e8, 2.5e9)}, ctx, {beta: 1.3e9})
    assert lim[beta] == (1.3e9, 2.5e9)
    # a free fit already at the upper bound leaves the modulus there, within a hair of it: an
    # interval the machine file accepts as bounds (a point stopped a diagnosis), not a point
    at_top = restrain.grown_volumes([excess], {**BOUNDS, beta: (3e8, 2.5e9)}, ctx, {beta: 2.5e9})
    assert at_top[beta] == (pytest.approx(2.5e9 * (1 - restrain.PINNED)), 2.5e9)
    held = restrain.apply(net, {beta: at_top[beta]}, {beta: 2.5e9})
    assert held.components[beta.split(".")[0]].params[beta.split(".")[1]].bounds == at_top[beta]
    assert beta not in restrain.grown_volumes([excess], {**BOUNDS, beta: (3e8, 2.5e9)}, ctx, {})
    # another actuator's finding leaves this one's oil alone
    assert beta not in restrain.grown_volumes([dict(excess, component="other")], {**BOUNDS, beta: (3e8, 2.5e9)},
                                              ctx, {beta: 1.3e9})


def test_when_the_drawn_volumes_do_not_decide_the_readings_on_top_of_the_grown_ones_do():
    """From the drawn volumes neither reading improves on the grown volumes (dev winch hose:
    air +2105, the line +49, its parameters' penalty); on top of the grown volumes the hose
    adds what a constant compliance lacks (its inertance and loss: −59) and air adds nothing
    (+37): the finding is the hose. The same rule the other way keeps air."""
    f = base_findings.labelled(_excess(), _rows(2105.0, 49.0), on_top=_rows(37.0, -59.0))
    assert f["effect"] == "line_dynamics" and f["alternatives"] == ["entrained_air"]
    assert "on top of the grown volume line_dynamics improves the training fit (ΔBIC -59)" in f["description"]
    assert base_findings.labelled(_excess(), _rows(2105.0, 49.0), on_top=_rows(-80.0, 30.0))["effect"] == "entrained_air"
    # the drawn volumes decide first: a hose that improves there is named whatever is on top
    f = base_findings.labelled(_excess(), _rows(835.0, -1621.0), on_top=_rows(-80.0, 30.0))
    assert f["effect"] == "line_dynamics" and "from the drawn volumes" in f["description"]
    # neither decides: the name stays and the description says so, once
    f = base_findings.labelled(_excess(), _rows(41.0, 42.0), on_top=_rows(37.0, 12.0))
    assert f["effect"] == "entrained_air" and f["description"].count("do not tell them apart") == 1


def test_when_no_reading_improves_anywhere_the_one_that_reproduces_the_grown_volumes_names_them():
    """Neither reading beats the grown volumes, from the drawn ones or on top of them: the
    grown volumes, a constant compliance, predict as well as anything. From the drawn volumes
    the reading that reproduces them decisively better (ΔBIC more than 10 lower) is what the
    excess is: a hose's volume is constant, air's compliance softens with falling pressure
    (dev winch distributed hose, seed 167: the line +311, air +491; on top air +32, the line
    +1321, neither improving)."""
    f = base_findings.labelled(_excess(), _rows(491.0, 311.0), on_top=_rows(32.0, 1321.0))
    assert f["effect"] == "line_dynamics" and f["alternatives"] == ["entrained_air"]
    assert "reproduces them decisively better (ΔBIC +311 against entrained_air +491)" in f["description"]
    assert "constant compliance" in f["description"]
    # the other way round: air stays, and says why
    f = base_findings.labelled(_excess(), _rows(311.0, 491.0), on_top=_rows(32.0, 1321.0))
    assert f["effect"] == "entrained_air" and "softens with falling pressure" in f["description"]
    # within the margin the name stays, and the finding says the data do not choose
    f = base_findings.labelled(_excess(), _rows(320.0, 311.0), on_top=_rows(32.0, 1321.0))
    assert f["effect"] == "entrained_air" and "do not tell them apart" in f["description"]
    # any improvement, on top or from the drawing, leaves the earlier rules to decide
    assert base_findings.labelled(_excess(), _rows(491.0, 311.0), on_top=_rows(-5.0, 1321.0))["effect"] == "entrained_air"
    assert base_findings.labelled(_excess(), _rows(-20.0, 311.0), on_top=_rows(32.0, 1321.0))["effect"] == "entrained_air"
    air_on_top = [r for r in _rows(-5.0, 0.0) if r["effect"] == "entrained_air"]      # the hose not fitted on top
    assert base_findings.labelled(_excess(), _rows(491.0, 311.0), on_top=air_on_top)["effect"] == "entrained_air"
    # a one-sided volume judged on top only: no drawn-volume comparison to make
    undrawn = {"effect": "line_dynamics", "component": "cylinder", "finding": "undrawn_volume",
               "alternatives": ["entrained_air"], "description": "d"}
    assert base_findings.labelled(undrawn, _rows(30.0, 491.0), basis=base_findings.ON_TOP)["effect"] == "line_dynamics"


def test_the_free_base_round_fits_the_readings_and_names_the_finding_from_both(monkeypatch):
    """In the diagnosis loop: the restrained round accepts nothing, the round from the free
    base fits the finding's readings whatever they screen, and the finding is named from both
    rounds' rows (engine._name_grown)."""
    calls = []
    monkeypatch.setattr(base_findings, "labelled", lambda a, drawn, progress=None, on_top=(): calls.append(
        (drawn, on_top)) or dict(a, effect="line_dynamics"))
    excess = _excess()
    out = engine._name_grown([{"effect": "sensor_lag"}, excess], ["drawn rows"], ["on-top rows"], None)
    assert [a["effect"] for a in out] == ["sensor_lag", "line_dynamics"] and calls == [(["drawn rows"], ["on-top rows"])]
    assert engine._readings([{"effect": "sensor_lag"}, excess]) == {"entrained_air", "line_dynamics"}


def test_on_top_of_a_one_sided_volume_the_decisively_stronger_reading_names_it():
    """On top of the grown volume each reading adds what a constant compliance lacks: when both
    improve, the one decisively stronger (ΔBIC more than 10 lower, Kass & Raftery's "very
    strong") names the finding (dev EHA pocket of air in chamber A, seed 136: air −1131, a hose
    −58, the default name a hose). Within the margin the default stands; from the drawn
    volumes only a reading that improves against one that does not renames."""
    undrawn = {"effect": "line_dynamics", "component": "cylinder", "finding": "undrawn_volume",
               "alternatives": ["entrained_air"], "description": "d"}
    on_top = base_findings.ON_TOP
    assert base_findings.labelled(undrawn, _rows(-1131.0, -58.0), basis=on_top)["effect"] == "entrained_air"
    assert base_findings.labelled(undrawn, _rows(-64.0, -58.0), basis=on_top)["effect"] == "line_dynamics"
    assert base_findings.labelled(undrawn, _rows(-58.0, -1131.0), basis=on_top)["effect"] == "line_dynamics"
    assert base_findings.labelled(undrawn, _rows(-1131.0, -58.0))["effect"] == "line_dynamics"   # from the drawing
    # given on top of the drawn rows' basis (the restrained round), the same rule decides there
    assert base_findings.labelled(undrawn, [], on_top=_rows(-1131.0, -58.0))["effect"] == "entrained_air"


def test_without_a_grown_volume_the_restrained_round_may_stop_at_the_floor(monkeypatch):
    """A restrained round with no volume finding to name (only a Stribeck value or a line volume
    restrained) has no readings to fit: round_step's noise-floor stop decides."""
    seen, _, _, _ = _round(monkeypatch, None)
    assert seen["readings"] == {"entrained_air", "line_dynamics"}
    b = SimpleNamespace(restrained="restrained base", stage=SimpleNamespace(model=None), fit=None, grown=frozenset(),
                        located={})
    engine._restrained_round(None, b, "free base", [{"effect": "external_leakage", "component": "vane",
                                                      "source": "base_fit"}], engine.Settings(), None, lambda m: None)
    assert seen["readings"] == frozenset()
