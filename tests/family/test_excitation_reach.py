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
