"""A base model that cannot follow the training recordings at all.

A closed-loop bench drives its actuator onto a stop the machine file does not have: the
controller winds up, the valve stays open, and the real actuator rests on the stop. Fed the
recorded command, the base model runs on until a chamber empties and the solver stops — at
every trial, so the base fit has nothing to work on. What an engineer does: put stops at the
ends of the travel the record shows and try again. When that lets the base simulate the
training recordings, the diagnosis starts from it and the end stop is a finding with
``source: base_fit`` (the base fit places and stiffens the stops; a stop the record never
presses is withdrawn out of reach, :func:`workers.withdraw_idle_stops`). When it does not,
the diagnosis stops with the solver's own message and what to check.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import HydroError
from ..experiments.initial import initial_state
from ..model.builder import build_model
from ..model.model import Model
from ..netlist.model import Netlist
from ..solve.simulate import simulate
from . import augment, residuals, workers
from .candidates import Candidate, Context, catalogue


def first_failure(model: Model, exps, p=None) -> str | None:
    """The first training experiment the model cannot simulate (its solver message), or None."""
    p = model.p0 if p is None else p
    for e in exps:
        try:
            simulate(model, e.inputs, e.t_out, p=p, x0=initial_state(model, e, p), opts=residuals.OPTS)
        except HydroError as exc:
            return f"'{e.name}': {exc.problems[0].message}"
    return None


@dataclass(frozen=True)
class Runaway:
    """The base machine with stops at the recorded ends, and why they were needed."""
    net: Netlist
    model: Model
    candidate: Candidate
    failure: str                # the base model's failure on the training recordings


def stops_if_needed(net: Netlist, model: Model, train, ctx: Context) -> Runaway | None:
    """None when the base simulates every training recording; else the machine with end
    stops (free, starting at the ends of the travel recorded) that does — or None when no
    end-stop candidate helps either (the caller's base fit then reports the failure)."""
    failure = first_failure(model, train)
    if failure is None:
        return None
    cands, _ = catalogue(ctx)
    # plain stops at both ends first (a cushion's metal stop holds one end only)
    for c in sorted((c for c in cands if c.effect == "end_stop"), key=lambda c: bool(c.variant)):
        # the probe values: stops just beyond the recorded ends, stiff
        aug = augment.set_values(c.build(net), {p.name: p.probe for p in c.params})
        m = build_model(aug)
        if first_failure(m, train) is None:
            return Runaway(aug, m, c, failure)
    return None


def finding(r: Runaway, estimates: dict[str, float], stderr: dict[str, float], withdrawn: list[str]) -> dict:
    """The end stop as an effect the base fit found (diagnosis.json ``accepted``)."""
    c = r.candidate
    return {"effect": c.effect, "component": c.component, "source": "base_fit",
            "parameters": workers.parameter_rows(c.params, estimates, stderr, withdrawn),
            "description": f"the base model cannot simulate the training recordings without stops ({r.failure}); "
                           f"with stops at the ends of the recorded travel it can: {c.description}"}
