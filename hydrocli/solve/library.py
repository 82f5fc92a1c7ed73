"""A model's compiled library: generated C → cc → cached shared object → ctypes handle.

Built on first use and kept on the model (``Model._compiled``); the shared object itself is
cached on disk by the hash of the C text (``solve.compiled.build_library``), so workers and
later runs load it without compiling. Lives in solve/ so that the model never imports the
solver (solve depends on model, not the reverse).
"""
from __future__ import annotations

import hashlib
import os

from ..model.model import Model
from . import compiled as _c
from .compiled import CompileError, CompiledModel

_UNAVAILABLE: dict[str, str] = {}


def compiled(model: Model) -> CompiledModel:
    """The model's compiled library (built on first use, cached on disk and on the model)."""
    if model._compiled is None:
        eq = model.equations
        so = _c.build_library(model.c_source)
        model._compiled = CompiledModel(so, len(eq.states), len(eq.params), len(eq.inputs), len(eq.outputs))
    return model._compiled


def compiled_or_none(model, warn=None):
    """``compiled(model)``, or None when no C compiler works or the library cannot be loaded.

    Only a compiler failure (:class:`CompileError`) or a library that will not load
    (``OSError``) falls back; anything else is a bug and propagates. A cached library that
    will not load (truncated, another architecture) is removed and rebuilt once. A failure
    is remembered per model source, so the compiler is not re-run for every simulation, and
    reported once on stderr (``warn``) with the reason and the fix.
    """
    import sys

    key = hashlib.sha256(model.c_source.encode("utf-8")).hexdigest()
    if key in _UNAVAILABLE:
        return None
    def load_error(exc) -> bool:                          # CompiledModel wraps the loader's OSError
        return isinstance(exc, OSError) or isinstance(exc.__cause__, OSError)

    try:
        try:
            return compiled(model)
        except (OSError, ValueError) as exc:             # a broken cached library: rebuild it once
            if not load_error(exc):
                raise
            os.unlink(_c.build_library(model.c_source))
            return compiled(model)
    except (CompileError, OSError, ValueError) as exc:
        if not isinstance(exc, CompileError) and not load_error(exc):
            raise
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        _UNAVAILABLE[key] = reason
        (warn or (lambda m: print(m, file=sys.stderr)))(
            f"warning: compiled backend unavailable for {model.name} ({reason}); using the Python backend, "
            "which is much slower. Install a C compiler (gcc, or set CC), or pass --backend python to choose it.")
        return None
