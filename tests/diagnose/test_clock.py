"""The diagnosis's step clock (hydrocli/diagnose/clock.py): laps add up to the elapsed time."""
from __future__ import annotations

import time

import pytest

from hydrocli.diagnose.clock import StepClock, line


def test_laps_are_the_steps_in_order_and_add_up_to_the_elapsed_time():
    t0 = time.perf_counter()
    c = StepClock(last=t0)
    time.sleep(0.02)
    c.lap("base fit")
    time.sleep(0.05)
    c.lap("round 1")
    c.lap("round 2")                          # stopped at once: a lap of about nothing
    elapsed = time.perf_counter() - t0
    rep = c.report()
    assert [r["step"] for r in rep] == ["base fit", "round 1", "round 2"]
    assert rep[0]["seconds"] >= 0.02 and rep[1]["seconds"] >= 0.05 and rep[2]["seconds"] < 0.01
    assert sum(r["seconds"] for r in rep) == pytest.approx(elapsed, abs=2e-3)


def test_the_line_leaves_out_steps_under_half_a_second():
    rep = [{"step": "base fit", "seconds": 4.2}, {"step": "round 1", "seconds": 275.4},
           {"step": "round 2", "seconds": 0.01}]
    assert line(rep, 280.0) == "Time: 280 s — base fit 4 s, round 1 275 s."
    assert line([], 3.0) == "Time: 3 s."
