"""Which effect is named first: ranking.by_importance."""


def test_the_effect_worth_most_to_the_final_model_leads():
    """by_importance: a later effect that gains more than the earlier one's removal costs (its
    backward-elimination test) leads the named effects; without that measurement the steps'
    own gains order them; base-fit findings keep their place."""
    from hydrocli.diagnose.ranking import by_importance

    def step(effect, before, after, **kw):
        return {"effect": effect, "source": "candidate", "esr_validation_before": {"P1": before},
                "esr_validation_after": {"P1": after}, **kw}
    finding = {"effect": "external_leakage", "source": "base_fit"}
    mount = step("structural_flexibility", 0.58, 0.55, removal_gain=0.06)
    seal = step("pressure_dependent_friction", 0.55, 0.06)
    assert by_importance([finding, mount, seal]) == ["external_leakage", "pressure_dependent_friction",
                                                     "structural_flexibility"]
    # the first effect still worth more than the later one beside it keeps the lead
    assert by_importance([dict(mount, removal_gain=0.6), seal])[0] == "structural_flexibility"
    # a mop-up after a large first effect: the steps' gains keep the order
    air, lag = step("entrained_air", 2.0, 0.7), step("sensor_lag", 0.7, 0.6)
    assert by_importance([air, lag]) == ["entrained_air", "sensor_lag"]
