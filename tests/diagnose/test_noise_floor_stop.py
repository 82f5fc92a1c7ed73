"""A further round is not run when no effect could pass rule 2 from the current model
(accept.within_reach): no model predicts held-out data better than their noise, and a second
effect must gain at least the whole noise floor."""
from types import SimpleNamespace

import numpy as np
import pytest

from hydrocli.diagnose import accept, engine
from hydrocli.diagnose.stage import Settings


def test_noise_esr_is_what_a_perfect_model_leaves():
    """The floor the rule leans on: the second-difference estimate of white noise on a smooth
    signal equals the ESR of the noise-free signal against the noisy one (within 3 %)."""
    from hydrocli.diagnose import stats
    rng = np.random.default_rng(3)
    t = np.arange(0, 30, 1e-3)
    s = 1e5 * np.sin(2 * np.pi * 0.4 * t) + 3e4 * np.sin(2 * np.pi * 1.3 * t)
    y = s + 2e3 * rng.normal(size=t.size)
    esr_perfect = 100 * np.sum((y - s) ** 2) / np.sum((y - y.mean()) ** 2)
    assert stats.noise_esr(y) == pytest.approx(esr_perfect, rel=0.03)


@pytest.mark.parametrize("later,first_gain", [(False, None), (True, 0.1), (True, 7.3)])
def test_not_within_reach_means_no_candidate_could_pass(later, first_gain):
    """The stop decides exactly what rule 2 would: whenever an effect is out of reach, every
    validation ESR at or above FLOOR_SHARE of the floor fails rule 2 (presence); whenever it
    is within reach, some such ESR passes."""
    noise = 0.37
    for val0 in np.linspace(0.3, 6.0, 200):
        reach = accept.within_reach(val0, noise, later, first_gain)
        best = accept.FLOOR_SHARE * noise
        _, _, _, reasons = accept.presence(1.0, 0.5, 2, 1e4, val0, best, noise, later=later,
                                           first_gain=first_gain)
        passes = not any("validation" in r for r in reasons)
        assert passes == reach, (val0, reach, reasons)


def test_dev_numbers():
    """Dev EHA rod–load link (seed 31): after the compliance the summed validation ESR is
    0.398 % against a floor of 0.373 % (first gain 7.3 %): nothing more can pass. A model at
    three times the floor is still worth a round. Dev EHA null (seed 33): the base fit at
    0.577 % against 0.573 %: no first effect can gain a quarter of the floor; the counterbalanced
    lift's null (seed 30) at 0.139 % against 0.056 % is screened."""
    assert not accept.within_reach(0.398, 0.373, True, 7.3)
    assert not accept.within_reach(0.398, 0.373, True, 0.05)
    assert accept.within_reach(1.2, 0.373, True, 0.5)
    assert not accept.within_reach(1.2, 0.373, True, 4.0)   # a later effect must matter next to the first
    assert not accept.within_reach(0.577, 0.573)
    assert accept.within_reach(0.139, 0.056)
    assert accept.within_reach(0.62, 0.573)    # 8 % above the floor: a first effect may still pass


READINGS = frozenset({"entrained_air", "line_dynamics"})   # a grown chamber volume's readings


def _setup_stage(val, noise):
    su = SimpleNamespace(train=[], validate=[], outputs=["P1"], noise_total=noise)
    stage = SimpleNamespace(esr_validation={"P1": val})
    return su, stage


def _accepted(before, after):
    return [{"source": "candidate", "effect": "load_compliance", "component": "cylinder",
             "esr_validation_before": {"P1": before}, "esr_validation_after": {"P1": after}}]


@pytest.fixture
def no_candidates(monkeypatch):
    """An empty catalogue with one effect the machine cannot carry: round_step returns right
    after its stop check, screening nothing."""
    skipped = [SimpleNamespace(effect="end_stop", reason="no stop parameter")]
    monkeypatch.setattr(engine, "catalogue", lambda *a, **k: ([], skipped))
    monkeypatch.setattr(engine, "context", lambda *a, **k: None)


def test_round_step_stops_at_the_floor(no_candidates):
    su, stage = _setup_stage(0.398, 0.373)
    rnd = engine.round_step(su, stage, _accepted(7.7, 0.398), 1, Settings(), None, {})
    assert rnd.accepted is None and rnd.rows == []
    assert rnd.stopped == {"round": 2, "esr_validation": 0.398, "noise_floor": 0.373,
                           "noise_band": pytest.approx(0.25 * (7.7 - 0.398))}
    assert rnd.skipped == [{"effect": "end_stop", "reason": "no stop parameter"}]
    su, stage = _setup_stage(0.577, 0.573)         # round 1 of a null at the floor
    rnd = engine.round_step(su, stage, [], 0, Settings(), None, {})
    assert rnd.stopped["round"] == 1 and rnd.stopped["noise_band"] == pytest.approx(0.25 * 0.573)
    # the null study's setting (tests/benchmarks/acceptance_study.py): round 1 is screened anyway
    assert engine.round_step(su, stage, [], 0, Settings(screen_always=True), None, {}).stopped is None


def test_round_step_goes_on_when_an_effect_could_still_pass(no_candidates):
    """Far above the floor, the round goes on (here to its empty catalogue)."""
    su, stage = _setup_stage(2.0, 0.373)
    assert engine.round_step(su, stage, _accepted(4.0, 2.0), 1, Settings(), None, {}).stopped is None
    su, stage = _setup_stage(0.8, 0.573)
    assert engine.round_step(su, stage, [], 0, Settings(), None, {}).stopped is None


def test_a_restrained_base_at_the_floor_is_not_screened_unless_a_grown_volume_is_to_be_named(no_candidates):
    """From a restrained base (a floor model given) the stop reads the RESTRAINED base's held-out
    error: its candidates' gains are measured from it, so at the floor none can pass (dev lift_cbv
    nulls, seeds 149–151: every base fit put line_A_oil.V at its bound, and the restrained
    round, then the free round, took 320–360 s to fit nothing). Above the floor it runs; with a
    grown volume's readings to fit it runs at the floor too."""
    su, at_floor = _setup_stage(0.577, 0.573)
    _, above = _setup_stage(0.8, 0.573)
    assert engine.round_step(su, at_floor, [], 0, Settings(), None, {}, floor=above).stopped is not None
    assert engine.round_step(su, above, [], 0, Settings(), None, {}, floor=at_floor).stopped is None
    assert engine.round_step(su, at_floor, [], 0, Settings(), None, {}, floor=above,
                             readings=READINGS).stopped is None


def test_a_round_that_must_name_a_grown_volume_is_fitted_at_the_floor(no_candidates):
    """A one-sided grown chamber volume (a hose the file leaves out, put into V_A0 by the base
    fit, which then predicts to the noise) is named by the round's fits of its readings (air,
    a hose: base_findings.labelled): that round runs even though no effect can pass."""
    su, stage = _setup_stage(0.577, 0.573)
    assert engine.round_step(su, stage, [], 0, Settings(), None, {}, readings=READINGS).stopped is None
    assert engine.round_step(su, stage, [], 0, Settings(), None, {}, readings=frozenset()).stopped is not None


def test_volume_readings_ask_the_late_rule_on_the_round_s_model(monkeypatch):
    from hydrocli.diagnose import base_findings, findings
    vols = ("cylinder.V_A0", "cylinder.V_B0")

    def late_rule(su, stage, judged, late=False):
        assert late
        return findings.undrawn_volume(judged, [findings.Chambers("cylinder", vols)], lambda v: (1.0, 0.1))
    monkeypatch.setattr(base_findings, "base_fit_findings", late_rule)

    def judged(values):
        return [{"name": n, "value": v, "initial": v0, "stderr": 1e-6} for n, v, v0 in zip(vols, values, (2e-4, 6e-4))]
    base = SimpleNamespace(p=None)
    # the round fits both readings of the one-sided volume whatever they screen (a hose on that
    # line, air trapped in that chamber): the finding is named by their fits, not by default
    grown = SimpleNamespace(judged=judged((6.1e-4, 6.6e-4)), stage=base)
    assert base_findings.volume_readings(None, grown, base) == {"line_dynamics", "entrained_air"}
    assert base_findings.volume_readings(None, SimpleNamespace(judged=judged((2.1e-4, 6.1e-4)), stage=base),
                                         base) == frozenset()
