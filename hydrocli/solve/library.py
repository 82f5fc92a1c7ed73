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

#: Rosenbrock coefficient sets of csrc/hy_methods.h by name (HY_METHOD)
METHODS = {"rodas4": 1, "rodas4p": 2, "rodas5p": 3}
DEFAULT_METHOD = "rodas5p"
#: further compile-time options per method.  Rodas4P (the default of ``hydro simulate``) uses
#: the generated fast tanh (model/codegen.py: TANH_C, issue 16); the default Rodas5P library of
#: the fitting commands keeps the C library's, so their numbers are unchanged (a fit's path is
#: sensitive to the last digits: a diagnose test's verdict flipped with another last-digit
#: change of the Rodas5P steps, docs/solver.md).
METHOD_DEFINES = {"rodas4p": ("HY_FAST_TANH",)}


def method_source(model: Model, method: str) -> str:
    """The C text of the model's library for ``method``: the model's source, preceded by the
    method's defines for any method other than the default."""
    if method == DEFAULT_METHOD:
        return model.c_source
    defines = [f"#define HY_METHOD {METHODS[method]}"] + [f"#define {d}" for d in METHOD_DEFINES.get(method, ())]
    return "\n".join(defines) + "\n" + model.c_source


def compiled(model: Model, method: str = DEFAULT_METHOD) -> CompiledModel:
    """The model's compiled library (built on first use, cached on disk and on the model).

    ``method`` picks the Rosenbrock coefficient set compiled in (``METHODS``); the default
    Rodas5P library is the model's plain source, any other is a second library built on
    first use (``#define HY_METHOD k`` before the model)."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    eq = model.equations
    sizes = (len(eq.states), len(eq.params), len(eq.inputs), len(eq.outputs))
    if method == DEFAULT_METHOD:
        if model._compiled is None:
            model._compiled = CompiledModel(_c.build_library(model.c_source), *sizes)
        return model._compiled
    libs = model.__dict__.setdefault("_compiled_methods", {})
    if method not in libs:
        libs[method] = CompiledModel(_c.build_library(method_source(model, method)), *sizes)
    return libs[method]


def compiled_or_none(model, warn=None, method: str = DEFAULT_METHOD):
    """``compiled(model)``, or None when no C compiler works or the library cannot be loaded.

    Only a compiler failure (:class:`CompileError`) or a library that will not load
    (``OSError``) falls back; anything else is a bug and propagates. A cached library that
    will not load (truncated, another architecture) is removed and rebuilt once. A failure
    is remembered per model source, so the compiler is not re-run for every simulation, and
    reported once on stderr (``warn``) with the reason and the fix.
    """
    import sys

    ready = model._compiled if method == DEFAULT_METHOD else model.__dict__.get("_compiled_methods", {}).get(method)
    if ready is not None:       # built and loaded before: no hashing of the source per simulation
        return ready
    key = hashlib.sha256(model.c_source.encode("utf-8")).hexdigest()
    if key in _UNAVAILABLE:
        return None
    def load_error(exc) -> bool:                          # CompiledModel wraps the loader's OSError
        return isinstance(exc, OSError) or isinstance(exc.__cause__, OSError)

    try:
        try:
            return compiled(model, method)
        except (OSError, ValueError) as exc:             # a broken cached library: rebuild it once
            if not load_error(exc):
                raise
            os.unlink(_c.build_library(method_source(model, method)))
            return compiled(model, method)
    except (CompileError, OSError, ValueError) as exc:
        if not isinstance(exc, CompileError) and not load_error(exc):
            raise
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        _UNAVAILABLE[key] = reason
        (warn or (lambda m: print(m, file=sys.stderr)))(
            f"warning: compiled backend unavailable for {model.name} ({reason}); using the Python backend, "
            "which is much slower. Install a C compiler (gcc, or set CC), or pass --backend python to choose it.")
        return None
