"""Backward elimination (backward.backward): once a second effect is in, the first must still
pass the presence test against the model with the second only; the greedy first round's
stand-in is withdrawn when it no longer does."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hydrocli.diagnose import accept, backward, engine

N_EFF = 2000.0
NOISE = {"P1": 0.1, "v": 0.1}


def _stage(cost, val):
    """A stage whose summed validation ESR is ``val`` (%)."""
    return SimpleNamespace(cost=cost, esr_validation={"P1": val / 2, "v": val / 2},
                           esr_train={"P1": val / 2, "v": val / 2}, model=None, Y_train=None)


def _acc(effect, component, before, after):
    return {"key": f"{effect}@{component}", "effect": effect, "component": component, "source": "candidate",
            "esr_train_before": {"P1": before}, "esr_validation_before": {"P1": before},
            "esr_train_after": {"P1": after}, "esr_validation_after": {"P1": after}}


def _run(monkeypatch, without_cost, without_val, full=(1.00, 0.40), effects=(("structural_flexibility", "mount"),
                                                                          ("input_delay", "valve"))):
    """Two accepted effects, the first with two parameters; ``_without`` re-fits to the given
    cost and validation ESR."""
    calls = []

    def fake_without(su, base_net, stage, keep, st, progress, what):
        calls.append([c.key for c in keep])
        return _stage(without_cost, without_val)

    monkeypatch.setattr(backward, "without", fake_without)
    monkeypatch.setattr(engine.residuals, "effective_n", lambda *a, **k: N_EFF)
    su = SimpleNamespace(noise_total=sum(NOISE.values()), train=None, outputs=None)
    b = SimpleNamespace(stage=SimpleNamespace(net=None))
    first = _acc(*effects[0], before=4.0, after=2.0)
    second = _acc(*effects[1], before=2.0, after=full[1])
    base_found = {"effect": "external_leakage", "component": "cylinder", "source": "base_fit"}
    built = {first["key"]: SimpleNamespace(key=first["key"], params=[1, 2]),
             second["key"]: SimpleNamespace(key=second["key"], params=[1])}
    stage, accepted, gone = backward.backward(su, b, _stage(*full), [base_found, first, second], built,
                                             engine.Settings(), None)
    return stage, accepted, gone, calls, first, second, base_found


def test_an_earlier_effect_the_later_one_makes_redundant_is_withdrawn(monkeypatch):
    # without the mount the delay alone fits as well (SSR +0.1 %: ΔBIC = 2000·ln(1/1.001) + 2·ln 2000 > 0)
    # and predicts as well (0.41 against 0.40 %)
    stage, accepted, gone, calls, first, second, found = _run(monkeypatch, 1.001, 0.41)
    assert calls == [[second["key"]]]                     # re-fitted with the delay only
    assert [a["effect"] for a in accepted] == ["external_leakage", "input_delay"]   # base-fit finding kept
    assert [g["effect"] for g in gone] == ["structural_flexibility"] and gone[0]["delta_bic"] > 0
    assert stage.cost == 1.001                            # the model without it is carried on
    # the delay now starts where the mount did and ends at the refitted model
    assert second["esr_validation_before"] == {"P1": 4.0}
    assert second["esr_validation_after"] == stage.esr_validation


def test_an_earlier_effect_still_needed_is_kept(monkeypatch):
    # without the mount: SSR ×1.5 and the held-out error 0.40 → 1.6 % (gain 1.2 % > band)
    stage, accepted, gone, *_ = _run(monkeypatch, 1.5, 1.6)
    assert gone == [] and stage.cost == 1.00
    assert [a["effect"] for a in accepted] == ["external_leakage", "structural_flexibility", "input_delay"]


def test_a_better_fit_that_does_not_predict_better_is_withdrawn(monkeypatch):
    # ΔBIC strongly negative, but the held-out gain (0.05 %) is inside a later effect's band (the whole floor)
    *_, gone, _, _, _, _ = _run(monkeypatch, 1.5, 0.45)
    assert gone and "noise band" in gone[0]["why"]


def test_two_forms_of_one_effect_on_one_component_are_not_split(monkeypatch):
    stage, accepted, gone, calls, *_ = _run(monkeypatch, 1.001, 0.41,
                                            effects=(("internal_leakage", "cylinder"), ("internal_leakage", "cylinder")))
    assert calls == [] and gone == [] and len(accepted) == 3


def test_the_presence_test_is_the_one_a_candidate_passes():
    """accept.presence is rules 1–2 of accept.judge: ΔBIC from the SSR ratio, the held-out gain
    against need()."""
    dbic, gain, band, reasons = accept.presence(1.0, 0.9, 1, N_EFF, 2.0, 1.0, 0.2)
    assert dbic == pytest.approx(N_EFF * np.log(0.9) + np.log(N_EFF))
    assert gain == pytest.approx(1.0) and band == pytest.approx(accept.need(2.0, 0.2)) and reasons == []
    assert accept.presence(1.0, 0.9999, 1, N_EFF, 2.0, 1.0, 0.2)[3]          # BIC does not improve
    assert accept.presence(1.0, 0.9, 1, N_EFF, 2.0, 1.99, 0.2)[3]            # no held-out gain


def test_an_effect_without_which_the_model_cannot_simulate_is_kept(monkeypatch):
    """The fit without the earlier effect leaves the model's valid range (a stroke overrun):
    ``without`` answers None (kept) instead of letting the error end the diagnosis."""
    from hydrocli.errors import IdentifyError, Problem

    def overrun(*a, **k):
        raise IdentifyError(Problem("every trial simulation failed (3)"))

    monkeypatch.setattr(backward, "build_model", lambda net: SimpleNamespace(param_names=[], free_params=[]))
    monkeypatch.setattr(backward.augment, "reload", lambda net, text: net)
    monkeypatch.setattr(backward.augment, "text_of", lambda net: "")
    monkeypatch.setattr(backward.workers, "warm_vector", lambda *a: np.zeros(0))
    monkeypatch.setattr(backward.baseline, "identify", overrun)
    said = []
    keep = [SimpleNamespace(build=lambda net: net)]
    stage = SimpleNamespace(model=SimpleNamespace(param_names=[]), p=np.zeros(0))
    assert backward.without(SimpleNamespace(train=[]), "net", stage, keep, engine.Settings(), said.append,
                            "a mount beside a delay") is None
    assert any("cannot simulate" in s for s in said)


def test_a_later_effect_hung_on_the_earlier_ones_frame_is_offered_again_without_it(tmp_path, monkeypatch):
    """A rod seal offered after a compliant mount acts between the rod and the mount's frame;
    the luffing cylinder without the mount has no such node, so that candidate cannot be built
    there and the mount could never be tested. ``without`` adds the candidate the catalogue
    offers under the same key on the machine without the mount: the seal then acts between the
    rod and the cylinder's own reference, with the same parameter names (the fit starts from
    their fitted values)."""
    from pathlib import Path

    from hydrocli.diagnose import augment
    from hydrocli.diagnose.candidates import Context, catalogue
    from hydrocli.diagnose.measurement import with_pressure_sensors
    from hydrocli.errors import HydroError
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist

    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path))
    outs = {"P1": "pressure", "P2": "pressure", "x": "position", "v": "velocity"}

    def ctx_of(net):
        return Context(net, set(build_model(net).free_params), {"rod": (0.0, 0.3)}, outs)

    def offered(net):
        return {c.key: c for c in catalogue(ctx_of(net))[0]}

    base, _ = with_pressure_sensors(load_netlist(Path(__file__).parents[2] / "machines" / "luffing_cylinder.yaml"))
    mount = offered(base)["structural_flexibility@cylinder"]
    mounted = augment.reload(base, augment.text_of(mount.build(base)))
    seal = offered(mounted)["pressure_dependent_friction@friction#rod"]
    (name,) = {p.name.rpartition(".")[0] for p in seal.params}
    frame = augment.reload(mounted, augment.text_of(seal.build(mounted))).components[name].ports["b"]
    assert frame not in base.nodes()                  # the mount's frame: gone with the mount
    with pytest.raises(HydroError):                   # the stale build does not stand on the base
        build_model(augment.reload(base, augment.text_of(seal.build(base))))
    monkeypatch.setattr(backward, "context_of", lambda su, net, free, model: ctx_of(net))
    net = backward._built_on(None, base, seal)
    model = build_model(net)
    assert {p.name for p in seal.params} <= set(model.free_params)
    assert net.components[name].ports["b"] in base.nodes()
    assert net.components[name].ports["a"] == "rod"
