"""A model's compiled library: generated C → cc → cached shared object → ctypes handle.

Built on first use and kept on the model (``Model._compiled``); the shared object itself is
cached on disk by the hash of the C text (``solve.compiled.build_library``), so workers and
later runs load it without compiling. Lives in solve/ so that the model never imports the
solver (solve depends on model, not the reverse).
"""
from __future__ import annotations

from ..model.model import Model
from .compiled import CompiledModel, build_library


def compiled(model: Model) -> CompiledModel:
    """The model's compiled library (built on first use, cached on disk and on the model)."""
    if model._compiled is None:
        eq = model.equations
        so = build_library(model.c_source)
        model._compiled = CompiledModel(so, len(eq.states), len(eq.params), len(eq.inputs), len(eq.outputs))
    return model._compiled
