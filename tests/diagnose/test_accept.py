"""Acceptance rule: BIC, validation beyond the noise band, plausible and determined parameter."""
from hydrocli.diagnose import accept
from hydrocli.diagnose.candidates import Candidate, NewParam


def _cand():
    return Candidate("coulomb_friction", "friction", [NewParam("f.kc", 1.0, (0.0, 5000.0), (10.0, 5000.0), 400.0)],
                     lambda n: n, "force", "test")


def _fit(value, se, cost):
    return {"names": ["f.kc"], "estimates": [value], "stderr": [se], "cost": cost}


def test_accepts_a_clear_improvement():
    v = accept.judge(_cand(), _fit(1200.0, 50.0, 0.2), ssr0=1.0, n_eff=500, val0=10.0, val1=2.0, noise=0.2)
    assert v["passed"] and v["delta_bic"] < 0


def test_rejects_gain_within_noise_band():
    v = accept.judge(_cand(), _fit(1200.0, 50.0, 0.9), ssr0=1.0, n_eff=500, val0=1.0, val1=0.9, noise=0.3)
    assert not v["passed"] and any("noise band" in r for r in v["reasons"])


def test_rejects_implausible_or_undetermined_parameter():
    at_bound = accept.judge(_cand(), _fit(5000.0, 50.0, 0.2), 1.0, 500, 10.0, 2.0, 0.2)
    assert not at_bound["passed"] and any("bound" in r for r in at_bound["reasons"])
    vague = accept.judge(_cand(), _fit(100.0, 90.0, 0.2), 1.0, 500, 10.0, 2.0, 0.2)
    assert not vague["passed"] and any("poorly determined" in r for r in vague["reasons"])
    tiny = accept.judge(_cand(), _fit(2.0, 0.1, 0.2), 1.0, 500, 10.0, 2.0, 0.2)
    assert not tiny["passed"] and any("plausible" in r for r in tiny["reasons"])


def test_rejects_when_bic_does_not_improve():
    v = accept.judge(_cand(), _fit(1200.0, 50.0, 0.999), ssr0=1.0, n_eff=50, val0=10.0, val1=2.0, noise=0.2)
    assert not v["passed"] and v["delta_bic"] > 0
