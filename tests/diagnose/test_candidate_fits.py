"""The candidates' fits split into one pool task per (start, gradient): longest first, each
candidate's winner chosen as one sequential loop over its starts would choose it."""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from types import SimpleNamespace

from hydrocli.diagnose import candidate_fits as cf


class RecordingPool:
    """A one-thread pool that remembers what was submitted, in order."""

    def __init__(self):
        self.ex = ThreadPoolExecutor(max_workers=1)
        self.seen = []

    def submit(self, fn, job):
        self.seen.append((fn.__name__, job))
        return self.ex.submit(fn, job)


def _fake_phases(monkeypatch):
    plans = {"slow": {"starts": ["a", "b"], "n_free": 20, "grads": ["auto", cf.FD], "sim_s": 0.5},
             "quick": {"starts": ["c"], "n_free": 5, "grads": ["auto"], "sim_s": 0.01},
             "broken": None}

    def plan(job):
        pl = plans[job["key"]]
        return {"key": job["key"], "error": "ValueError: no model"} if pl is None else dict(pl, key=job["key"], error=None)

    def fit_start(task):
        return {"error": None, "result": SimpleNamespace(cost=1.0, tag=(task["job"]["key"], task["start"], task["gradient"]))}

    def finish(job):
        return {"key": job["key"], "error": None, "tags": [f["result"].tag for f in job["fits"]]}

    monkeypatch.setattr(cf, "plan", plan)
    monkeypatch.setattr(cf, "fit_start", fit_start)
    monkeypatch.setattr(cf, "finish", finish)


def test_fits_are_submitted_longest_first_and_come_back_per_candidate_in_start_order(monkeypatch):
    _fake_phases(monkeypatch)
    jobs = [{"key": k, "max_evals": 15} for k in ("quick", "broken", "slow")]
    pool = RecordingPool()
    told = SimpleNamespace(seen=[])
    told.status = told.seen.append
    out = cf.fit_all(jobs, pool, progress=told, what="round 1: candidate")
    # the status counts each phase in its own unit: candidates, fits (start × Jacobian), candidates
    assert {"round 1: candidate starts 3/3", "round 1: candidate fits done 5/5",
            "round 1: candidate fits scored 2/2"} <= set(told.seen)
    fits = [job for name, job in pool.seen if name == "fit_start"]
    est = [cf.estimated_seconds({"n_free": 20 if t["job"]["key"] == "slow" else 5,
                                 "sim_s": 0.5 if t["job"]["key"] == "slow" else 0.01}, t["gradient"], 15) for t in fits]
    assert est == sorted(est, reverse=True) and len(fits) == 5
    # finite differences on 20 parameters cost more than sensitivities: those went first
    assert fits[0]["gradient"] == cf.FD and fits[-1]["job"]["key"] == "quick"
    assert [o["key"] for o in out] == ["quick", "broken", "slow"]
    assert out[1]["error"] == "ValueError: no model"
    assert out[2]["tags"] == [("slow", "a", "auto"), ("slow", "a", cf.FD), ("slow", "b", "auto"), ("slow", "b", cf.FD)]
    # without a pool the same phases run in this process, with the same result
    assert cf.fit_all(jobs, None) == out


def test_the_lowest_cost_wins_the_first_among_equals_and_a_failed_fit_fails_the_candidate():
    r = [SimpleNamespace(cost=c, n=i) for i, c in enumerate((2.0, 1.0, 1.0, 3.0))]
    res, err = cf.best([{"error": None, "result": x} for x in r])
    assert err is None and res.n == 1
    res, err = cf.best([{"error": None, "result": r[0]}, {"error": "SolverError: at t = 3 s"}, {"error": "later"}])
    assert res is None and err == "SolverError: at t = 3 s"


def test_the_estimate_breaks_even_between_the_two_jacobians_near_nine_parameters():
    """docs/identify.md: a sensitivity run costs about six plain runs plus 0.3 per column, so
    per Jacobian the two break even near nine free parameters."""
    def cost(n, g):
        return cf.estimated_seconds({"n_free": n, "sim_s": 0.04}, g, 15)
    assert all(cost(n, cf.FD) < cost(n, "auto") for n in range(1, 8))
    assert all(cost(n, cf.FD) > cost(n, "auto") for n in range(10, 40))
