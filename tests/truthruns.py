"""Shared helpers of the truth-form tests (tests/family/test_third_forms.py,
test_fourth_forms.py): a family machine's truth with one effect, and inputs that hold still."""
from __future__ import annotations

from experiments.concealed.truth.eha import Inputs
from experiments.family.generate import _truth
from experiments.family.machines import MACHINES


def truth_model(machine, effect, inputs=None, **over):
    """The family truth of ``machine`` at its nominal parameters (``over`` replaced), with ``effect``."""
    p = dict(MACHINES[machine].nominal)
    p.update(over)
    return _truth(MACHINES[machine], p, effect, inputs)


def still_inputs(T=1.0, dt=1e-3, Ps=1.6e7):
    """Valve closed, supply at ``Ps``, no external force, for ``T`` seconds at ``dt``."""
    n = int(T / dt) + 2
    return Inputs(0.0, dt, [0.0] * n, [Ps] * n, [0.0] * n)
