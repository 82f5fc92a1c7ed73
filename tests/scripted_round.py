"""``engine.round_step`` on scripted screening and fits: the catalogue, the score tests, the
candidate fits and the polish are replaced by given values, so a test can follow which
candidates a round fits, in which waves, and what it names."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from hydrocli.diagnose import augment, candidate_fits, engine, residuals
from hydrocli.diagnose.stage import Settings


def fitted(c, values: dict, cost: float, val: float) -> dict:
    """A candidate fit's record: ``values`` of its parameters, training ``cost``, summed
    validation ESR ``val`` (one output, P1)."""
    names = [p.name for p in c.params]
    return {"key": c.key, "error": None, "names": names, "estimates": [values[n] for n in names],
            "stderr": [1e-3 * abs(values[n]) for n in names], "correlation": None, "cost": cost,
            "esr_validation": {"P1": val}, "esr_train": {"P1": val}}


def run_round(monkeypatch, cands, scores: dict, fit, base_val: float, located: dict | None = None, top: int = 1,
              p_value=lambda score: 1e-20):
    """One round from a base at training cost 1.0 and validation ESR ``base_val`` (P1, noise
    0.08 %): ``scores`` {key: share explained}, ``fit(c)`` the candidate's fit record.
    Returns (the Round, the keys fitted in order, the progress lines)."""
    monkeypatch.setattr(engine, "catalogue", lambda *a, **k: (cands, []))
    monkeypatch.setattr(engine, "context", lambda *a, **k: None)
    monkeypatch.setattr(engine, "_drawing", lambda su: {})
    monkeypatch.setattr(augment, "text_of", lambda net: "")
    monkeypatch.setattr(residuals, "effective_n", lambda *a: 2.0e4)
    monkeypatch.setattr(engine, "_screen", lambda stage, cs, *a: {
        c.key: {"key": c.key, "dr2": scores[c.key], "p_value": p_value(scores[c.key]), "error": None, "t": [],
                "starts": [], "transfers": []} for c in cs})
    asked = []

    def fit_all(jobs, pool=None, progress=None, what=""):
        out = []
        for j in jobs:
            if j["key"].startswith(engine.CONTROL):
                out.append({"key": j["key"], "error": None, "cost": 1.0, "esr_validation": {"P1": base_val}})
                continue
            asked.append(j["key"])
            out.append(fit(next(c for c in cands if c.key == j["key"])))
        return out
    monkeypatch.setattr(candidate_fits, "fit_all", fit_all)
    monkeypatch.setattr(engine, "_polish", lambda su, stage, c, text, f, *a: (
        SimpleNamespace(esr_train=f["esr_train"], esr_validation=f["esr_validation"]), f))
    su = SimpleNamespace(train=[], validate=[], outputs=["P1"], noise_total=0.08, noise={"P1": 0.08},
                         machine="m.yaml", model=None)
    stage = SimpleNamespace(net=None, model=SimpleNamespace(param_names=[]), p=np.zeros(0), cost=1.0,
                            esr_validation={"P1": base_val}, esr_train={"P1": 0.3}, Y_train=[], free=[])
    said = []
    rnd = engine.round_step(su, stage, [], 0, Settings(top=top), None, located or {}, progress=said.append)
    return rnd, asked, said
