"""The catalogue of candidate effects: one module per family (see :mod:`.base`)."""
from __future__ import annotations

from .base import VOCABULARY, Candidate, Context, NewParam, Skipped, split
from .circuit import CircuitFamily
from .friction import FrictionFamily
from .leakage import CylinderFamily
from .mechanics import MechanicsFamily
from .signals import InputDelayFamily, SensorLagFamily
from .valve import ValveFamily

FAMILIES = (CylinderFamily(), FrictionFamily(), ValveFamily(), CircuitFamily(), MechanicsFamily(),
            InputDelayFamily(), SensorLagFamily())


def catalogue(ctx: Context) -> tuple[list[Candidate], list[Skipped]]:
    """Every candidate applicable to the machine, and the effects skipped with a reason."""
    items = []
    for fam in FAMILIES:
        items.extend(fam.candidates(ctx))
    cands, skipped = split(items)
    covered = {c.effect for c in cands}
    skipped = [s for s in skipped if s.effect not in covered] + [s for s in skipped if s.effect in covered]
    return cands, skipped


__all__ = ["VOCABULARY", "Candidate", "Context", "NewParam", "Skipped", "catalogue", "FAMILIES"]
