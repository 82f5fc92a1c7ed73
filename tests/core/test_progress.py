"""The diagnosis's progress: messages at once, a status line every few seconds between them
when stderr is not a terminal (issue 10 item 3), counts of completed fan-out jobs."""
from concurrent.futures import ThreadPoolExecutor

from hydrocli.diagnose.workers import run_all
from hydrocli.progress import Heartbeat, status


class Clock:
    def __init__(self):
        self.t = 0.0

    def __call__(self):
        return self.t


def test_status_line_only_when_due_and_only_between_messages():
    lines, clock = [], Clock()
    hb = Heartbeat(lines.append, every=5.0, live=False, clock=clock)
    hb("round 1: screening 16 candidate(s)…")
    hb.status("round 1: screened 3/16")
    clock.t = 4.0
    hb.tick()
    assert lines == ["round 1: screening 16 candidate(s)…"]          # not due yet
    clock.t = 5.5
    hb.tick()
    assert lines[-1] == "  … round 1: screened 3/16 (6 s)"
    clock.t = 7.0
    hb.tick()
    assert len(lines) == 2                                               # next one 5 s later
    clock.t = 10.6
    hb.tick()
    assert len(lines) == 3
    hb("  best: leakage")                                                # a message clears the status
    clock.t = 30.0
    hb.tick()
    assert lines[-1] == "  best: leakage"


def test_status_ignored_by_a_plain_callable():
    seen = []
    status(seen.append, "anything")           # a plain callable has no .status: nothing happens
    assert seen == []


def test_thread_prints_while_the_caller_is_busy():
    import time
    lines = []
    with Heartbeat(lines.append, every=0.05, live=False) as hb:
        hb.status("base fit: 3 simulations")
        time.sleep(0.3)
    assert any("base fit: 3 simulations" in ln for ln in lines)


class Recorder:
    def __init__(self):
        self.seen = []

    def __call__(self, msg):
        pass

    def status(self, text):
        self.seen.append(text)


def _square(j):
    return {"key": j["k"], "v": j["k"] ** 2}


def test_run_all_counts_completions_and_keeps_order():
    rec = Recorder()
    jobs = [{"k": k} for k in range(5)]
    with ThreadPoolExecutor(2) as pool:
        out = run_all(_square, jobs, pool, progress=rec, what="fits")
    assert [o["v"] for o in out] == [0, 1, 4, 9, 16]
    assert rec.seen[0] == "fits 0/5" and rec.seen[-1] == "fits 5/5" and len(rec.seen) == 6
    rec2 = Recorder()
    assert [o["v"] for o in run_all(_square, jobs, None, progress=rec2, what="x")] == [0, 1, 4, 9, 16]
    assert rec2.seen[-1] == "x 5/5"
