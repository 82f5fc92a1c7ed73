"""The console summary says what was added, how much it helped, and which other effect the
data could barely tell apart from it."""
from types import SimpleNamespace

from hydrocli.diagnose.summary import console_summary


def _diag(alternatives):
    acc = {"effect": "input_delay", "component": "valve", "delta_bic": -1457.0,
           "parameters": [{"name": "u_delay.T", "value": 0.0096, "stderr": 0.0002}],
           "esr_validation_before": {"P1": 9.15, "v": 1.49}, "esr_validation_after": {"P1": 2.88, "v": 0.64},
           "alternatives": alternatives}
    data = {"located": {"outputs": {}, "regimes": []}, "base_parameters": [], "accepted": [acc],
            "verdict": "missing_physics", "effects": ["input_delay"], "runtime_s": 60.0, "ranking": []}
    return SimpleNamespace(data=data)


def test_summary_names_the_effect_its_gain_and_a_close_alternative():
    text = console_summary(_diag([{"effect": "valve_hysteresis", "component": "valve", "delta_bic": -1386.0,
                                   "esr_validation_after": {}}]))
    assert "Input delay on 'valve' was missing" in text and "from 9.15 % to 2.88 %" in text
    assert "Nearly as good: valve hysteresis on 'valve' (ΔBIC -1386)" in text
    assert "Nearly as good" not in console_summary(_diag([]))


def test_summary_says_when_an_effects_size_is_poorly_determined():
    d = _diag([])
    d.data["accepted"][0]["size_poorly_determined"] = ["u_delay.T poorly determined (±56 % of its effect)"]
    text = console_summary(d)
    assert "Its size is poorly determined (u_delay.T poorly determined (±56 % of its effect))" in text
    assert "poorly determined" not in console_summary(_diag([]))


def test_summary_says_when_an_effect_fits_best_at_the_end_of_its_range():
    d = _diag([])
    d.data["accepted"][0]["ended_at_bound"] = ["valve_line_B.l ended at a bound (20)"]
    text = console_summary(d)
    assert "a value at the end of its plausible range (valve_line_B.l ended at a bound (20))" in text
    assert "end of its plausible range" not in console_summary(_diag([]))


def test_summary_says_when_an_effect_is_named_below_its_naming_floor():
    d = _diag([])
    d.data["accepted"][0]["below_naming_floor"] = ["no new parameter in its plausible range (valve.g_PB = 0.931)"]
    text = console_summary(d)
    assert "below what is usually worth naming (no new parameter in its plausible range (valve.g_PB = 0.931))" in text
    assert "worth naming" not in console_summary(_diag([]))


def test_summary_says_which_earlier_effect_a_later_one_made_redundant():
    d = _diag([])
    d.data["withdrawn"] = [{"effect": "structural_flexibility", "component": "vane", "delta_bic": 10478.0,
                            "why": "not needed beside input_delay on 'valve': BIC does not improve (ΔBIC = +10478)"}]
    text = console_summary(d)
    assert ("Structural flexibility on 'vane', accepted in an earlier round, was withdrawn: not needed beside "
            "input_delay on 'valve'") in text
    assert "withdrawn" not in console_summary(_diag([]))


def test_summary_says_what_grown_volumes_are_and_what_else_they_could_be():
    from hydrocli.diagnose import base_findings
    found = {"effect": "entrained_air", "component": "vane", "source": "base_fit", "finding": "fluid_compliance_excess",
             "parameters": [{"name": "vane.V_1", "value": 1.3e-4, "stderr": 2e-6, "file_value": 6e-5}],
             "validation_gain": 1.99, "noise_band": 0.3, "alternatives": ["line_dynamics"],
             "description": "the base fit needs more fluid compliance in every chamber of 'vane'"}
    rows = [{"effect": "entrained_air", "fitted": True, "delta_bic": 835.0},
            {"effect": "line_dynamics", "fitted": True, "delta_bic": -1621.0}]
    d = _diag([])
    d.data["accepted"] = [base_findings.labelled(found, rows)]
    text = console_summary(d)
    assert "Line dynamics on 'vane' is present: the base fit found it (vane.V_1 = 0.00013" in text
    assert "named line_dynamics: from the drawn volumes line_dynamics fits the training data better" in text
    assert "It could also be entrained air (the held-out data do not tell them apart)." in text


def test_summary_and_report_say_when_nothing_was_screened_at_the_noise_floor():
    d = _diag([])
    d.data.update(accepted=[], verdict="none", effects=["none"], skipped=[],
                  stopped_at_noise_floor={"round": 1, "esr_validation": 0.189, "noise_floor": 0.184,
                                          "noise_band": 0.046})
    text = console_summary(d)
    assert ("the base model predicts the held-out data to the noise (validation ESR 0.189 % against a noise floor "
            "of 0.184 %), so no effect could gain the 0.046 % it must; no candidate was screened") in text
    from hydrocli.report import diagnosis
    fig = diagnosis._ranking(d)
    shown = "\n".join(t.get_text() for ax in fig.axes for t in ax.texts)
    assert "Round 1 not screened: validation ESR 0.189 % against a noise floor of 0.184 %" in shown
    del d.data["stopped_at_noise_floor"]
    assert "not screened" not in console_summary(d)
    assert "not screened" not in "\n".join(t.get_text() for ax in diagnosis._ranking(d).axes for t in ax.texts)


def test_summary_says_when_the_held_out_data_overruled_the_training_bic():
    d = _diag([])
    d.data["accepted"][0]["held_out_over"] = {"effect": "structural_flexibility", "component": "cylinder",
                                              "delta_bic": -8719.0, "noise_band": 0.175,
                                              "esr_validation_after": {"P1": 0.25, "v": 0.433}}
    text = console_summary(d)
    assert ("Structural flexibility on 'cylinder' fits the training data better (ΔBIC -8719) but predicts the "
            "held-out data worse (summed validation ESR 0.683 %, noise band 0.175 %): the held-out data decide.") in text
    assert "held-out data decide" not in console_summary(_diag([]))


def test_summary_says_when_an_effect_passed_on_a_gain_specific_to_it():
    """An effect accepted below the look-elsewhere margin because no other effect came near its
    held-out gain (accept.specific_need) says so, with the figures it was judged on."""
    d = _diag([])
    d.data["accepted"][0]["specific_gain"] = {"gain": 0.111, "other": 0.0, "band": 0.0291}
    text = console_summary(d)
    assert ("Its held-out gain (0.111 %) is smaller than the look-elsewhere margin but specific to it: no other "
            "effect fitted gained more than 0 % (band 0.0291 %).") in text
    assert "specific to it" not in console_summary(_diag([]))


def test_summary_says_which_sensor_separates_two_springs_no_input_can():
    """Two compliances of the mechanics (a payload's rope, a compliant mount) with free masses
    are one two-mass system to the actuator's own transducers: when no designed test separates
    them, the summary says a sensor on the far side of the spring would, not "other operating
    points"; any other undecidable pair keeps the operating-point advice."""
    prop = {"z": {"P1": 0.4}, "discrimination": 3.0, "decisive": False, "description": "a slow sine",
            "file": "proposed_experiment_1.yaml", "esr_gap": 0.01, "band": 0.17}
    for two_mass, says, not_says in ((True, "an accelerometer or position on the load", "other operating points"),
                                     (False, "other operating points", "accelerometer")):
        d = _diag([])
        d.data["ambiguous"] = [{"effects": ["payload_swing", "structural_flexibility"], "delta_bic": [-900.0, -880.0],
                                "proposed_experiment": prop, "two_mass": two_mass}]
        text = console_summary(d)
        assert "No designed test separates them" in text and says in text and not_says not in text
