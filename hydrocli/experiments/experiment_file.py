"""Experiment files (YAML): which recording feeds which machine input, what to compare.

Format (all keys optional except what the machine needs; full guide in docs/experiments.md)::

    name: eha_train
    description: seed 004 training run
    data: ../../../shared/recordings/eha_none/train.csv   # .csv | .h5/.hdf5 | .mat, relative to this file
    time: t                       # or {column: t, unit: ms}; default 't'/'time' (CSV: first column)
    inputs:                       # machine input → column, or a designed signal (signals.py)
      u: u                        #   shorthand: column name, values as the file's unit says
      Ps: {column: Ps, unit: Pa, scale: 1, offset: "0 bar"}
      Fext: {step: {at: 1 s, to: "500 N"}}
    outputs:                      # (alias measured:) machine output → column
      x: {column: pos, unit: V, scale: "0.02 m/V"}      # SI = scale·(raw in unit) + offset
    window: [1 s, 20 s]
    initial: from_data            # default | steady (settle with frozen inputs) | {piston.x: "70 mm"}
    settle: 2 s                   # pre-roll for initial: steady
    preprocess:
      remove_offset: {P1: {samples: 100}, P2: "0.3 bar"}
      lowpass: {order: 4, cutoff: 30 Hz, signals: [P1, P2]}   # default signals: the outputs
      resample: 1 kHz
    mask: {x: {above: "199.9 mm"}, all: {times: [[0 s, 0.2 s]]}, v: {nan: ignore}}
    fit: [P1, P2, v]
    weights: {P1: 1, v: 2}        # cost wls
    thresholds: {dp: 10, v: 5}    # (alias max_esr:) validate: max ESR % per output
    duration: 10 s                # without data: designed signals only, on a grid at
    rate: 1 kHz                   #   this rate
    experiments:                  # several experiments: each item overrides the keys above
      - {name: run1, window: [0 s, 10 s]}
      - {name: run2, data: run2.csv}

Processing order: read → map columns to SI (unit, scale, offset) → remove_offset → lowpass
(zero phase) → resample → window → masks. Bad data (NaN, non-monotonic time, an unknown
column, a column of the wrong length, a missing input) raises DataError (exit 3) with the file
and row or YAML line.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import DataError, Location, Problem
from ..model.model import Model
from ..netlist import yamldoc as Y
from ..solve.simulate import InputTable
from ..units import si_factor, to_si
from .experiment import Experiment, experiment_from_recording
from .recording import Recording, read_csv, read_recording
from .channels import ChannelsMixin
from .spec_check import check_spec
from .steps import StepsMixin
from .unit_check import check_samples, checked_quantity

KEYS = ("name", "description", "data", "time", "inputs", "outputs", "measured", "window", "initial", "settle",
        "preprocess", "mask", "fit", "weights", "thresholds", "max_esr", "duration", "rate", "experiments")


def recording_from_file(path: str | Path) -> Recording:
    return read_recording(path)


def load_experiment_files(path: str | Path, model: Model) -> list[Experiment]:
    """Every experiment in the file (one, or one per item of ``experiments:``)."""
    path = Path(path)
    try:
        doc, _ = Y.load_file(path)
    except DataError:
        raise
    except Exception as exc:  # NetlistError for YAML syntax: same exit code, keep it
        if hasattr(exc, "problems"):
            raise DataError(exc.problems) from None
        raise
    _check_keys(doc, str(path))
    items = doc.get("experiments")
    if items is None:
        return [_Builder(path, doc, model, path.stem).build()]
    if not Y.is_seq(items) or not items:
        raise DataError(Problem("'experiments:' must be a non-empty list of mappings", Y.key_loc(doc, "experiments", str(path))))
    out = []
    for i, item in enumerate(items):
        if not Y.is_map(item):
            raise DataError(Problem("each item of 'experiments:' must be a mapping", Y.item_loc(items, i, str(path))))
        _check_keys(item, str(path))
        merged = dict((k, v) for k, v in doc.items() if k != "experiments")
        merged.update(item)
        out.append(_Builder(path, merged, model, f"{path.stem}_{i + 1}", item, doc).build())
    return out


def load_experiment_file(path: str | Path, model: Model, name: str | None = None) -> Experiment:
    exps = load_experiment_files(path, model)
    if name is not None:
        for e in exps:
            if e.name == name:
                return e
        raise DataError(Problem(f"no experiment named '{name}' in {path}", Location(str(path)),
                                f"experiments: {', '.join(e.name for e in exps)}"))
    if len(exps) > 1:
        raise DataError(Problem(f"{path} holds {len(exps)} experiments", Location(str(path)),
                                f"pick one as {path}#NAME ({', '.join(e.name for e in exps)})"))
    return exps[0]


def _check_keys(m, file: str) -> None:
    from ..suggest import suggest
    bad = [k for k in m if k not in KEYS]
    if bad:
        k = bad[0]
        raise DataError(Problem(f"unknown key '{k}' in experiment file{suggest(str(k), KEYS)}",
                                Y.key_loc(m, k, file, str(k)), f"allowed: {', '.join(KEYS)}"))


class _Builder(ChannelsMixin, StepsMixin):
    """Turns one experiment mapping into an :class:`Experiment`."""

    def __init__(self, path: Path, spec, model: Model, default_name: str, own=None, top=None):
        self.path, self.file, self.spec, self.model = path, str(path), spec, model
        self.own = own if own is not None else spec      # the item's own keys (with line numbers)
        self.top = top if top is not None else spec      # the file's top level (inherited keys)
        self.name = str(spec.get("name") or default_name)

    # -- locations and conversions ---------------------------------------------------
    def loc(self, *keys) -> Location:
        m = self.own if keys[0] in self.own else self.top
        node, ypath = m, ""
        for k in keys[:-1]:
            if Y.is_map(node) and k in node:
                ypath += f"{k}."
                node = node[k]
        last = keys[-1]
        return Y.value_loc(node, last, self.file, ypath + str(last)) if Y.is_map(node) and last in node \
            else Location(self.file, path=".".join(map(str, keys)))

    def fail(self, msg: str, loc: Location, hint: str | None = None):
        raise DataError(Problem(msg, loc, hint))

    def time(self, x, *keys) -> float:
        what, loc = ".".join(map(str, keys)), self.loc(*keys)
        return checked_quantity(to_si(x, "s", location=loc, what=what), loc, what)

    def rate(self, x, *keys) -> float:
        what, loc = ".".join(map(str, keys)), self.loc(*keys)
        return checked_quantity(to_si(x, "Hz", location=loc, what=what), loc, what, positive=True)

    # -- the pipeline ---------------------------------------------------------------
    def build(self) -> Experiment:
        s = self.spec
        check_spec(self)
        outputs_spec = s.get("outputs") if s.get("outputs") is not None else s.get("measured") or {}
        inputs_spec = s.get("inputs") or {}
        rec = self.recording()
        t = rec.t if rec is not None else self.design_grid()
        missing = [n for n in self.model.input_names if n not in inputs_spec and not (rec and n in rec.columns)]
        if missing:
            self.fail(f"experiment '{self.name}' gives no value for machine input(s) {', '.join(missing)}",
                      self.loc("inputs") if "inputs" in s else Location(self.file, 1, 1),
                      "map each machine input to a column or a designed signal under 'inputs:'")
        nan_ok = self.nan_ignored()
        ins = {n: self.channel(rec, t, "inputs", n, inputs_spec.get(n, n), self.model.input_units.get(n, "1"), False)
               for n in self.model.input_names}
        outs = {}
        for n in outputs_spec:
            if n not in self.model.output_names:
                from ..suggest import suggest
                self.fail(f"'{n}' is not an output of machine {self.model.name}{suggest(str(n), self.model.output_names)}",
                          self.loc("outputs" if "outputs" in s else "measured", n),
                          f"outputs: {', '.join(self.model.output_names)}")
            unit = self.model.output_unit_si(n) or self.model.output_units.get(n) or "1"
            outs[n] = self.channel(rec, t, "outputs" if "outputs" in s else "measured", n, outputs_spec[n], unit,
                                   n in nan_ok)
        t, ins, outs = self.preprocess(t, ins, outs)
        keep = self.window(t)
        t = t[keep]
        ins = {k: v[keep] for k, v in ins.items()}
        outs = {k: v[keep] for k, v in outs.items()}
        U = np.column_stack([ins[n] for n in self.model.input_names]) if ins else np.zeros((t.size, 0))
        exp = Experiment(name=self.name, file=self.file, inputs=InputTable(t, U), t_out=t.copy(), measured=outs,
                         description=str(s.get("description") or ""))
        exp.mask = self.masks(t, outs, nan_ok)
        self.initial(exp)
        self.targets(exp)
        return exp

    def recording(self) -> Recording | None:
        data = self.spec.get("data")
        if data is None:
            return None
        p = Path(str(data))
        if not p.is_absolute():
            p = self.path.parent / p
        if not p.exists():
            self.fail(f"recording '{data}' not found (looked for {p.resolve()})", self.loc("data"),
                      "paths are relative to the experiment file's folder")
        tspec = self.spec.get("time")
        tcol = tspec.get("column") if Y.is_map(tspec) else tspec
        rec = read_recording(p, str(tcol) if tcol is not None else None, check_columns=False)
        if Y.is_map(tspec) and tspec.get("unit") is not None:
            rec.t = rec.t * si_factor(str(tspec["unit"])) / si_factor(rec.units.get(str(tcol), "1") or "1")
        return rec

    def design_grid(self) -> np.ndarray:
        if "duration" not in self.spec:
            self.fail(f"experiment '{self.name}' has neither 'data:' nor 'duration:'", Location(self.file, 1, 1),
                      "give a recording with 'data: file.csv', or 'duration: 10 s' (and 'rate: 1 kHz') "
                      "with designed input signals")
        T = self.time(self.spec["duration"], "duration")
        fs = self.rate(self.spec.get("rate", "1 kHz"), "rate")
        checked_quantity(T, self.loc("duration"), "duration", positive=True)
        check_samples(T, fs, self.loc("duration"), "duration")
        return np.arange(int(round(T * fs)) + 1) / fs

    def initial(self, exp: Experiment) -> None:
        init = self.spec.get("initial", "from_data")
        if init == "steady":
            exp.settle = self.time(self.spec.get("settle", "2 s"), "settle")
        elif init == "from_data":
            pass
        elif Y.is_map(init):
            for k, v in init.items():
                if k == "from_data":
                    exp.initial_from_data = bool(v)
                    continue
                if k not in self.model.state_names:
                    from ..suggest import suggest
                    self.fail(f"initial: '{k}' is not a state{suggest(str(k), self.model.state_names)}",
                              self.loc("initial", k), f"states: {', '.join(self.model.state_names)}")
                unit = self.model.states[self.model.state_index(k)].unit
                exp.initial[k] = to_si(v, unit, location=self.loc("initial", k), what=f"initial.{k}")
        else:
            self.fail(f"initial: '{init}' is not understood", self.loc("initial"),
                      "use from_data, steady, or a mapping state → value")

    def targets(self, exp: Experiment) -> None:
        s = self.spec
        fit = s.get("fit")
        if fit is not None:
            names = [x.strip() for x in fit.split(",")] if isinstance(fit, str) else [str(x) for x in fit]
            for n in names:
                if n not in exp.measured:
                    self.fail(f"fit: '{n}' is not measured in this experiment", self.loc("fit"),
                              f"measured: {', '.join(exp.measured)}")
            exp.fit_outputs = names
        exp.weights = {str(k): float(v) for k, v in (s.get("weights") or {}).items()}
        th = s.get("thresholds") if s.get("thresholds") is not None else s.get("max_esr")
        for k, v in (th or {}).items():
            if k not in self.model.output_names:
                self.fail(f"threshold for unknown output '{k}'", self.loc("thresholds" if "thresholds" in s else "max_esr", k))
            exp.thresholds[str(k)] = float(v)


def load_experiment(path: str | Path, model: Model) -> Experiment:
    """One experiment; ``file.yaml#name`` picks one of several in an experiment file."""
    text = str(path)
    if "#" in text and text.split("#", 1)[0].lower().endswith((".yaml", ".yml")):
        file, name = text.split("#", 1)
        return load_experiment_file(file, model, name=name)
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return experiment_from_recording(read_csv(path), model, name=path.stem)
    if suffix in (".yaml", ".yml"):
        return load_experiment_file(path, model)
    if suffix in (".h5", ".hdf5", ".mat"):
        return experiment_from_recording(recording_from_file(path), model, name=path.stem)
    raise DataError(Problem(f"unknown experiment format '{suffix}' for {path}", Location(str(path)),
                            "give an experiment .yaml, or a recording .csv/.h5/.mat"))


def load_all(path: str | Path, model: Model) -> list[Experiment]:
    """Every experiment a path names: all of an experiment file's, or the one of a recording
    (``file.yaml#name`` picks one)."""
    p = str(path)
    if p.lower().endswith((".yaml", ".yml")):
        return load_experiment_files(p, model)
    return [load_experiment(p, model)]
