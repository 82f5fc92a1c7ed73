"""The diagnosis's typed state: its settings, a model state (:class:`Stage`), what every step
works on (:class:`Setup`), and each step's product; with the small helpers that make and
print them. Data flows one way: :mod:`.engine` and the steps it calls import this, never the
reverse."""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..identify.fit import FitResult
from ..model.model import Model
from ..netlist.model import Netlist
from ..progress import status
from ..experiments.experiment import Experiment
from . import locate, residuals, travel
from .candidates import Candidate, Context
from .nuisance import Nuisance


@dataclass
class Settings:
    max_effects: int = 3
    jobs: int = 2
    top: int = 3                 # effects re-identified per round (their best-screening forms)
    base_evals: int = 100        # optimiser iterations of the base fit (it stops earlier when converged)
    candidate_evals: int = 15
    window_s: float = 0.5
    only: tuple[str, ...] = ()   # restrict the catalogue to these effects (empty: all)
    nuisance: bool = True        # free the valves' spool dynamics in the base fit
    # fits of candidates that switch (friction, stops, dead bands, play) on BOTH Jacobians, the
    # lower cost wins: forward sensitivities are not error-controlled and can lose accuracy
    # through stick–slip and contact events, exactly where those act, while finite differences
    # of a steep switching law can stall the search (a Coulomb force that a widened Stribeck
    # term already imitates: stopped at 170 N on differences, 340 N on sensitivities, truth
    # 380–480 N); every other fit uses sensitivities ("auto")
    switching_gradient: str = "both"
    scheduler: str | None = None  # Dask scheduler address (None: local process pool)
    # when the whole-record rounds name nothing and the held-out error stays above the noise,
    # test the state-free laws on short windows started from the measured state (:mod:`.short_horizon`)
    short_horizon: bool = True
    # a study setting, not a user's: screen and fit round 1 even when no effect could pass on the
    # held-out data (:func:`accept.within_reach`), to measure what the best candidates gain on
    # null cases (tests/benchmarks/acceptance_study.py, the look-elsewhere margin)
    screen_always: bool = False


@dataclass
class Stage:
    """A model state of the diagnosis: machine, model, parameters, scores."""
    net: Netlist
    model: Model
    p: np.ndarray
    cost: float
    free: list[str]
    esr_train: dict[str, float]
    esr_validation: dict[str, float]
    Y_train: list[np.ndarray]
    Y_validation: list[np.ndarray]
    stderr: dict[str, float] = field(default_factory=dict)   # the fit's (inflated) standard errors, by name


@dataclass
class Setup:
    """Step 1's product: what every later step works on."""
    machine: str
    net: Netlist
    model: Model
    sensors: dict[str, str]
    nuisance: list[Nuisance]
    train: list[Experiment]
    validate: list[Experiment]
    outputs: list[str]
    noise: dict[str, float]          # validation noise floor, ESR %
    noise_sigma: dict[str, float]    # the same as a standard deviation (SI)
    inputs_start: dict[str, float]   # each input's first sample (mean over training): once per diagnosis

    @property
    def noise_total(self) -> float:
        return residuals.total(self.noise)


@dataclass
class Baseline:
    """Step 2's product."""
    stage: Stage
    fit: FitResult
    judged: list[dict]
    located: dict
    whiteness: dict
    found: list[dict]            # effects the base fit found (source: base_fit)
    n_eff: float                 # effective residual samples of the base fit
    restrained: Stage | None = None   # the base re-fitted with implausible values restrained (:mod:`.restrain`)
    restraints: dict = field(default_factory=dict)
    slow_spools: dict = field(default_factory=dict)   # spool time constants at their ceiling (:func:`.restrain.slow_spools`)
    grown: frozenset = frozenset()   # of ``restraints``: grown volumes and their oil's modulus (:func:`.restrain.grown_volumes`)


@dataclass
class Round:
    """Step 3's product: every candidate's row, and the accepted effect (or None)."""
    rows: list[dict]
    accepted: dict | None = None
    stage: Stage | None = None
    skipped: list[dict] = field(default_factory=list)
    ambiguous: dict | None = None    # the accepted effect and one the data cannot tell from it
    candidate: Candidate | None = None   # the accepted one's candidate (to rebuild it elsewhere: backward.backward)
    stopped: dict | None = None      # not run: the model is within reach of the noise floor (accept.within_reach)


@dataclass
class Diagnosis:
    data: dict
    base: Stage
    final: Stage
    train: list
    validate: list
    outputs: list[str]
    history: list = field(default_factory=list)
    proposed_experiments: list[str] = field(default_factory=list)   # YAML texts, one per ambiguity


def fit_status(progress, what: str):
    """identify's progress callback (simulations run, cost) as a status line of ``progress``."""
    if getattr(progress, "status", None) is None:
        return None
    return lambda n, cost, best: status(progress, f"{what}: {n} simulations, cost {best:.6g}")


def log(progress, msg):
    if progress:
        progress(msg)


def make_stage(net, model, p, cost, free, train, validate, outputs, stderr=None) -> Stage:
    Ytr = residuals.simulate_outputs(model, train, p)
    Yva = residuals.simulate_outputs(model, validate, p)
    return Stage(net, model, p, cost, free, residuals.esr_table(model, train, Ytr, outputs),
                 residuals.esr_table(model, validate, Yva, outputs), Ytr, Yva, dict(stderr or {}))


def stops_of(c) -> list[dict]:
    """A candidate's stop positions, as :func:`workers.withdraw_idle_stops` reads them."""
    return [{"name": p.name, "start": p.start, "seen": p.seen, "bounds": p.bounds, "scale": p.scale}
            for p in c.params if p.seen]


def context(su: Setup, stage: Stage, located: dict | None = None) -> Context:
    """The catalogue's view of ``stage``; with the base fit's ``located`` residual, the
    frequencies its spectra peak at (:func:`locate.residual_peaks`)."""
    ctx = context_of(su, stage.net, set(stage.free), stage.model)
    return replace(ctx, residual_peaks_hz=locate.residual_peaks(located)) if located else ctx


def context_of(su: Setup, net: Netlist, free: set[str], model: Model) -> Context:
    """What the catalogue looks at for this machine: the travel the training recordings show
    (ranges and masked ends, read through ``model``'s outputs), outputs, inputs at the start,
    and the travel every recording shows (where a stop the training never pressed must not
    sit)."""
    ranges, censored = travel.ends(model, su.train)
    held, _ = travel.ends(model, su.validate)
    recorded = {s: (min(r[0], held[s][0]), max(r[1], held[s][1])) if s in held else r for s, r in ranges.items()}
    return Context(net, free, ranges, locate.output_quantities(model), su.inputs_start, censored,
                   recorded_range=recorded, drawn=su.net)


def fmt_esr(table: dict) -> str:
    return ", ".join(f"{k} {v:.3g} %" for k, v in table.items())
