"""Shared helpers of the truth-form tests (tests/family/test_third_forms.py,
test_fourth_forms.py, test_fifth_forms.py): a family machine's truth with one effect, inputs
that hold still, a short sine-driven run, and how far a form moves it from the base truth."""
from __future__ import annotations

import math

import numpy as np

from experiments.concealed.truth.eha import Inputs
from experiments.family import catalogue as cat
from experiments.family.generate import _truth
from experiments.family.machines import MACHINES
from experiments.family.truth.actuator import ActuatorTruth

EFFECT_OF = {f: e for e, fs in cat.FORMS.items() for f in fs}    # form -> its effect


def truth_model(machine, effect, inputs=None, **over):
    """The family truth of ``machine`` at its nominal parameters (``over`` replaced), with ``effect``."""
    p = dict(MACHINES[machine].nominal)
    p.update(over)
    return _truth(MACHINES[machine], p, effect, inputs)


def still_inputs(T=1.0, dt=1e-3, Ps=1.6e7):
    """Valve closed, supply at ``Ps``, no external force, for ``T`` seconds at ``dt``."""
    n = int(T / dt) + 2
    return Inputs(0.0, dt, [0.0] * n, [Ps] * n, [0.0] * n)


def sine_run(machine, effect, form, start, amp, T=0.4):
    """``machine``'s truth with ``effect`` (None: the base truth with ``form``'s base overrides)
    driven by a 3 Hz command sine of ``amp`` % from ``start`` = (x0, P0, PB0) for ``T`` s at
    1 kHz: (measured signals, the first nine states)."""
    mt = MACHINES[machine]
    x0, P0, PB0 = start
    dt = 1e-3
    n = int(T / dt) + 2
    t = dt * np.arange(n)
    u = amp * np.sin(2 * math.pi * 3.0 * t)
    p = dict(mt.nominal)
    p.update(getattr(cat.FORMS[EFFECT_OF[form]][form][0], "base_overrides", {}))
    m = _truth(mt, p, effect, Inputs(0.0, dt, u, [mt.bench["Ps0"]] * n, [0.0] * n))
    y0 = m.initial_state(x0, P0, PB0) if isinstance(m, ActuatorTruth) else m.initial_state(x0, P0)
    sol = m.simulate(t[:-1], y0)
    assert sol.success and np.all(np.isfinite(sol.y))
    return m.measured(sol.y), sol.y[:9]


def deviation(run, machine, form, prm):
    """The largest deviation of P1, P2, v (over each signal's base range) that ``form`` with
    parameters ``prm`` makes from the base truth, both run by ``run(machine, effect, form)``."""
    on, _ = run(machine, cat.make(EFFECT_OF[form], form, prm), form)
    off, _ = run(machine, None, form)
    return max(np.max(np.abs(on[k] - off[k])) / np.ptp(off[k]) for k in ("P1", "P2", "v"))


def esr(run, machine, form):
    """The effect ESR [%] per signal of ``form`` at its nominal size against the base truth."""
    effect = EFFECT_OF[form]
    on, _ = run(machine, cat.make(effect, form, cat.scaled_params(machine, effect, form, 1.0)), form)
    off, _ = run(machine, None, form)
    return {k: 100.0 * np.var(on[k] - off[k]) / np.var(on[k]) for k in ("P1", "P2", "v")}
