"""An end-stop case must touch its stop in every experiment (experiments/family/bench.reach):
otherwise the effect is absent from the training recording and the case tests nothing."""
from __future__ import annotations

import pytest

from experiments.family import catalogue as cat
from experiments.family.bench import Excitation, reach
from experiments.family.generate import FS, PREROLL, STOP_MARGIN
from experiments.family.machines import MACHINES


def test_reach_sets_the_highest_target_to_the_limit_and_keeps_the_path_continuous():
    segs = [(0.0, 1.0, 0.0, 0.05), (2.0, 1.0, 0.05, 0.08), (4.0, 1.0, 0.08, 0.02)]
    out = reach(segs, 0.1)
    assert [s[3] for s in out] == [0.05, 0.1, 0.02]
    assert all(out[i][3] == out[i + 1][2] for i in range(len(out) - 1))
    clipped = reach([(0.0, 1.0, 0.0, 0.3), (2.0, 1.0, 0.3, 0.0)], 0.1)
    assert [s[3] for s in clipped] == [0.1, 0.0]                  # already reaches it: only clipped


def test_the_move_raised_to_the_stop_ends_inside_the_recording_at_a_speed_the_bench_uses():
    """Lift dev seed 162: the highest move began 0.64 s before the recording ended, so the piston
    was 7 cm below the stop at the end whatever the setpoint (effect ESR 0). The move raised is
    the highest of those that end inside the recording, stretched to the bench's speed, and the
    later moves are shifted by as much."""
    segs = [(0.0, 1.0, 0.0, 0.05), (2.0, 0.5, 0.05, 0.06), (3.0, 1.0, 0.06, 0.02), (9.5, 1.0, 0.02, 0.09)]
    out = reach(segs, 0.1, duration=10.0, max_speed=0.1)
    assert [s[3] for s in out] == [0.05, 0.1, 0.02, 0.09]         # not the last move: it is cut off
    t0, T, a, b = out[1]
    assert 1.875 * (b - a) / T == pytest.approx(0.1)               # stretched from 0.5 s to 0.9375 s
    assert out[2][0] == pytest.approx(3.0 + T - 0.5) and out[2][2] == 0.1   # later moves shifted, path continuous
    # a move that already reaches the limit but is cut off by the end does not count
    late = reach([(0.0, 1.0, 0.0, 0.05), (9.5, 1.0, 0.05, 0.3)], 0.1, duration=10.0)
    assert late[0][3] == 0.1


@pytest.mark.parametrize("machine", ["eha", "lift", "lift_cbv", "rotary"])
@pytest.mark.parametrize("seed", [1, 2, 3, 160, 161, 162, 163])
def test_the_move_to_the_stop_ends_before_the_recording_does(machine, seed):
    mt = MACHINES[machine]
    smax = cat.FORMS["end_stop"]["bumper_linear"][1][machine]["x_stop"] + STOP_MARGIN[machine]
    for kind in (1, 2):
        exc = Excitation(mt.bench, [seed, kind], 20.0, FS, PREROLL, smax)
        assert any(b >= smax and t0 + T <= 20.0 for t0, T, _, b in exc.segs)


@pytest.mark.parametrize("machine", ["eha", "lift", "rotary"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_experiment_of_an_end_stop_case_drives_to_its_stop(machine, seed):
    mt = MACHINES[machine]
    smax = cat.FORMS["end_stop"]["bumper_linear"][1][machine]["x_stop"] + STOP_MARGIN[machine]
    for kind in (1, 2):                    # train, validate
        exc = Excitation(mt.bench, [seed, kind], 20.0, FS, PREROLL, smax)
        assert max(s[3] for s in exc.segs) == pytest.approx(smax)


def test_a_servo_that_settles_short_of_the_stop_is_driven_further_until_it_touches_it():
    """EHA dev seed 160, Hunt–Crossley stop: the servo under its load settled 3.6 mm short of
    a setpoint 4 mm past the stop, so the training recording never touched it (effect ESR 0 on
    training, 50 % on the held-out record). The closed loop is rerun with the setpoint raised by
    the shortfall (:meth:`CaseRunner.closed_loop`) until the piston reaches the stop."""
    from experiments.family.generate import CaseRunner
    cr = CaseRunner("eha", "end_stop", "hunt_crossley", 160, 20.0)
    # since the raised move ends inside the recording (reach's duration) this case reaches its
    # stop at once; a setpoint 2 mm short of the stop stands for the servo that settles short
    cr.setpoint_max = cr.x_stop - 2e-3
    exc, _, _, _, _, sol = cr.closed_loop("train", 1.0)
    assert exc.setpoint_max > cr.setpoint_max           # the first setpoint was not enough
    assert sol.y[5].max() >= cr.x_stop                  # the piston is on the stop


def test_a_lift_whose_highest_move_came_at_the_end_now_touches_its_stop_in_both_experiments():
    """Lift dev seed 162, linear bumper: before the fix the training reached 0.268 m and the
    held-out record 0.27 m against a stop at 0.34 m (effect ESR 0 in both)."""
    from experiments.family.generate import CaseRunner
    cr = CaseRunner("lift", "end_stop", "bumper_linear", 162, 20.0)
    for kind in ("train", "validate"):
        *_, sol = cr.closed_loop(kind, 1.0)
        assert sol.y[5].max() >= cr.x_stop
