"""The catalogue of candidate effects: one module per family (see :mod:`.base`).

Families are found, not listed: every :class:`~.base.Family` subclass defined in a module of
this package takes part (in module order), so adding a candidate effect is one new module
(and its test) — nothing else changes.
"""
from __future__ import annotations

import importlib
import inspect
import pkgutil

from .base import VOCABULARY, Candidate, Context, Family, NewParam, Skipped, split


def _discover() -> tuple[Family, ...]:
    found = []
    for mod in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if mod.name == "base":
            continue
        module = importlib.import_module(f"{__name__}.{mod.name}")
        for _, cls in inspect.getmembers(module, inspect.isclass):
            if issubclass(cls, Family) and cls is not Family and cls.__module__ == module.__name__:
                found.append(cls())
    return tuple(found)


FAMILIES = _discover()
SWITCHING = frozenset().union(*(f.switching for f in FAMILIES))       # effects whose law switches
COMPLIANCES = frozenset().union(*(f.compliances for f in FAMILIES))   # effects that add a compliance
LAGS = frozenset().union(*(f.lags for f in FAMILIES))                 # effects that retard the response
BANDS = frozenset().union(*(f.bands for f in FAMILIES))               # dead bands of one element
LAWS = frozenset().union(*(f.laws for f in FAMILIES))                 # effects offered in several laws
FRICTIONS = frozenset().union(*(f.frictions for f in FAMILIES))       # forces following a contact's speed
REDUCES_TO = frozenset().union(*(f.reduces_to for f in FAMILIES))     # (richer law, its special case)


def catalogue(ctx: Context) -> tuple[list[Candidate], list[Skipped]]:
    """Every candidate applicable to the machine, and the effects skipped with a reason."""
    items = []
    for fam in FAMILIES:
        items.extend(fam.candidates(ctx))
    cands, skipped = split(items)
    covered = {c.effect for c in cands}
    skipped = [s for s in skipped if s.effect not in covered] + [s for s in skipped if s.effect in covered]
    return cands, skipped


__all__ = ["VOCABULARY", "Candidate", "Context", "NewParam", "Skipped", "catalogue", "FAMILIES", "SWITCHING", "COMPLIANCES", "LAGS", "BANDS", "LAWS", "FRICTIONS", "REDUCES_TO"]
