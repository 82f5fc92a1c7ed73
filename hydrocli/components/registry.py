"""The registry of component types, keyed by the YAML ``type:``.

Registering a type is one decorator; modules of the library register themselves when
:func:`load_library` imports them. An unknown type lists the closest known ones.
"""
from __future__ import annotations

import difflib
import importlib
import pkgutil

from .base import Component

_TYPES: dict[str, type[Component]] = {}
_LOADED = False


def register(cls: type[Component]) -> type[Component]:
    if not cls.type:
        raise ValueError(f"{cls.__name__} has no type name")
    if cls.type in _TYPES and _TYPES[cls.type] is not cls:
        raise ValueError(f"component type '{cls.type}' registered twice "
                         f"({_TYPES[cls.type].__module__} and {cls.__module__})")
    _TYPES[cls.type] = cls
    return cls


def load_library() -> None:
    """Import every module under ``hydrocli.components`` so their types register."""
    global _LOADED
    if _LOADED:
        return
    from .. import components as pkg
    for mod in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
        if mod.name.rsplit(".", 1)[-1] in ("base", "registry"):
            continue
        importlib.import_module(mod.name)
    _LOADED = True


def get(type_name: str) -> type[Component] | None:
    load_library()
    return _TYPES.get(type_name)


def all_types() -> dict[str, type[Component]]:
    load_library()
    return dict(sorted(_TYPES.items()))


def offering(role_name: str) -> dict[str, type[Component]]:
    """Every registered type that offers the role ``role_name`` (see :mod:`.roles`)."""
    return {t: c for t, c in all_types().items() if c.role(role_name) is not None}


def suggest(name: str, choices) -> str:
    """' (did you mean …?)' or an empty string."""
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.6)
    if not close:
        return ""
    return " (did you mean " + " or ".join(f"'{c}'" for c in close) + "?)"
