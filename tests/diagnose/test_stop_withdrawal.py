"""A stop fitted beyond every recorded position was never pressed (pressed, it would have been
compressed and the record would reach past it): the candidate fit withdraws it out of reach
(workers.withdraw_idle_stops), unless the recording's mask hides that end (a clipping sensor:
the Festo rig, tests/diagnose/test_festo_end_stop.py, needs its stop beyond the clip)."""
from types import SimpleNamespace

import numpy as np

from hydrocli.diagnose.workers import IDLE_STOP, withdraw_idle_stops

NAMES = ["k", "x_min", "x_max"]


class _Model:
    param_names = NAMES

    def param_index(self, n):
        return NAMES.index(n)


class _Cost:
    """Training cost that rises when the lower stop leaves its fitted place (the fit leaned on it)."""

    def __init__(self, p_fit):
        self.p_fit = np.array(p_fit)

    def cost(self, q):
        return 1.0 + float(np.sum((np.asarray(q) - self.p_fit) ** 2))


def _stops(seen=(-0.5, 0.5)):
    return [{"name": "x_min", "start": -0.7, "seen": seen, "bounds": (-1.0, -0.48), "scale": 1.0},
            {"name": "x_max", "start": 0.7, "seen": seen, "bounds": (0.48, 1.5), "scale": 1.0}]


def _res(p):
    return SimpleNamespace(p=np.array(p, float), names=list(NAMES), estimates=np.array(p, float), cost=2.0)


def test_a_stop_beyond_the_record_is_withdrawn_and_the_cost_is_the_withdrawn_models():
    p = [1e8, -0.5 - 2 * IDLE_STOP, 0.499]        # lower stop beyond the record, upper pressed
    res = _res(p)
    out = withdraw_idle_stops(_Cost(p), _Model(), res, _stops())
    assert out == ["x_min"]
    assert res.p[1] == -1.0 and res.estimates[1] == -1.0 and res.p[2] == 0.499
    c1 = 1.0 + (-1.0 - p[1]) ** 2
    assert np.isclose(res.cost, 2.0 * c1 / 1.0)    # scaled by the withdrawn/kept cost ratio


def test_stops_the_record_reaches_are_kept():
    p = [1e8, -0.5 - 0.5 * IDLE_STOP, 0.5 + 0.5 * IDLE_STOP]   # within the tolerance: contact, compression
    res = _res(p)
    assert withdraw_idle_stops(_Cost(p), _Model(), res, _stops()) == []
    assert list(res.p) == p and res.cost == 2.0


def test_an_end_hidden_by_the_mask_keeps_its_stop():
    p = [1e8, -0.6, 0.7]                           # both beyond; the upper end is censored
    res = _res(p)
    assert withdraw_idle_stops(_Cost(p), _Model(), res, _stops(seen=(-0.5, np.inf))) == ["x_min"]
    assert res.p[2] == 0.7
