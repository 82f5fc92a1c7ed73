"""The experiment file's processing steps applied to mapped signals: ``preprocess:``
(remove_offset → lowpass → resample), ``window:`` and ``mask:`` (numerics in preprocess.py)."""
from __future__ import annotations

import numpy as np

from ..netlist import yamldoc as Y
from ..units import dimensionality, to_si
from . import preprocess as pp
from .unit_check import check_samples


class StepsMixin:
    """Needs ``self.spec``, ``self.model``, ``self.loc``, ``self.fail``, ``self.time``, ``self.rate``."""

    def preprocess(self, t, ins, outs):
        pre = self.spec.get("preprocess") or {}
        for k in pre:
            if k not in ("remove_offset", "lowpass", "resample"):
                self.fail(f"unknown preprocessing step '{k}'", self.loc("preprocess", k),
                          "steps: remove_offset, lowpass, resample")
        signals = {**ins, **outs}
        for n, how in (pre.get("remove_offset") or {}).items():
            if n not in signals:
                self.fail(f"remove_offset: no signal '{n}'", self.loc("preprocess", "remove_offset"))
            target = outs if n in outs else ins
            if Y.is_map(how):
                target[n] = pp.remove_offset(target[n], samples=int(how.get("samples", 1)))
            else:
                unit = self.model.output_unit_si(n) if n in outs else dimensionality_unit(self.model.input_units.get(n, "1"))
                target[n] = pp.remove_offset(target[n], value=to_si(how, unit, location=self.loc("preprocess", "remove_offset")))
        lp = pre.get("lowpass")
        if lp is not None:
            loc = self.loc("preprocess", "lowpass")
            names = list(lp.get("signals") or outs)
            if names == ["all"]:
                names = list(signals)
            for n in names:
                target = outs if n in outs else ins if n in ins else None
                if target is None:
                    self.fail(f"lowpass: no signal '{n}'", loc)
                finite = np.isfinite(target[n])
                y = np.interp(t, t[finite], target[n][finite]) if not finite.all() else target[n]
                target[n] = np.where(finite, pp.lowpass(t, y, int(lp.get("order", 4)),
                                                        self.rate(lp.get("cutoff"), "preprocess", "lowpass", "cutoff"), loc), np.nan)
        if pre.get("resample") is not None:
            fs = self.rate(pre["resample"], "preprocess", "resample")
            check_samples(float(t[-1] - t[0]), fs, self.loc("preprocess", "resample"), "preprocess.resample")
            hold = {n for n in ins if self.model.input_hold.get(n) == "zoh"}
            tn, ins = pp.resample(t, ins, fs, hold)
            _, outs = pp.resample(t, outs, fs)
            t = tn
        return t, ins, outs

    def window(self, t) -> np.ndarray:
        w = self.spec.get("window")
        if w is None:
            return np.ones(t.size, dtype=bool)
        if not Y.is_seq(w) or len(w) != 2:
            self.fail("window must be [t_start, t_end]", self.loc("window"))
        t0, t1 = (None if v is None else self.time(v, "window") for v in w)
        keep = pp.window(t, t0, t1)
        if keep.sum() < 2:
            self.fail(f"window [{t0}, {t1}] s leaves fewer than two samples (data from {t[0]:g} to {t[-1]:g} s)",
                      self.loc("window"))
        return keep

    def nan_ignored(self) -> set[str]:
        m = self.spec.get("mask") or {}
        return {n for n, c in m.items() if Y.is_map(c) and str(c.get("nan", "")) == "ignore"}

    def masks(self, t, outs, nan_ok) -> dict[str, np.ndarray]:
        spec = self.spec.get("mask") or {}
        bad = {n: ~np.isfinite(y) for n, y in outs.items()}
        for n, cond in spec.items():
            loc = self.loc("mask", n)
            names = list(outs) if n in ("all", "*") else [n]
            if n not in ("all", "*") and n not in outs:
                self.fail(f"mask: '{n}' is not a measured output of this experiment", loc,
                          f"measured: {', '.join(outs)} (or 'all')")
            if not Y.is_map(cond):
                self.fail("a mask is a mapping {above: …, below: …, times: [[t0, t1], …], nan: ignore}", loc)
            for k in cond:
                if k not in ("above", "below", "times", "nan"):
                    self.fail(f"unknown mask condition '{k}'", loc, "conditions: above, below, times, nan")
            for o in names:
                unit = self.model.output_unit_si(o) or "1"
                above = to_si(cond["above"], unit, location=loc, what="mask.above") if "above" in cond else None
                below = to_si(cond["below"], unit, location=loc, what="mask.below") if "below" in cond else None
                with np.errstate(invalid="ignore"):
                    bad[o] |= pp.mask_condition(outs[o], above, below)
                if "times" in cond:
                    ivs = [(self.time(a, "mask", n), self.time(b, "mask", n)) for a, b in cond["times"]]
                    bad[o] |= pp.mask_times(t, ivs)
        return {n: ~b for n, b in bad.items() if b.any()}


def dimensionality_unit(unit: str) -> str:
    """An SI unit string of the same dimension as ``unit`` (for to_si's dimension check)."""
    from ..units import si_unit
    return si_unit(unit) if dimensionality(unit) else unit


