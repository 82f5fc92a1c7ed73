"""Spelling hints for error messages: ``' (did you mean 'Kv'?)'`` or nothing.

One function for every "unknown name" message (netlist keys, component types, parameters,
ports, states, outputs, experiment keys, validation thresholds).
"""
from __future__ import annotations

import difflib


def suggest(name: str, choices) -> str:
    """' (did you mean …?)' with up to three close matches (difflib ratio ≥ 0.6), or ''."""
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.6)
    if not close:
        return ""
    return " (did you mean " + " or ".join(f"'{c}'" for c in close) + "?)"
