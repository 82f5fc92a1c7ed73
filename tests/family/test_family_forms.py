"""Every effect form the family generates is wired into the truth it runs on: switched on, it
changes the measured signals of a short open-loop run (a form whose hook a truth ignored
would leave them identical and yield a case with no concealed effect)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from experiments.concealed.truth.eha import Inputs
from experiments.family import catalogue as cat
from experiments.family.generate import _truth
from experiments.family.machines import MACHINES
from experiments.family.truth.actuator import ActuatorTruth

# the fourth forms have their own run that reaches each one's regime (a cracking pressure, a
# pump's flow limit): tests/family/test_fourth_forms.py; so do the fifth: test_fifth_forms.py
CASES = [(m, e, f) for m in MACHINES for e in cat.FORMS for f in cat.forms_of(m, e)
         if f not in cat.FOURTH_FORMS and f not in cat.FIFTH_FORMS]


def _run(mt, p, effect, x0, u_bias):
    dt, T = 1e-3, 0.4
    n = int(T / dt) + 2
    t = dt * np.arange(n)
    u = u_bias + 8.0 * np.sin(2 * math.pi * 3.0 * t)
    inputs = Inputs(0.0, dt, u, [mt.bench["Ps0"]] * n, [0.0] * n)
    m = _truth(mt, p, effect, inputs)
    B = mt.bench
    y0 = (m.initial_state(x0, B["P0"], B["PB0"]) if isinstance(m, ActuatorTruth)
          else m.initial_state(x0, B["P0"]))
    sol = m.simulate(t[:-1], y0)
    assert sol.success
    return m.measured(sol.y)


@pytest.mark.slow
@pytest.mark.parametrize("machine,effect,form", CASES, ids=["/".join(c) for c in CASES])
def test_form_changes_the_recording(machine, effect, form):
    mt = MACHINES[machine]
    p = dict(mt.nominal)
    params = cat.scaled_params(machine, effect, form, 1.0)
    x0, bias = mt.bench["x_home"], 0.0
    if effect == "end_stop":                         # start just below the stop, pushing up
        x0, bias = params["x_stop"] - 2e-4, 15.0
    if form == "scored_bore":                        # start on the scored band of the barrel
        x0 = 0.5 * (params["x1"] + params["x2"])
    off_p = dict(p)
    on_p = dict(p)
    on_p.update(getattr(cat.FORMS[effect][form][0], "base_overrides", {}))
    off_p.update(on_p)                               # same base: only the effect differs
    on = _run(mt, on_p, cat.make(effect, form, params), x0, bias)
    off = _run(mt, off_p, None, x0, bias)
    diff = max(np.max(np.abs(on[k] - off[k])) / (np.ptp(off[k]) + 1e-12) for k in ("P1", "P2", "v"))
    assert diff > 1e-3, (machine, effect, form, diff)
