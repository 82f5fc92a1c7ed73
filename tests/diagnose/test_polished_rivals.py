"""Two candidates whose quick fits the data do not tell apart are both polished and judged
again (engine._decide_polished): the choice rests on fits at their minimum, not on where a
15-iteration budget stopped each."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from hydrocli.diagnose import engine, stats

N_EFF = 5000.0
SSR0 = 1.0


def _cand(effect, k):
    return SimpleNamespace(key=f"{effect}@x", effect=effect, params=[0] * k)


def _quick(cost, val):
    return {"cost": cost, "esr_validation": {"P1": val}}


def _decide(monkeypatch, polished_costs, polished_vals, band=0.2):
    link, hose = _cand("load_compliance", 2), _cand("line_dynamics", 6)
    calls = []

    def fake_polish(su, stage, c, text, f, n_eff, st, progress):
        calls.append(c.effect)
        new = SimpleNamespace(esr_validation={"P1": polished_vals[c.effect]}, p=np.zeros(1),
                              model=SimpleNamespace(param_names=["a"]))
        return new, dict(f, cost=polished_costs[c.effect])

    monkeypatch.setattr(engine, "_polish", fake_polish)
    # quick fits: the link slightly ahead on the held-out data, alike on BIC
    win = (stats.delta_bic(SSR0, 0.55, N_EFF, 2), link, _quick(0.55, 0.46))
    rival = (stats.delta_bic(SSR0, 0.54, N_EFF, 6), hose, _quick(0.54, 0.58))
    return engine._decide_polished(None, None, win, rival, {link.key: "", hose.key: ""}, N_EFF, {link.key: SSR0, hose.key: SSR0},
                                   band, engine.Settings(), None), calls


def test_the_polished_fits_decide_when_one_pulls_clear(monkeypatch):
    # polished, the hose halves the link's remaining SSR: no longer close on BIC → the hose, no rival
    (first, rival, polished), calls = _decide(monkeypatch, {"load_compliance": 0.55, "line_dynamics": 0.2},
                                              {"load_compliance": 0.46, "line_dynamics": 0.30})
    assert sorted(calls) == ["line_dynamics", "load_compliance"]
    assert first[1].effect == "line_dynamics" and rival is None
    assert first[0] == pytest.approx(stats.delta_bic(SSR0, 0.2, N_EFF, 6))
    assert set(polished) == {"load_compliance@x", "line_dynamics@x"}
    assert first[2]["esr_validation"] == {"P1": 0.30}          # judged on the polished model's prediction


def test_still_alike_after_polishing_stays_ambiguous(monkeypatch):
    (first, rival, _), _ = _decide(monkeypatch, {"load_compliance": 0.55, "line_dynamics": 0.53},
                                   {"load_compliance": 0.46, "line_dynamics": 0.50})
    # close on BIC: the held-out data rank them (the link predicts better), and they are not separated
    assert first[1].effect == "load_compliance" and rival is not None and rival[1].effect == "line_dynamics"


def test_separated_on_held_out_data_after_polishing_is_not_ambiguous(monkeypatch):
    (first, rival, _), _ = _decide(monkeypatch, {"load_compliance": 0.55, "line_dynamics": 0.53},
                                   {"load_compliance": 0.46, "line_dynamics": 0.90})
    assert first[1].effect == "load_compliance" and rival is None


def test_still_alike_after_polishing_the_special_case_is_named(monkeypatch):
    """A seal friction μ·A·(p_A + p_B) at a constant supply is a Coulomb force with one
    dependence more (ranking.simplest): polished and still not told apart, the special case
    is named and the richer law stays the rival (the project's concealed Coulomb case)."""
    seal, coulomb = _cand("pressure_dependent_friction", 2), _cand("coulomb_friction", 2)

    def fake_polish(su, stage, c, text, f, n_eff, st, progress):
        new = SimpleNamespace(esr_validation={"P1": {"pressure_dependent_friction": 1.40,
                                                     "coulomb_friction": 1.41}[c.effect]},
                              p=np.zeros(1), model=SimpleNamespace(param_names=["a"]))
        return new, dict(f, cost={"pressure_dependent_friction": 0.500, "coulomb_friction": 0.501}[c.effect])

    monkeypatch.setattr(engine, "_polish", fake_polish)
    win = (stats.delta_bic(SSR0, 0.5, N_EFF, 2), seal, _quick(0.5, 1.40))
    rival = (stats.delta_bic(SSR0, 0.501, N_EFF, 2), coulomb, _quick(0.501, 1.41))
    first, second, _ = engine._decide_polished(None, None, win, rival, {seal.key: "", coulomb.key: ""}, N_EFF,
                                               {seal.key: SSR0, coulomb.key: SSR0}, 0.2, engine.Settings(), None)
    assert first[1].effect == "coulomb_friction" and second[1].effect == "pressure_dependent_friction"


def test_a_polish_that_cannot_simulate_keeps_the_candidates_own_fit(monkeypatch):
    """Dev lift_cbv sharp overlap (seed 47): with all 25 parameters free the polish's first
    simulations overran the stroke and its IdentifyError ended the diagnosis after the overlap
    had been fitted. The polish is a refinement: the candidate's own fit now stands."""
    from hydrocli.errors import IdentifyError, Problem

    def overrun(*a, **k):
        raise IdentifyError(Problem("every trial simulation failed (2)"))

    made = {}
    monkeypatch.setattr(engine.augment, "reload", lambda net, text: "aug")
    monkeypatch.setattr(engine.augment, "set_values", lambda net, values: (net, values))
    model = SimpleNamespace(free_params=["a", "b"], param_index=["a", "b"].index)
    monkeypatch.setattr(engine, "build_model", lambda net: model)
    monkeypatch.setattr(engine.workers, "warm_vector", lambda model, names, p: np.asarray(p, float))
    monkeypatch.setattr(engine.baseline, "identify", overrun)
    monkeypatch.setattr(engine, "make_stage", lambda net, model, p, cost, *a: made.update(p=p, cost=cost, net=net))
    said = []
    f = {"p": [1.0, 2.0], "param_names": ["a", "b"], "cost": 0.3, "names": ["a"], "stderr": [0.1],
         "esr_validation": {"P1": 0.5}}
    su = SimpleNamespace(train=[], validate=[], outputs=["P1"])
    _, f_out = engine._polish(su, SimpleNamespace(net=None), _cand("valve_overlap", 4), "", f, N_EFF,
                              engine.Settings(), said.append)
    assert f_out is f and made["cost"] == 0.3 and list(made["p"]) == [1.0, 2.0]
    assert made["net"][1] == {"a": 1.0, "b": 2.0}
    assert any("cannot simulate" in s and "every trial simulation failed" in s for s in said)
