"""What nothing explains at the ends of the stroke brings the stops into the round
(shortlist.at_the_ends): a stop acts at the ends of the travel and nowhere else, while its
score test — a stop probed just beyond the recorded end — is barely touched by a base fit that
bent itself to keep the replayed piston inside the recorded travel (dev EHA, a rubber bumper
pressed 1.5 mm, effect ESR 28 %: the stop screened 0.2 %, was never fitted, and the verdict was
an unexplained mismatch "at the end of stroke")."""
from __future__ import annotations

import pytest

from hydrocli.diagnose import engine, findings
from hydrocli.diagnose.candidates import Candidate, NewParam
from hydrocli.diagnose.locate import END_OF_STROKE as ENDS
from hydrocli.diagnose.shortlist import at_the_ends
from scripted_round import fitted, run_round


def _p(name, primary=True, **kw):
    return NewParam(name, 1.0, (1e-3, 1e9), (1e-2, 1e9), 10.0, True, primary=primary, **kw)


def _cands():
    leak = Candidate("internal_leakage", "cyl", [_p("leak.G")], lambda n: n, "continuity", "leak")
    lag = Candidate("sensor_lag", "p1", [_p("sensor.tau")], lambda n: n, "measurement", "lag")
    comp = Candidate("load_compliance", "cyl", [_p("link.k"), _p("link.c", False)], lambda n: n, "force", "link")
    stop = Candidate("end_stop", "cyl", [_p("cyl.x_max", scale=0.1, reach=(0.03, 0.14), seen=(0.04, 0.13)),
                                         _p("cyl.k_stop", False)], lambda n: n, "force", "stops")
    cushion = Candidate("end_stop", "cyl", [_p("cushion.x_end", scale=0.1, reach=(0.03, 0.14)),
                                            _p("cushion.needle", False)], lambda n: n, "continuity", "cushion",
                        variant="cushion_max")
    return leak, lag, comp, stop, cushion


def _fillers():
    return [Candidate(e, "cyl", [_p(f"{e}.a")], lambda n: n, eq, e)
            for e, eq in (("valve_overlap", "valve"), ("input_delay", "signal"), ("entrained_air", "continuity"),
                          ("external_leakage", "continuity"))]


def _located(regime: str, concentration: float) -> dict:
    return {"regimes": [{"regime": regime, "share": 0.68, "time_share": 0.68 / concentration,
                         "concentration": concentration}], "windows": []}


@pytest.mark.parametrize("regime,concentration,expect", [(ENDS, 1.55, True), ("moving +", 3.2, False),
                                                         (ENDS, 1.1, False)])
def test_the_stops_are_what_an_error_at_the_ends_of_the_stroke_asks_for(regime, concentration, expect):
    leak, lag, comp, stop, cushion = _cands()
    mismatch = findings.unexplained({"P1": 23.0}, {"P1": 0.08}, _located(regime, concentration))
    assert mismatch is not None      # the validation error is far above the noise in every case
    got = at_the_ends(mismatch, [leak, stop, lag, cushion, comp])
    assert [c.key for c in got] == ([stop.key, cushion.key] if expect else [])
    assert at_the_ends(None, [stop, cushion]) == []          # explained: nothing more to fit


def test_a_round_fits_the_stops_when_the_unexplained_error_lies_at_the_ends_and_names_one(monkeypatch):
    """round_step on scripted screening and fits: the stop screens last and no shortlisted
    candidate passes; with the error concentrated at the ends of the stroke the round fits the
    stops in one more wave after the shortlist's and names the stop. With the error elsewhere
    the stops are not fitted and nothing is named."""
    leak, lag, comp, stop, cushion = _cands()
    fillers = _fillers()
    cands = [leak, lag, comp, stop, cushion] + fillers
    scores = {leak.key: 0.10, lag.key: 0.036, comp.key: 0.017, cushion.key: 0.003, stop.key: 0.002,
              **{f.key: 0.012 - 0.002 * i for i, f in enumerate(fillers)}}
    values = {"leak.G": 1e-12, "sensor.tau": 1e-3, "link.k": 1e7, "link.c": 1e3, "cyl.x_max": 0.13,
              "cyl.k_stop": 3e10, "cushion.x_end": 0.129, "cushion.needle": 1e-8, **{f"{f.effect}.a": 1.0 for f in fillers}}
    # (training cost, summed validation ESR): the base stands at 1.0 and 46.2 %
    result = {leak.key: (0.98, 45.0), lag.key: (0.99, 47.0), comp.key: (0.995, 45.5), cushion.key: (0.97, 44.0),
              stop.key: (0.30, 2.4), **{f.key: (0.99, 46.0) for f in fillers}}
    for regime, extra_waves, named in ((ENDS, 2, "end_stop"), ("moving +", 2, None), (ENDS, 0, "end_stop")):
        monkeypatch.setattr(engine, "EXTRA_WAVES", extra_waves)
        rnd, asked, said = run_round(monkeypatch, cands, scores, lambda c: fitted(c, values, *result[c.key]),
                                     base_val=46.2, located=_located(regime, 1.55),
                                     p_value=lambda score: 1e-20 if score > 0.005 else 0.5)
        assert len(asked) == len(set(asked)), asked                 # nothing is fitted twice
        stops = {stop.key, cushion.key}
        assert (stops <= set(asked)) == (named is not None), (regime, extra_waves, asked)
        if named is None:
            assert rnd.accepted is None and not stops & set(asked)
        else:
            assert rnd.accepted["effect"] == named and rnd.accepted["key"] == stop.key, said
            # the stops come after the shortlist's waves, in one wave of their own
            assert asked[-2:] in ([stop.key, cushion.key], [cushion.key, stop.key]), asked
            assert any(ENDS in s for s in said)
