"""The deterministic dev / held-out split of the family.

A case is named by (machine, effect, form, seed). Its split is the parity of the first byte
of sha256("machine|effect|form|seed"): even -> "dev", odd -> "heldout". No list is stored;
anyone can recompute it, and a case never changes side when others are added.
"""
from __future__ import annotations

import hashlib


def case_hash(machine: str, effect: str, form: str, seed: int) -> bytes:
    return hashlib.sha256(f"{machine}|{effect}|{form}|{int(seed)}".encode()).digest()


def split_of(machine: str, effect: str, form: str, seed: int) -> str:
    return "dev" if case_hash(machine, effect, form, seed)[0] % 2 == 0 else "heldout"


def unit_draw(machine: str, effect: str, form: str, seed: int) -> float:
    """A number in [0, 1) fixed by the case (bytes 1-4 of the same hash)."""
    return int.from_bytes(case_hash(machine, effect, form, seed)[1:5], "big") / 2 ** 32


def case_id(machine: str, effect: str, form: str, seed: int) -> str:
    return f"{machine}__{effect}__{form}__s{int(seed)}"
