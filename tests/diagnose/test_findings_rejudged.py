"""A base-fit finding is a reading of the base fit's parameter values; once a candidate is
accepted those values may go back to the file's (they stood in for it), and the finding must be
judged again on the final model by the same rules."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hydrocli.components.hydraulic.fluid import effective_bulk_modulus
from hydrocli.diagnose import base_findings, engine, findings, stage as stage_of
from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.candidates.leakage import AIR_MAX
from hydrocli.netlist.loader import load_netlist

ROOT = Path(__file__).resolve().parents[2]
VOLS = ("cylinder.V_A0", "cylinder.V_B0")


def _judged(values, initial=(2.0e-4, 6.0e-4), se=1e-6):
    return [{"name": n, "value": v, "initial": v0, "stderr": se} for n, v, v0 in zip(VOLS, values, initial)]


def _final(values, se=1e-6):
    names = list(VOLS) + ["u_delay.T"]
    p = np.array(list(values) + [0.02])
    model = SimpleNamespace(param_names=names, param_index=names.index)
    return SimpleNamespace(p=p, model=model, stderr={n: se for n in names})


def _rule(su, stage, judged):
    """The real rule (more oil than drawn in every chamber), needed on held-out data."""
    return findings.fluid_compliance_excess(judged, [findings.Chambers("cylinder", VOLS)], lambda vals: (1.0, 0.1))


AIR = {"effect": "entrained_air", "component": "cylinder", "source": "base_fit", "validation_gain": 1.0,
       "finding": "fluid_compliance_excess"}
STOPS = {"effect": "end_stop", "component": "cylinder", "source": "base_fit"}   # a runaway finding: not re-judged
DELAY = {"effect": "input_delay", "component": "valve", "source": "candidate"}


def test_a_base_fit_finding_is_withdrawn_when_the_final_model_no_longer_needs_it(monkeypatch):
    monkeypatch.setattr(base_findings, "base_fit_findings", _rule)
    b = SimpleNamespace(judged=_judged((8.6e-4, 1.3e-3)))
    assert _rule(None, None, b.judged)                       # the base fit: both chambers ×4.3, ×2.1 → air
    # the delay accepted, the polished model puts the volumes back near the drawing (×1.15, ×0.9)
    kept = base_findings.still_found(None, b, _final((2.3e-4, 5.4e-4)), [AIR, STOPS, DELAY])
    assert kept == [STOPS, DELAY]
    # still ×2 in both chambers, well determined: the finding stands beside the delay
    kept = base_findings.still_found(None, b, _final((4.0e-4, 1.2e-3)), [AIR, STOPS, DELAY])
    assert kept == [AIR, STOPS, DELAY]
    # ×2, but the final fit no longer determines them (3 σ): withdrawn
    kept = base_findings.still_found(None, b, _final((4.0e-4, 1.2e-3), se=2e-4), [AIR, DELAY])
    assert kept == [DELAY]


def test_the_air_law_covers_a_third_of_the_volume_as_free_air_at_one_bar():
    """The library's law with r = α₀/(1 − α₀) is the mixture law written with the air's volume
    FRACTION α₀ at 1 bar (independent closed form: 1/β_e = (1 − α)/β + α/(n p),
    α = g/(g + 1 − α₀), g = α₀ (p₀/p)^(1/n)); the air candidate's bound reaches α₀ = 0.38."""
    beta, n = 1.6e9, 1.4
    for a0 in (0.01, 0.15, 0.38):
        for p in (5e5, 5e6, 1.5e7):
            g = a0 * (1e5 / p) ** (1 / n)
            alpha = g / (g + 1 - a0)
            ref = 1.0 / ((1 - alpha) / beta + alpha / (n * p))
            e = effective_bulk_modulus(beta, p, a0 / (1 - a0), n)
            assert np.isclose(getattr(e, "value", e), ref, rtol=1e-12)
    net = load_netlist(ROOT / "machines/eha_testbench.yaml")
    cands, _ = catalogue(Context(net, set()))
    air = next(c for c in cands if c.effect == "entrained_air")
    amount = next(p for p in air.params if p.primary)
    assert amount.bounds[1] == AIR_MAX >= 0.38 / 0.62 and amount.plausible[1] >= 0.38 / 0.62


def _late_rule(su, stage, judged, late=False):
    """The real rules: every chamber grown → air (early); one chamber grown → a hose (late)."""
    ch = [findings.Chambers("cylinder", VOLS)]
    return (findings.undrawn_volume(judged, ch, lambda vals: (1.0, 0.1)) if late
            else findings.fluid_compliance_excess(judged, ch, lambda vals: (1.0, 0.1)))


LIFT = {"effect": "load_compliance", "component": "cylinder", "source": "candidate"}
HOSE = {"effect": "line_dynamics", "component": "valve", "source": "candidate"}


def test_volume_one_side_needs_beyond_the_drawing_is_a_hose_named_after_the_candidates(monkeypatch):
    """A lift whose bore-side hose the file leaves out: the base fit puts it into V_A0 (dev:
    ×1.7–3.1, V_B0 ×1.0–1.4) and explains the held-out data to the noise, so no line candidate
    can gain on it. The grown volume IS the finding — but only after the candidates: a rod–load
    link on a gravity load grows V_A0 too (dev ×2.6) and takes it back once modelled."""
    monkeypatch.setattr(base_findings, "base_fit_findings", _late_rule)
    base = SimpleNamespace(p=None)
    b = SimpleNamespace(judged=_judged((6.1e-4, 6.6e-4)), stage=base)     # V_A0 ×3.05, V_B0 ×1.1
    assert _late_rule(None, None, b.judged) == []                        # not air: one chamber only
    late = base_findings.late_findings(None, b, base, [])
    assert [(f["effect"], f["source"]) for f in late] == [("line_dynamics", "base_fit")]
    assert [p["name"] for p in late[0]["parameters"]] == ["cylinder.V_A0"]
    assert late[0]["alternatives"] == ["entrained_air"]
    # a candidate took the volume back to the drawing's: the final model shows no hose
    assert base_findings.late_findings(None, b, _final((2.2e-4, 6.1e-4)), [LIFT]) == []
    # the final model still needs it beside the candidate: listed after it
    assert [f["effect"] for f in base_findings.late_findings(None, b, _final((6.0e-4, 6.1e-4)), [LIFT])] == ["line_dynamics"]
    # a line (on the valve that feeds the cylinder) or air already accepted explains the volume
    assert base_findings.late_findings(None, b, _final((6.0e-4, 6.1e-4)), [LIFT, HOSE]) == []
    # both chambers grown is the air rule's; poorly determined is nothing
    assert findings.undrawn_volume(_judged((6e-4, 1.8e-3)), [findings.Chambers("cylinder", VOLS)],
                                   lambda v: (1.0, 0.1)) == []
    assert findings.undrawn_volume(_judged((6e-4, 6e-4), se=2e-4), [findings.Chambers("cylinder", VOLS)],
                                   lambda v: (1.0, 0.1)) == []
    # not needed by the held-out data: nothing
    assert findings.undrawn_volume(_judged((6e-4, 6e-4)), [findings.Chambers("cylinder", VOLS)],
                                   lambda v: (0.05, 0.1)) == []



def _row(effect, dbic):
    return {"effect": effect, "component": "cylinder", "fitted": True, "delta_bic": dbic}


def test_a_one_sided_volume_is_named_by_what_improves_on_it_in_the_last_round(monkeypatch):
    """The late finding is a constant extra compliance on one side. The last round fitted each
    reading ON TOP of it: air's stiffness softens with falling pressure, a hose adds an
    inertance and a loss. When air improves the training fit there (dev rotary polytropic air:
    −1424) and the line does not (+66), the volume lacks air's pressure dependence and the
    finding is named entrained_air, with the hose as its alternative; a hose that improves on it
    keeps the hose's name (dev lift hoses: line −731 … −3335, air +10 … +29)."""
    monkeypatch.setattr(base_findings, "base_fit_findings", _late_rule)
    base = SimpleNamespace(p=None)
    b = SimpleNamespace(judged=_judged((6.1e-4, 6.6e-4)), stage=base)
    air = base_findings.late_findings(None, b, base, [], rows=[_row("entrained_air", -1424.0),
                                                                _row("line_dynamics", 66.0)])
    assert [(f["effect"], f["alternatives"], f["finding"]) for f in air] == [
        ("entrained_air", ["line_dynamics"], "undrawn_volume")]
    assert "on top of the grown volume" in air[0]["description"]
    for rows in ([_row("entrained_air", 29.0), _row("line_dynamics", -731.0)],
                 [_row("entrained_air", -51.0), _row("line_dynamics", -3335.0)],   # both improve: its own name
                 [_row("entrained_air", -1424.0)],                                 # the line not fitted: no verdict
                 []):
        assert [f["effect"] for f in base_findings.late_findings(None, b, base, [], rows=rows)] == ["line_dynamics"]

def test_a_finding_reports_the_held_out_error_without_it_and_with_it():
    """The real wiring (base_findings.base_fit_findings on the short demo lift): pretend the drawing
    says a third of the bore-side volume the recording needs. The late rule finds the hose,
    and the finding carries the held-out ESR with V_A0 back at the drawing's (before) and as
    fitted (after), like a candidate does — the benchmark's gap is measured from 'before'."""
    case = ROOT / "experiments" / "family" / "demo" / "lift" / "lift__none__base_a__s0"
    su = engine.prepare(case / "base.yaml", [case / "train.csv"], [case / "validate.csv"], engine.Settings())
    m = su.model
    p = np.array(m.p0, float)
    stage = stage_of.make_stage(su.net, m, p, 1.0, list(m.free_params), su.train, su.validate, su.outputs)
    va, vb = (float(p[m.param_index(n)]) for n in VOLS)
    judged = [{"name": VOLS[0], "value": va, "initial": va / 3, "stderr": va * 1e-3},
              {"name": VOLS[1], "value": vb, "initial": vb, "stderr": vb * 1e-3}]
    found = base_findings.base_fit_findings(su, stage, judged, late=True)
    assert [(f["effect"], f["source"]) for f in found] == [("line_dynamics", "base_fit")]
    f = found[0]
    assert f["esr_validation_after"] == stage.esr_validation
    before, after = sum(f["esr_validation_before"].values()), sum(stage.esr_validation.values())
    assert before - after == pytest.approx(f["validation_gain"], rel=1e-9) and before > after
    # the volume as drawn: nothing found
    judged[0]["initial"] = va
    assert base_findings.base_fit_findings(su, stage, judged, late=True) == []


def test_chambers_grown_alike_are_every_chamber_a_one_sided_growth_is_one_side():
    """Free air softens every chamber, a hose grows the side it feeds: 'every chamber' is
    read against the largest growth, not chamber by chamber against the ×1.5 cut. Dev rotary
    isothermal air grew the chambers ×1.57 and ×1.49: every chamber (air first, the hose its
    alternative), no longer a one-sided volume named a hose. A one-sided hose leaves the other
    chamber at ×1.0–1.4 of a ×1.7–5 growth (dev lifts): one side. Nothing grows ×1.5: nothing."""
    ch = [findings.Chambers("cylinder", VOLS)]
    gain = lambda vals: (1.0, 0.1)                                            # noqa: E731
    air = _judged((2.0e-4 * 1.57, 6.0e-4 * 1.49))
    assert findings.grown_alike(air)
    assert [f["effect"] for f in findings.fluid_compliance_excess(air, ch, gain)] == ["entrained_air"]
    assert findings.undrawn_volume(air, ch, gain) == []
    for other in (1.0, 1.22, 1.4):                                          # a ×2.9 hose, the other side near the drawing
        hose = _judged((2.0e-4 * 2.92, 6.0e-4 * other))
        assert not findings.grown_alike(hose)
        assert findings.fluid_compliance_excess(hose, ch, gain) == []
        assert [f["effect"] for f in findings.undrawn_volume(hose, ch, gain)] == ["line_dynamics"]
    assert not findings.grown_alike(_judged((2.0e-4 * 1.45, 6.0e-4 * 1.45)))   # both below the cut
    assert not findings.grown_alike(_judged((2.0e-4 * 1.6, 6.0e-4 * 1.5), se=1e-4))   # not determined
