"""Free parameters ↔ the optimiser's unit box.

Each free parameter p with bounds [lo, hi] is searched as z ∈ [0, 1]:
linear p = lo + z·(hi − lo), or logarithmic p = lo·(hi/lo)^z when the bounds are positive
and span more than two decades (or the machine file says ``log: true``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import IdentifyError, Problem
from ..model.model import Model


@dataclass
class FreeParameters:
    names: list[str]
    index: np.ndarray          # positions in the model's parameter vector
    lo: np.ndarray
    hi: np.ndarray
    log: np.ndarray            # bool per parameter

    @classmethod
    def from_model(cls, model: Model, names: list[str] | None = None,
                   bounds: dict[str, tuple[float, float]] | None = None) -> "FreeParameters":
        names = list(names) if names else model.free_params
        if not names:
            raise IdentifyError(Problem("no free parameters to identify",
                                        hint="mark parameters 'free: true' with bounds in the machine file, "
                                             "or pass --free comp.param"))
        bounds = bounds or {}
        idx, lo, hi, lg = [], [], [], []
        problems = []
        for n in names:
            i = model.param_index(n)
            info = model.params[i]
            b = bounds.get(n) or info.bounds
            if b is None:
                v = info.value
                b = (v / 10, v * 10) if v > 0 else None
            if b is None or not b[0] < b[1]:
                problems.append(Problem(f"parameter '{n}' needs bounds [lower, upper] to be identified",
                                        hint=f"write {n.rsplit('.', 1)[-1]}: {{value: …, free: true, bounds: [lo, hi]}}"))
                continue
            idx.append(i)
            lo.append(float(b[0]))
            hi.append(float(b[1]))
            lg.append(bool(info.log) if info.log is not None else (b[0] > 0 and b[1] / b[0] > 100.0))
        if problems:
            raise IdentifyError(problems)
        return cls(names, np.array(idx, dtype=int), np.array(lo), np.array(hi), np.array(lg, dtype=bool))

    def to_z(self, values: np.ndarray) -> np.ndarray:
        v = np.clip(np.asarray(values, float), self.lo, self.hi)
        z = np.empty_like(v)
        lin = ~self.log
        z[lin] = (v[lin] - self.lo[lin]) / (self.hi[lin] - self.lo[lin])
        z[self.log] = np.log(v[self.log] / self.lo[self.log]) / np.log(self.hi[self.log] / self.lo[self.log])
        return z

    def from_z(self, z: np.ndarray) -> np.ndarray:
        z = np.clip(np.asarray(z, float), 0.0, 1.0)
        v = np.empty_like(z)
        lin = ~self.log
        v[lin] = self.lo[lin] + z[lin] * (self.hi[lin] - self.lo[lin])
        v[self.log] = self.lo[self.log] * (self.hi[self.log] / self.lo[self.log]) ** z[self.log]
        return v

    def dp_dz(self, z: np.ndarray) -> np.ndarray:
        """Derivative of p with respect to z (for standard errors)."""
        v = self.from_z(z)
        ratio = np.where(self.log, self.hi / np.where(self.log, self.lo, 1.0), 1.0)   # log-scaled only
        return np.where(self.log, v * np.log(ratio), self.hi - self.lo)

    def full_vector(self, base: np.ndarray, values: np.ndarray) -> np.ndarray:
        p = np.array(base, dtype=float, copy=True)
        p[self.index] = values
        return p

    def at_bound(self, values: np.ndarray, tol: float = 1e-3) -> list[str]:
        z = self.to_z(values)
        return [n for n, zi in zip(self.names, z) if zi < tol or zi > 1 - tol]
