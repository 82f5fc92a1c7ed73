"""Designed input signals for design studies without a recording.

A signal is written in an experiment file under ``inputs:`` as one of

* a constant: ``100 bar`` or a bare number (in the machine input's unit);
* ``{step: {at: 1 s, from: 0, to: 20}}``                       (``from`` defaults to 0);
* ``{ramp: {start: 1 s, stop: 3 s, from: 0, to: 20}}``         (held constant outside);
* ``{sine: {amplitude: 10, frequency: 2 Hz, offset: 0, phase: 0 deg, start: 0 s}}``;
* ``{chirp: {amplitude: 10, f0: 0.1 Hz, f1: 10 Hz, duration: 10 s, start: 0 s,
  method: linear | logarithmic, offset: 0}}``;
* ``{table: {t: [0, 1, 2], values: [0, 5, 5]}}`` (linear interpolation, held at the ends);
* a list of the above, or ``{sum: [...]}``: their sum.

Closed forms (t' = t − start, zero before start for sine and chirp):
sine = offset + A·sin(2πf·t' + φ); linear chirp = A·sin(2π(f0·t' + (f1 − f0)·t'²/(2T)));
logarithmic chirp = A·sin(2π·f0·T/ln(f1/f0)·((f1/f0)^(t'/T) − 1)). Values are numbers in the
input's unit or strings with units (``"5 bar"``); times are seconds or strings (``"20 ms"``).
"""
from __future__ import annotations

import re

import numpy as np

from ..errors import DataError, Location, Problem
from ..units import si_factor, si_unit, to_si
from .unit_check import checked_quantity

KINDS = ("step", "ramp", "sine", "chirp", "table", "sum", "constant")


class SignalSpec:
    """Converts the YAML of one signal into a function of time (SI values)."""

    def __init__(self, unit: str, loc: Location):
        self.unit, self.loc = unit or "1", loc

    def value(self, x, what: str) -> float:
        return checked_quantity(to_si(x, si_unit(self.unit), default_unit=self.unit, location=self.loc, what=what),
                                self.loc, what)

    def time(self, x, what: str) -> float:
        return checked_quantity(to_si(x, "s", location=self.loc, what=what), self.loc, what)

    def freq(self, x, what: str) -> float:
        return checked_quantity(to_si(x, "Hz", location=self.loc, what=what), self.loc, what)

    def fail(self, msg: str, hint: str | None = None):
        raise DataError(Problem(msg, self.loc, hint or f"signal kinds: {', '.join(KINDS)}"))

    def build(self, spec):
        """A vectorised function f(t) -> SI values."""
        if isinstance(spec, (int, float, str)) and not isinstance(spec, bool):
            c = self.value(spec, "constant signal")
            return lambda t: np.full_like(np.asarray(t, float), c)
        if isinstance(spec, list):
            parts = [self.build(s) for s in spec]
            return lambda t: sum(f(t) for f in parts)
        if not isinstance(spec, dict) or len(spec) != 1:
            self.fail(f"a signal must be a value, a list, or one of {{{', '.join(KINDS)}: …}}; got {spec!r}")
        kind, args = next(iter(spec.items()))
        if kind not in KINDS:
            self.fail(f"unknown signal kind '{kind}'")
        if kind == "sum":
            return self.build(list(args))
        if kind == "constant":
            return self.build(args)
        if not isinstance(args, dict) and kind != "table":
            self.fail(f"'{kind}' needs a mapping of its settings")
        return getattr(self, f"_{kind}")(args)

    def _get(self, args, key, conv, default=None, kind=""):
        if key in args:
            return conv(args[key], f"{kind}.{key}")
        if default is None:
            self.fail(f"signal '{kind}' needs '{key}'")
        return default

    def _step(self, a):
        at = self._get(a, "at", self.time, 0.0, "step")
        v0 = self._get(a, "from", self.value, 0.0, "step")
        v1 = self._get(a, "to", self.value, None, "step")
        return lambda t: np.where(np.asarray(t, float) >= at, v1, v0)

    def _ramp(self, a):
        t0 = self._get(a, "start", self.time, 0.0, "ramp")
        t1 = self._get(a, "stop", self.time, None, "ramp")
        v0 = self._get(a, "from", self.value, 0.0, "ramp")
        v1 = self._get(a, "to", self.value, None, "ramp")
        if not t1 > t0:
            self.fail("ramp: 'stop' must be later than 'start'")
        return lambda t: np.interp(np.asarray(t, float), [t0, t1], [v0, v1])

    def _sine(self, a):
        amp = self._get(a, "amplitude", self.value, None, "sine")
        f = self._get(a, "frequency", self.freq, None, "sine")
        off = self._get(a, "offset", self.value, 0.0, "sine")
        ph = to_si(a.get("phase", 0.0), "rad", location=self.loc, what="sine.phase")
        t0 = self._get(a, "start", self.time, 0.0, "sine")

        def f_t(t):
            tt = np.asarray(t, float) - t0
            return off + np.where(tt >= 0, amp * np.sin(2 * np.pi * f * tt + ph), 0.0)
        return f_t

    def _chirp(self, a):
        amp = self._get(a, "amplitude", self.value, None, "chirp")
        f0 = self._get(a, "f0", self.freq, None, "chirp")
        f1 = self._get(a, "f1", self.freq, None, "chirp")
        T = self._get(a, "duration", self.time, None, "chirp")
        t0 = self._get(a, "start", self.time, 0.0, "chirp")
        off = self._get(a, "offset", self.value, 0.0, "chirp")
        method = str(a.get("method", "linear"))
        if method not in ("linear", "logarithmic"):
            self.fail(f"chirp method '{method}'", "use linear or logarithmic")
        if T <= 0 or f0 <= 0 and method == "logarithmic":
            self.fail("chirp needs duration > 0 (and f0 > 0 for a logarithmic sweep)")

        def f_t(t):
            tt = np.clip(np.asarray(t, float) - t0, 0.0, None)
            if method == "linear":
                phase = 2 * np.pi * (f0 * tt + (f1 - f0) * tt ** 2 / (2 * T))
            else:
                k = np.log(f1 / f0)
                phase = 2 * np.pi * f0 * T / k * (np.exp(k * tt / T) - 1.0)
            return off + np.where(np.asarray(t, float) >= t0, amp * np.sin(phase), 0.0)
        return f_t

    def _table(self, a):
        if isinstance(a, list):
            try:
                ts, vs = zip(*a)
            except (TypeError, ValueError):
                self.fail("table as a list needs [time, value] pairs")
        else:
            ts, vs = a.get("t"), a.get("values")
            if ts is None or vs is None:
                self.fail("table needs 't: [...]' and 'values: [...]'")
        tt = np.array([self.time(x, "table.t") for x in ts])
        vv = np.array([self.value(x, "table.values") for x in vs])
        if tt.size != vv.size or tt.size < 1:
            self.fail(f"table has {tt.size} times but {vv.size} values", "give one value per time")
        if np.any(np.diff(tt) <= 0):
            self.fail("table times must be strictly increasing")
        return lambda t: np.interp(np.asarray(t, float), tt, vv)


def signal(spec, unit: str = "1", loc: Location | None = None):
    """``f(t)`` for a signal specification (see the module docstring)."""
    return SignalSpec(unit, loc or Location()).build(spec)


def is_signal(spec) -> bool:
    """True when an input mapping describes a designed signal rather than a recording column."""
    if isinstance(spec, list):
        return True
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        return True
    if isinstance(spec, str):
        return bool(re.match(r"^\s*[-+]?(\d|\.\d)", spec))   # "100 bar"; a bare name is a column
    return isinstance(spec, dict) and len(spec) == 1 and next(iter(spec)) in KINDS


__all__ = ["signal", "is_signal", "KINDS", "si_factor"]
