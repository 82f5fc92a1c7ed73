"""Score a model on held-out experiments: ESR, NRMSE and fit % per experiment and output,
checked against thresholds (maximum ESR in %).

Thresholds come from three places, later ones overriding earlier ones per output:
the experiment (``Experiment.thresholds``), a validation file and the command line
(``--max-esr dp=10``). A validation file is YAML::

    max_esr: {dp: 10, v: 5}              # every experiment
    experiments:                         # optional, per experiment name
      validate: {max_esr: {dp: 3}}

An output with a threshold that the experiment does not measure fails (a CI gate must
never pass because nothing was compared). Outputs that are not recorded but are sums,
differences or products of recorded ones (``dp = chamber_1.p - chamber_2.p`` with P1 and P2
recorded) are derived from the recording (:func:`derive_measured`).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .errors import DataError, Location, Problem
from .metrics import all_metrics
from .results import RunResult
from .runfiles import load_run
from .suggest import suggest


@dataclass
class Row:
    """One experiment × output line of the verdict."""

    experiment: str
    output: str
    esr: float
    nrmse: float
    fit: float
    threshold: float | None = None
    note: str = ""

    @property
    def passed(self) -> bool | None:
        """None when no threshold applies, else whether ESR ≤ threshold (NaN fails)."""
        if self.threshold is None:
            return None
        return bool(np.isfinite(self.esr) and self.esr <= self.threshold)


@dataclass
class Verdict:
    machine: str
    rows: list[Row] = field(default_factory=list)
    results: list[RunResult] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def checked(self) -> list[Row]:
        return [r for r in self.rows if r.threshold is not None]

    @property
    def failed(self) -> list[Row]:
        return [r for r in self.rows if r.passed is False]

    @property
    def exit_code(self) -> int:
        return 1 if self.failed else 0


@dataclass
class Thresholds:
    common: dict[str, float] = field(default_factory=dict)
    per_experiment: dict[str, dict[str, float]] = field(default_factory=dict)
    source: str = "command line"

    def for_experiment(self, name: str, base: dict[str, float] | None = None) -> dict[str, float]:
        out = dict(base or {})
        out.update(self.common)
        out.update(self.per_experiment.get(name, {}))
        return out

    def overridden_by(self, other: "Thresholds") -> "Thresholds":
        """``other`` (the command line) wins over ``self`` (a file), even per experiment."""
        per = {}
        for k in set(self.per_experiment) | set(other.per_experiment):
            per[k] = {**self.per_experiment.get(k, {}), **other.common, **other.per_experiment.get(k, {})}
        return Thresholds({**self.common, **other.common}, per, f"{self.source} and {other.source}")

    def outputs(self) -> set[str]:
        return set(self.common).union(*[set(v) for v in self.per_experiment.values()])


# -- threshold input ------------------------------------------------------------------
def _percent(value, where: str, loc: Location) -> float:
    text = str(value).strip().removesuffix("%").strip() if isinstance(value, str) else value
    try:
        v = float(text)
    except (TypeError, ValueError):
        v = float("nan")
    if isinstance(value, bool) or not np.isfinite(v) or v < 0:
        raise DataError(Problem(f"{where}: maximum ESR must be a non-negative number of percent, got {value!r}",
                                loc, "write e.g. 'dp: 10' (meaning ESR(dp) ≤ 10 %)"))
    return v


def parse_max_esr(items: list[str] | None) -> Thresholds:
    """``["dp=10", "v=5%"]`` → thresholds (``experiment:output=value`` targets one experiment)."""
    th = Thresholds()
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise DataError(Problem(f"--max-esr '{item}': expected OUTPUT=PERCENT", Location(path="--max-esr"),
                                    "write e.g. --max-esr dp=10"))
        exp, _, out = name.strip().rpartition(":")
        v = _percent(value, f"--max-esr {item}", Location(path="--max-esr"))
        (th.per_experiment.setdefault(exp, {}) if exp else th.common)[out] = v
    return th


def load_thresholds(path: str | Path) -> Thresholds:
    """Read a validation file (see module docstring)."""
    from .netlist.yamldoc import is_map, key_loc, load_file, node_loc, value_loc
    path = str(path)
    doc, _ = load_file(path)
    if not is_map(doc):
        raise DataError(Problem("a validation file must be a mapping with 'max_esr:'", Location(path, 1, 1),
                                "write e.g. 'max_esr: {dp: 10, v: 5}'"))

    def table(m, ypath) -> dict[str, float]:
        if not is_map(m):
            raise DataError(Problem(f"{ypath} must map output names to a maximum ESR in %",
                                    node_loc(m, path, ypath), "write e.g. 'max_esr: {dp: 10, v: 5}'"))
        return {str(k): _percent(v, f"{ypath}.{k}", value_loc(m, k, path, f"{ypath}.{k}")) for k, v in m.items()}

    for key in doc:
        if key not in ("max_esr", "experiments"):
            raise DataError(Problem(f"unknown key '{key}' in validation file{suggest(str(key), ['max_esr', 'experiments'])}",
                                    key_loc(doc, key, path, str(key)), "allowed keys: max_esr, experiments"))
    th = Thresholds(table(doc["max_esr"], "max_esr") if "max_esr" in doc else {}, {}, path)
    exps = doc.get("experiments") or {}
    for name, entry in exps.items():
        ypath = f"experiments.{name}"
        if not is_map(entry) or set(entry) - {"max_esr"}:
            raise DataError(Problem(f"{ypath} must hold only 'max_esr:'", value_loc(exps, name, path, ypath),
                                    f"write e.g. '{name}: {{max_esr: {{dp: 3}}}}'"))
        th.per_experiment[str(name)] = table(entry.get("max_esr", {}), f"{ypath}.max_esr")
    return th


def check_outputs(th: Thresholds, known: list[str]) -> None:
    """Refuse thresholds on outputs the machine does not have (typos must not pass CI)."""
    bad = sorted(th.outputs() - set(known))
    if bad:
        raise DataError([Problem(f"threshold for unknown output '{b}'{suggest(b, known)}", Location(th.source),
                                 f"the machine's outputs are: {', '.join(known)}") for b in bad])


# -- scoring ----------------------------------------------------------------------------
def score(res: RunResult, thresholds: dict[str, float], mask: dict | None = None) -> list[Row]:
    """Rows for every measured output and every output with a threshold, in output order."""
    rows = []
    for name, y_sim in res.outputs.items():
        lim = thresholds.get(name)
        if name in res.measured:
            m = all_metrics(res.measured[name], y_sim, (mask or {}).get(name))
            rows.append(Row(res.experiment, name, m["esr"], m["nrmse"], m["fit"], lim))
        elif lim is not None:
            rows.append(Row(res.experiment, name, np.nan, np.nan, np.nan, lim, "not measured"))
    return rows


_ARITH = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide}


def derive_measured(model, measured: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Outputs not recorded but computable by arithmetic from recorded outputs that read a
    state or variable directly (e.g. ``dp = chamber_1.p - chamber_2.p`` from P1 and P2)."""
    exprs = model.equations.output_exprs
    leaves = {}
    for name, e in exprs.items():
        e = _resolve(model, e)
        if name in measured and e.op == "sym":
            leaves[e.args] = measured[name]

    def ev(e):
        e = _resolve(model, e)
        if e.op == "const":
            return e.args[0]
        if e.op == "sym":
            return leaves[e.args]          # KeyError: not derivable
        if e.op in _ARITH:
            return _ARITH[e.op](ev(e.args[0]), ev(e.args[1]))
        raise KeyError(e.op)

    out = {}
    for name, e in exprs.items():
        if name not in measured:
            try:
                value = ev(e)
            except KeyError:
                continue
            if np.ndim(value) == 1:
                out[name] = np.asarray(value, float)
    return out


def _resolve(model, e):
    """Follow ``var`` aliases (a variable defined as another symbol)."""
    for _ in range(20):
        if e.op != "sym" or e.args[0] != "var":
            return e
        nxt = model.equations.variables.get(e.args[1])
        if nxt is None or nxt.op not in ("sym", "const"):
            return e
        e = nxt
    return e


# -- the two entry points -------------------------------------------------------------------
def validate_machine(machine, experiments, th: Thresholds, sets=None, opts=None, on_result=None) -> Verdict:
    """Simulate each experiment (every one of a multi-experiment file; ``file.yaml#name``
    picks one) with the machine's nominal parameters and score it."""
    from .runner import load_machine, simulate_experiment
    from .experiments.experiment_file import load_all
    _, model = load_machine(machine, sets)
    check_outputs(th, model.output_names)
    verdict = Verdict(model.name, notes=[f"warning: {w}" for w in model.warnings])
    for exp in (e for path in experiments for e in load_all(path, model)):
        derived = derive_measured(model, exp.measured)
        exp = replace(exp, measured={**exp.measured, **derived})       # a copy: experiments are never mutated
        if derived:
            verdict.notes.append(f"{exp.name}: {', '.join(derived)} derived from the recorded outputs")
        res = simulate_experiment(model, exp, opts=opts)
        verdict.rows += score(res, th.for_experiment(exp.name, exp.thresholds), exp.mask)
        verdict.results.append(res)
        if on_result:
            on_result(res)
    return verdict


def validate_results(paths, th: Thresholds) -> Verdict:
    """Score result files that already hold /outputs and /measured (no simulation)."""
    verdict = Verdict("")
    for path in paths:
        res = load_run(path)
        if not res.measured:
            raise DataError(Problem(f"{path} has no /measured group: nothing to compare with", Location(str(path)),
                                    "simulate with an experiment that records the outputs, or validate the machine "
                                    "with --experiment"))
        check_outputs(th, list(res.outputs))
        verdict.machine = verdict.machine or res.machine
        verdict.rows += score(res, th.for_experiment(res.experiment))
        verdict.results.append(res)
    return verdict
