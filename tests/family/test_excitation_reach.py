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
    exc, _, _, _, _, sol = cr.closed_loop("train", 1.0)
    assert exc.setpoint_max > cr.setpoint_max           # the first setpoint was not enough
    assert sol.y[5].max() >= cr.x_stop                  # the piston is on the stop
