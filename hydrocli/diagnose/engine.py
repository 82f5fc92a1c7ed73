"""``diagnose``: from a mismatch to the missing physics (DESIGN.md, "Diagnosis"), as a
pipeline of small typed steps:

1. :func:`prepare` — the machine with its measurement model (pressure-sensor lags) and
   nuisance parameters (valve spool dynamics) free, the experiments, the noise floors;
2. :func:`baseline_step` — re-identify the base model, judge its parameters, test and locate
   the residual (:mod:`.locate`, :mod:`.equations`), and read the effects the base fit itself
   found (:mod:`.findings`);
3. :func:`round_step` — build the candidate catalogue for THIS machine (:mod:`.candidates`),
   screen every candidate with a score test (:mod:`.workers`, :mod:`.stats`), re-identify the
   best few next to a control fit, accept the best that passes BIC, validation-beyond-noise
   and plausibility (:mod:`.accept`); repeated up to ``max_effects``;
4. :func:`conclude` — the verdict: ``missing_physics``, ``none``, or ``unexplained_mismatch``,
   and the JSON-ready record.
"""
from __future__ import annotations

import itertools
import time
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import DataError, HydroError, Problem
from ..experiments.experiment_file import load_all
from ..executor import executor
from ..identify.fit import sensitivities_available
from ..model.builder import build_model
from ..netlist.flatten import flat_doc, is_flat
from ..netlist.loader import load_doc, load_netlist
from . import (accept, augment, backward, base_findings, baseline, candidate_fits, design, findings, locate, nuisance,
               ranking, residuals, restrain, restrained, runaway, short_horizon, stats, travel, workers)
from .candidates import COMPLIANCES, SWITCHING, Candidate, catalogue
from .clock import StepClock
from .equations import located_equations
from .measurement import with_pressure_sensors
from .ranking import ALTERNATIVE
from .shortlist import after_wave, at_the_ends, creeping, shortlist
from .stage import (Baseline, Diagnosis, Round, Settings, Setup, Stage, context, context_of, fit_status, fmt_esr,
                    log, make_stage, stops_of)

CONTROL = "control: current model, same budget"
EXTRA_WAVES = 2     # further shortlists fitted when none passes and the mismatch stays unexplained (round_step)


def load_data(model, paths):
    """Every experiment the paths name (all of a multi-experiment file, as in identify). A
    modelled sensor and what it senses start from the sensor's first sample
    (:func:`hydrocli.experiments.initial.given_state`)."""
    return [e for p in paths for e in load_all(p, model)]


def _inputs_start(model, exps) -> dict:
    """Each machine input's value at the start, averaged over the training experiments."""
    return {n: float(np.mean([e.inputs.U[0, j] for e in exps])) for j, n in enumerate(model.input_names)}


# -- step 1 -------------------------------------------------------------------------------
def diagnosed_machine(machine, with_nuisance: bool = True):
    """(the machine the diagnosis works on, its pressure sensors, its nuisance parameters): the
    file flattened when it has includes or template instances — every candidate edits
    components of the main document, and a template instance's or an included file's exist
    only after loading (knuckle-boom crane: KeyError 'inner.dcv') — with the measurement model
    (:func:`.measurement.with_pressure_sensors`) and the valves' spool dynamics freed
    (:mod:`.nuisance`)."""
    net = load_netlist(machine)
    if not is_flat(net):
        net = load_doc(flat_doc(net), net.file)
    net, sensors = with_pressure_sensors(net)
    found = []
    if with_nuisance:
        free0 = {f"{c}.{p}" for c, d in net.components.items() for p, v in d.params.items() if v.free}
        net, found = nuisance.with_nuisance(net, free0)
    return net, sensors, found


def prepare(machine, train_paths, validate_paths, settings: Settings) -> Setup:
    net, sensors, found = diagnosed_machine(machine, settings.nuisance)
    model = build_model(net)
    train = load_data(model, train_paths)
    validate = load_data(model, validate_paths)
    outputs = [o for o in model.output_names
               if any(o in e.measured for e in train) and any(o in e.measured for e in validate)]
    if not outputs:
        raise DataError(Problem("no machine output is measured in both the training and the validation data",
                                hint=f"map recording columns to outputs ({', '.join(model.output_names)}) "
                                     "in the experiment files"))
    train, validate = residuals.focus(train, outputs), residuals.focus(validate, outputs)
    noise = {o: float(np.mean([stats.noise_esr(e.measured[o]) for e in validate if o in e.measured]))
             for o in outputs}
    sigma = {o: float(np.sqrt(noise[o] / 100.0 * np.mean([np.nanvar(e.measured[o]) for e in validate
                                                          if o in e.measured]))) for o in outputs}
    return Setup(str(machine), net, model, sensors, found, train, validate, outputs, noise, sigma,
                 _inputs_start(model, train))


# -- step 2 -------------------------------------------------------------------------------
def follow(su: Setup, progress=None) -> tuple[Setup, runaway.Runaway | None]:
    """The setup, with stops at the recorded ends of travel when the base model cannot
    simulate the training recordings without them (:mod:`.runaway`)."""
    ctx = context_of(su, su.net, set(su.model.free_params), su.model)
    run = runaway.stops_if_needed(su.net, su.model, su.train, ctx)
    if run is None:
        return su, None
    log(progress, f"the base model cannot simulate the training recordings ({run.failure}); stops placed at the "
                  f"ends of the recorded travel of '{run.candidate.component}' let it: the base fit starts from them")
    return replace(su, net=run.net, model=run.model), run


def baseline_step(su: Setup, st: Settings, progress=None, run: runaway.Runaway | None = None) -> Baseline:
    model, train, validate, outputs = su.model, su.train, su.validate, su.outputs
    log(progress, f"re-identifying the base model ({len(model.free_params)} free parameters) on "
                  f"{len(train)} training experiment(s)…")
    res0 = baseline.identify(model, train, iterations=st.base_evals, threads=st.jobs, progress=fit_status(progress, "base fit"))
    withdrawn = (workers.withdraw_idle_stops(residuals.objective(model, train), model, res0, stops_of(run.candidate))
                 if run is not None else [])
    base = make_stage(augment.set_values(su.net, dict(zip(res0.names, res0.estimates))), model, res0.p, res0.cost,
                      res0.names, train, validate, outputs)
    n_eff = residuals.effective_n(model, train, base.Y_train, outputs)
    judged = baseline.judge(model, res0, n_eff)
    log(progress, f"base model: train ESR {fmt_esr(base.esr_train)}; validation ESR {fmt_esr(base.esr_validation)}")
    where = locate.locate(model, train, base.Y_train, outputs, st.window_s)
    white = locate.whiteness(model, train, base.Y_train, outputs)
    where["equations"], why = located_equations(model, train[0], base.p)
    if why:
        log(progress, f"  the equation errors are not computed ({why})")
    found = base_findings.base_fit_findings(su, base, judged)
    if run is not None:
        found.insert(0, runaway.finding(run, dict(zip(res0.names, res0.estimates)),
                                        {j["name"]: j["stderr"] for j in judged}, withdrawn))
    for f in found:
        why = (f"validation gain {f['validation_gain']:.3g} % > {f['noise_band']:.3g} %" if "validation_gain" in f
               else "needed to simulate the training recordings at all")
        log(progress, f"  the base fit found {f['effect']} on '{f['component']}' ({why})")
    bounds, at_bound = _bounds(model, res0)
    ctx, est, file_values = context(su, base), dict(zip(res0.names, res0.estimates)), dict(zip(res0.names, res0.initial))
    lim = restrain.limits(ctx, est, bounds, file_values, at_bound)
    grown = restrain.grown_volumes(found, bounds, ctx, est)
    lim.update(grown)
    held = restrained.restrained_base(su, base, lim, st, progress) if lim else None
    return Baseline(base, res0, judged, where, white, found, n_eff, held, lim,
                    restrain.slow_spools(ctx, est, bounds, file_values), frozenset(grown))


def _bounds(model, res) -> tuple[dict[str, tuple[float, float]], set[str]]:
    """The fit's free parameters' bounds, and those its estimates ended at."""
    from ..identify.transforms import FreeParameters
    fp = FreeParameters.from_model(model, res.names)
    return ({n: (float(lo), float(hi)) for n, lo, hi in zip(res.names, fp.lo, fp.hi)},
            set(fp.at_bound(res.estimates)))


# -- step 3 -------------------------------------------------------------------------------
def round_step(su: Setup, stage: Stage, accepted: list[dict], round_: int, st: Settings, pool,
               located: dict, progress=None, floor: Stage | None = None, withdrawn: frozenset = frozenset(),
               readings: frozenset = frozenset()) -> Round:
    """One round from ``stage``. ``floor``: a model every candidate must beat as well — the
    free base when ``stage`` is the restrained one (:mod:`.restrain`). ``withdrawn``: keys of
    candidates accepted earlier and withdrawn since (:func:`backward`), not offered again.
    ``readings``: effects fitted whatever they screen (:func:`shortlist`), the readings of a
    grown chamber volume. The round ends before screening when no effect can pass
    (:func:`accept.within_reach`, from ``stage``'s held-out error: a restrained base's too),
    unless it has readings to fit: their fits name a base-fit finding all the same."""
    train, validate, outputs = su.train, su.validate, su.outputs
    cands, skipped = catalogue(context(su, stage, located))
    out = Round([], skipped=[{"effect": s.effect, "reason": s.reason} for s in skipped])
    first = _first_gain(accepted)
    later, val = first is not None, residuals.total(stage.esr_validation)
    if (not (st.screen_always and round_ == 0)
            and not accept.within_reach(val, su.noise_total, later, first) and not readings):
        need = accept.need(val, su.noise_total, later=later, first_gain=first)
        log(progress, f"  validation ESR {val:.3g} % is {val - su.noise_total:+.3g} % from the noise floor "
                      f"({su.noise_total:.3g} %): no {'further ' if later else ''}effect can gain "
                      f"the {need:.3g} % it needs — not screened")
        out.stopped = {"round": round_ + 1, "esr_validation": val, "noise_floor": su.noise_total, "noise_band": need}
        return out
    cands = offered(cands, accepted, set(withdrawn), st.only)
    texts = {}
    for c in cands:
        try:
            texts[c.key] = augment.text_of(c.build(stage.net))
        except Exception as exc:
            out.skipped.append({"effect": c.effect, "reason": f"cannot augment '{c.component}': {exc}"})
    cands = [c for c in cands if c.key in texts]
    if not cands:
        return out
    common = {"file": su.machine, "names": stage.model.param_names, "values": stage.p, "train": train,
              "outputs": outputs}
    drawing = {"drawing": _drawing(su)}
    n_eff = residuals.effective_n(stage.model, train, stage.Y_train, outputs)
    scores = _screen(stage, cands, texts, common, n_eff, pool, round_, progress)
    order = sorted(cands, key=lambda c: -scores[c.key]["dr2"])
    n_fit = st.top if round_ == 0 else max(1, st.top - 1)   # later rounds: residual already small
    ceiling = None if floor is None else residuals.total(floor.esr_validation)
    before = floor if floor is not None and residuals.total(floor.esr_validation) < residuals.total(
        stage.esr_validation) else stage
    remaining = [c for c in order if scores[c.key]["error"] is None]
    fits, base_ref, grad, passing, judged, imprecise, bounded, small = {}, {}, {}, [], {}, [], [], []
    extra = []    # a wave a mechanism asks for: the frictions (creeping), the stops (at_the_ends)
    for wave in itertools.count():   # the shortlist's waves, and those the mechanisms ask for, once each
        if wave > EXTRA_WAVES and not extra:
            break
        best = extra or shortlist(remaining, scores, n_fit, readings)
        if not best:
            break
        log(progress, ("  best: " if wave == 0 else "  next: ")
            + ", ".join(f"{c.key} ({100 * scores[c.key]['dr2']:.1f} %)" for c in best))
        grad.update({c.key: st.switching_gradient if c.effect in SWITCHING else "auto" for c in best})
        # one control per gradient in use: each candidate is compared with the current model
        # re-identified with the same budget AND the same Jacobian (a fair comparison)
        controls = [dict(common, **drawing, key=f"{CONTROL} ({g})", text=augment.text_of(stage.net),
                         validate=validate, max_evals=st.candidate_evals, n_eff=n_eff, gradient=g)
                    for g in sorted({grad[c.key] for c in best} - set(base_ref))]
        wave_fits = candidate_fits.fit_all(controls + [dict(common, **drawing, key=c.key, text=texts[c.key],
                                                            validate=validate, starts=scores[c.key].get("starts"),
                                                            transfers=scores[c.key].get("transfers"),
                                                            max_evals=st.candidate_evals, n_eff=n_eff,
                                                            gradient=grad[c.key], stops=stops_of(c),
                                                            each_base=c.effect in COMPLIANCES,
                                                            basins={q.name: q.shapes for q in c.params if q.basins})
                                                       for c in best], pool,
                                           progress=progress, what=f"round {round_ + 1}: candidate")
        wave_fits = {f["key"]: f for f in wave_fits}
        for g in {grad[c.key] for c in best} - set(base_ref):
            ctl = wave_fits.pop(f"{CONTROL} ({g})")
            ssr, val = stage.cost, residuals.total(stage.esr_validation)
            if floor is not None:
                # BIC against the better of the two bases; held-out gain against the restrained base,
                # with the free base's validation ESR as a ceiling (_judge): a plausible explanation
                # that predicts as well as the implausible fit is preferred to it
                ssr = min(ssr, floor.cost)
            if ctl.get("error") is None and ctl["cost"] < ssr:
                ssr, val = ctl["cost"], min(val, residuals.total(ctl["esr_validation"]))
            base_ref[g] = (ssr, val)
        fits.update(wave_fits)
        for c in best:
            ssr0, val0 = base_ref[grad[c.key]]
            row, passed = _judge(c, scores[c.key], fits.get(c.key), round_, ssr0, val0, n_eff, su.noise_total,
                                 accepted, located, ceiling)
            judged[c.key] = row
            if passed:
                passing.append((row["delta_bic"], c, fits[c.key]))
            elif row.get("imprecise"):
                imprecise.append((row["delta_bic"], c, fits[c.key]))
            elif row.get("bounded"):
                bounded.append((row["delta_bic"], c, fits[c.key]))
            elif row.get("small"):
                small.append((row["delta_bic"], c, fits[c.key]))
        if not later:
            passing += _specific(best, judged, fits, {c.key: base_ref[grad[c.key]][1] for c in best},
                                 su.noise_total, progress)
        # the screening is a linearisation at one probe: when none of its picks passes and the
        # held-out error is still far above the noise (the verdict would be an unexplained
        # mismatch), the next effects in its order are fitted before saying so (real Festo rig,
        # a runaway piston at pA ESR 95 %: the missing end stop screened fifth, 10 %, behind
        # four effects a fit could not use; with a residual that slow, n_eff 24, no score test
        # is significant, so the order alone decides)
        remaining = after_wave(remaining, set(fits))
        # an overdamped compliance stands for a force following the speed: once a round, since
        # that wave fits every friction left in ``remaining`` and after_wave then drops them all
        stand_ins, extra = creeping(best, fits, judged, remaining)
        if extra:
            log(progress, "  " + ", ".join(f"{c.effect}'s mode is overdamped (ζ = {z:.3g})" for c, z in stand_ins)
                + ": a mode damped that much rings at no frequency and may stand for friction that follows the speed; "
                  "fitting the friction laws too")
            continue
        mismatch = None if passing else findings.unexplained(stage.esr_validation, su.noise, located)
        if mismatch is None:
            break
        # the shortlist's waves done and still unexplained: where the error lies says what to fit
        # next — the stops, when it concentrates at the ends of the stroke (once: they are fitted)
        extra = at_the_ends(mismatch, remaining) if wave >= EXTRA_WAVES else []
        if extra:
            log(progress, f"  the unexplained error concentrates at the {locate.END_OF_STROKE}, where only a stop acts: fitting "
                          + ", ".join(c.key for c in extra))
    v_base = min([v for _, v in base_ref.values()] + [residuals.total(stage.esr_validation)])
    for c in order:   # the fitted ones were judged in their wave; the rest carry their screening
        if c.key not in judged:
            judged[c.key], _ = _judge(c, scores[c.key], None, round_, stage.cost, v_base, n_eff, su.noise_total,
                                      accepted, located, ceiling)
        out.rows.append(judged[c.key])
    lead = (ranking.dominant(imprecise, passing, judged) or ranking.dominant(bounded, passing, judged, alone=False)
            or ranking.dominant(small, passing, judged, alone=False))
    if lead is not None:
        row = judged[lead[1].key]
        why = ("a value ended at its bound" if row["bounded"] else "its size is below the floor worth naming"
               if row["small"] else "its size is poorly determined")
        row.update(passed=True, notes=row.pop("reasons"), reasons=[])
        log(progress, f"  {lead[1].effect} beats every {'precise' if row['imprecise'] else 'passing'} candidate on "
                      f"ΔBIC and held-out gain; {why} ({'; '.join(row['notes'])})")
    out.rows.sort(key=lambda d: (not d.get("passed", False), not d.get("fitted", False), -d["score"]))
    if not passing and lead is None:
        log(progress, "  no candidate passes BIC + validation + plausibility")
        return out
    band = accept.indistinct(v_base, su.noise_total)
    by_bic = min(passing, key=lambda x: x[0]) if passing else None
    ranked = ranking.rank_passing(passing, band) if passing else []
    passing = ranking.simplest(([lead] if lead is not None else []) + ranked, band)
    dbic_best, c, f = passing[0]
    close = ALTERNATIVE * min(p[0] for p in passing)   # ΔBIC that the training data barely tell from the best
    alternatives = [{"effect": c2.effect, "component": c2.component, "delta_bic": d2,
                     "esr_validation_after": f2["esr_validation"]}
                    for d2, c2, f2 in passing[1:] if c2.effect != c.effect and d2 <= close]
    # the rival: a passing candidate, or one whose size alone the quick fit left imprecise
    # (accept.judge), that these data do not tell from the winner
    rival = next(((d2, c2, f2) for d2, c2, f2 in passing[1:] + sorted(imprecise, key=lambda x: x[0])
                  if c2.effect != c.effect and d2 <= close and not ranking.separated(f, f2, band)), None)
    polished = {}
    if rival is not None:
        (dbic_best, c, f), rival, polished = _decide_polished(su, stage, passing[0], rival, texts, n_eff,
                                                              {k: base_ref[grad[k]][0] for k in (c.key, rival[1].key)},
                                                              band, st, progress)
        row = judged[c.key]
        if not row.get("passed"):     # the imprecise one won on its polished fit: named, its size flagged
            row.update(passed=True, notes=row.pop("reasons"), reasons=[])
    if rival is not None:
        out.ambiguous = _ambiguous(su, (dbic_best, c, f), rival, texts, progress, st.candidate_evals, band)
    over = _overruled(by_bic, c, f, band, progress)
    alternatives = [a for a in alternatives if not (over and a["effect"] == over["effect"])]
    new, f = polished[c.key] if c.key in polished else _polish(su, stage, c, texts[c.key], f, n_eff, st, progress)
    row = next(rw for rw in out.rows if rw["effect"] == c.effect and rw["component"] == c.component)
    out.accepted = {"key": c.key, "effect": c.effect, "component": c.component, "source": "candidate",
                    "description": c.description, "parameters": _new_params(c, f),
                    "delta_bic": row["delta_bic"], "esr_train_before": before.esr_train,
                    "esr_train_after": new.esr_train, "esr_validation_before": before.esr_validation,
                    "esr_validation_after": new.esr_validation, "alternatives": alternatives,
                    **({"held_out_over": over} if over else {}),
                    **({"specific_gain": {"gain": row["validation_gain"], "other": row["specific_over"],
                                          "band": row["noise_band"]}} if "specific_over" in row else {}),
                    **({("ended_at_bound" if row.get("bounded") else "below_naming_floor" if row.get("small")
                         else "size_poorly_determined"): row["notes"]} if row.get("notes") else {})}
    out.stage, out.candidate = new, c
    log(progress, f"  accepted {c.effect} on '{c.component}': validation ESR {fmt_esr(before.esr_validation)} "
                  f"→ {fmt_esr(new.esr_validation)}")
    return out


def offered(cands: list[Candidate], accepted: list[dict], withdrawn: set[str] = frozenset(),
            only: tuple[str, ...] = ()) -> list[Candidate]:
    """The candidates a round fits: not accepted or withdrawn before (by key), of the ``only``
    effects when given, and of an effect not accepted yet — except in its OTHER forms on the
    same component (a worn-seal orifice on top of the laminar leak): once the main effect is in,
    what remains is mostly its form mismatch, which the effect's own other forms should take
    before unrelated candidates mop it up. A volume the base fit grew (a finding with a
    ``finding`` kind) is a reading of a compliance, not its model: a hose named from it still has
    its inertance and resistance to add, so the effect's candidates stay on offer on top of it
    (dev winch, two 11 m hoses: the grown volumes, ×2.3, were named line_dynamics, and with the
    hoses' candidates withheld a valve underlap stood in for their flow-dependent pressure drop)."""
    done = {a["key"] for a in accepted if "key" in a} | set(withdrawn)
    modelled = {a["effect"] for a in accepted if not a.get("finding")}
    found = {(a["effect"], a["component"]) for a in accepted}
    return [c for c in cands if c.key not in done and (not only or c.effect in only)
            and (c.effect not in modelled or ((c.effect, c.component) in found and c.variant))]


def _overruled(by_bic, c, f: dict, band: float, progress) -> dict | None:
    """The training-BIC winner the held-out data overruled (:func:`ranking.rank_passing`: the
    named candidate predicts the held-out data better by more than the noise band), or None."""
    if by_bic is None or by_bic[1].effect == c.effect:
        return None
    v, v_bic = residuals.total(f["esr_validation"]), residuals.total(by_bic[2]["esr_validation"])
    if not v < v_bic - band:
        return None
    log(progress, f"  {c.effect} predicts the held-out data better than {by_bic[1].effect} (summed validation ESR "
                  f"{v:.3g} against {v_bic:.3g} %, noise band {band:.3g} %), which fits the training data better "
                  f"(ΔBIC {by_bic[0]:.0f}): the held-out data decide")
    return {"effect": by_bic[1].effect, "component": by_bic[1].component, "delta_bic": by_bic[0],
            "esr_validation_after": by_bic[2]["esr_validation"], "noise_band": band}


def _drawing(su: Setup) -> dict[str, float]:
    """The machine as drawn: the file's values of the base model's free parameters (measurement
    and nuisance parameters at their typical values), where candidate fits also start."""
    free = set(su.model.free_params)
    return {n: float(v) for n, v in zip(su.model.param_names, su.model.p0) if n in free}


def _screen(stage: Stage, cands: list[Candidate], texts: dict, common: dict, n_eff: float, pool, round_: int,
            progress) -> dict:
    """Score test of every candidate against the current residual."""
    obj = residuals.objective(stage.model, common["train"])
    if sensitivities_available(stage.model):
        # the current model's own parameter sensitivities, exact and in one run (identify's)
        r, B = obj.residuals_jacobian(stage.p, list(stage.free))
    else:
        r = obj.residuals(stage.p)
        idx = [stage.model.param_index(n) for n in stage.free]
        steps = [max(abs(stage.p[i]) * 1e-3, 1e-12) for i in idx]
        B = residuals.sensitivities(obj, stage.p, idx, steps, r)
    log(progress, f"round {round_ + 1}: screening {len(cands)} candidate(s)…")
    scr = workers.run_all(workers.screen_one, [dict(common, key=c.key, text=texts[c.key], params=c.params,
                                                    r=r, B=B, n_eff=n_eff) for c in cands], pool,
                          progress=progress, what=f"round {round_ + 1}: screened")
    return {s["key"]: s for s in scr}


def _judge(c: Candidate, score: dict, f: dict | None, round_: int, ssr0: float, val0: float, n_eff: float,
           noise_total: float, accepted: list[dict], where: dict, ceiling: float | None = None) -> tuple[dict, bool]:
    row = {"effect": c.effect, "component": c.component, "round": round_ + 1,
           "screening_explained": score["dr2"], "score": score["dr2"], "evidence": _evidence(c, score, where)}
    passed = False
    if f is not None and f.get("error") is None:
        first_gain = _first_gain(accepted)
        verdict = accept.judge(c, f, ssr0, n_eff, val0, residuals.total(f["esr_validation"]), noise_total,
                               later=first_gain is not None, first_gain=first_gain, ceiling=ceiling)
        row.update(score=max(1.0 - f["cost"] / ssr0, 0.0), fitted=True, **verdict,
                   esr_validation_after=f["esr_validation"], parameters=_new_params(c, f))
        row["evidence"] += (f"; re-identified: train SSR −{100 * row['score']:.1f} %, ΔBIC {verdict['delta_bic']:+.0f}, "
                            f"validation ESR {val0:.3g} → {residuals.total(f['esr_validation']):.3g} %")
        passed = verdict["passed"]
    elif f is not None:
        row.update(fitted=True, passed=False, reasons=[f["error"]])
    if score["error"]:
        row["error"] = score["error"]
    return row, passed


def _specific(best: list[Candidate], judged: dict, fits: dict, val0: dict, noise: float, progress) -> list:
    """The (ΔBIC, candidate, fit) of this wave's first-effect candidates that failed on the
    held-out band alone but whose gain no other effect's comes near (:func:`accept.specific_need`,
    against every candidate of another effect fitted in this round so far); their rows are
    marked passed, with the band they beat and the other effects' best gain."""
    out = []
    for c in best:
        row = judged[c.key]
        if not row.get("band_only"):
            continue
        other = accept.other_gain(c.effect, judged.values())
        band = accept.specific_need(val0[c.key], noise, other)
        if not row["validation_gain"] > band:
            continue
        row.update(passed=True, band_only=False, reasons=[], noise_band=band, specific_over=other)
        out.append((row["delta_bic"], c, fits[c.key]))
        log(progress, f"  {c.effect} on '{c.component}' gains {row['validation_gain']:.3g} % on the held-out data, "
                      f"no other effect gained more than {other:.3g} %: a gain specific to it (band {band:.3g} %)")
    return out


def _first_gain(accepted: list[dict]) -> float | None:
    """The held-out gain of the first effect a round accepted (None before one was): a later
    effect is judged against it (:func:`accept.need`)."""
    cand_acc = [a for a in accepted if a.get("source") == "candidate"]
    if not cand_acc:
        return None
    return residuals.total(cand_acc[0]["esr_validation_before"]) - residuals.total(cand_acc[0]["esr_validation_after"])


def _decide_polished(su: Setup, stage: Stage, win, rival, texts: dict, n_eff: float, ssr0: dict, band: float,
                     st: Settings, progress):
    """Two passing candidates whose quick fits (``candidate_evals`` iterations each) the data do
    not tell apart: both are polished (all parameters free, :func:`_polish`) and judged again
    on the polished fits, by the round's own ranking (:func:`ranking.rank_passing`, then
    :func:`ranking.simplest`: still alike, the special case is named). A quick fit
    stops where the budget ends, and two candidates reach it at different distances from
    their optimum: a hose whose fit must tune a volume, an inertance and a loss together can
    still be short of its minimum where a rod–load link, one stiffness, is already at its own.
    Comparing them there would compare budgets, not explanations. Returns the winner
    (ΔBIC, candidate, fit), the rival when they are still not told apart (else None), and
    {key: (stage, fit)} of the polished models."""
    polished, again = {}, []
    for _, c, f in (win, rival):
        new, fp = _polish(su, stage, c, texts[c.key], f, n_eff, st, progress)
        polished[c.key] = (new, fp)
        again.append((stats.delta_bic(ssr0[c.key], fp["cost"], n_eff, len(c.params)), c,
                      dict(fp, esr_validation=new.esr_validation, p=new.p, param_names=new.model.param_names)))
    first, second = ranking.simplest(ranking.rank_passing(again, band), band)
    log(progress, f"  polished: {first[1].effect} ΔBIC {first[0]:+.0f}, validation "
                  f"{residuals.total(first[2]['esr_validation']):.3g} %; {second[1].effect} ΔBIC {second[0]:+.0f}, "
                  f"validation {residuals.total(second[2]['esr_validation']):.3g} %")
    still = second[0] <= ALTERNATIVE * first[0] and not ranking.separated(first[2], second[2], band)
    return first, (second if still else None), polished


def _ambiguous(su: Setup, win, rival, texts: dict, progress, refit_iterations: int = 0,
               band: float | None = None) -> dict:
    """Two candidates the data cannot tell apart, and the test that would (:mod:`.design`)."""
    import tempfile
    models = []
    for d, c, f in (win, rival):
        m = workers.model_from_text(texts[c.key], su.machine)
        models.append((c.effect, m, workers.warm_vector(m, f["param_names"], f["p"])))
    log(progress, f"  {win[1].effect} and {rival[1].effect} fit alike: designing a test that separates them…")
    with tempfile.TemporaryDirectory() as tmp:
        prop = design.propose(models[0], models[1], su.net, su.train, su.noise_sigma, Path(tmp),
                              Path(su.machine).stem, refit_iterations=refit_iterations, band=band)
    entry = {"effects": [win[1].effect, rival[1].effect], "components": [win[1].component, rival[1].component],
             "delta_bic": [win[0], rival[0]],
             "esr_validation_after": [win[2]["esr_validation"], rival[2]["esr_validation"]],
             # both a spring in the force balance (a rope, a mount, a rod–load link): with the masses
             # free, the same two-mass system as the actuator's own transducers see it
             "two_mass": all(c.effect in COMPLIANCES and c.equation == "force" for c in (win[1], rival[1]))}
    if prop is not None:
        entry.update(proposed_experiment={k: v for k, v in prop.items() if k != "text"},
                     proposed_experiment_text=prop["text"])
    return entry


def _polish(su: Setup, stage: Stage, c: Candidate, text: str, f: dict, n_eff: float, st: Settings, progress):
    """The accepted model re-identified with all its parameters free (exact sensitivities),
    kept only if it fits the training data better AND does not predict the held-out data
    worse than the candidate's own fit (early stopping on held-out data: with every nuisance
    parameter free a polish can trade them against the new effect's parameters)."""
    aug = augment.reload(stage.net, text)
    model_c = build_model(aug)
    p_c = workers.warm_vector(model_c, f["param_names"], f["p"])
    free_c = list(model_c.free_params)
    log(progress, f"  polishing the model with {c.effect} (all {len(free_c)} free parameters)…")
    try:
        pol = baseline.identify(model_c, su.train, p_start=p_c, iterations=st.base_evals, threads=st.jobs,
                                progress=fit_status(progress, f"polishing {c.effect}"))
        if pol.cost < f["cost"]:
            Yva = residuals.simulate_outputs(model_c, su.validate, pol.p)
            val = residuals.total(residuals.esr_table(model_c, su.validate, Yva, su.outputs))
            if val <= residuals.total(f["esr_validation"]):
                p_c, f = pol.p, dict(f, cost=pol.cost, names=pol.names, estimates=pol.estimates.tolist(),
                                     stderr=baseline.inflated_stderr(pol, n_eff).tolist())
    except HydroError as exc:
        # the polish is a refinement: when its simulations leave the model's valid range (dev
        # lift_cbv sharp overlap, seed 47: the piston overran the stroke near the training
        # record's end with every parameter free) the candidate's own fit stands
        log(progress, f"  the polish cannot simulate ({exc.problems[0].message}): keeping {c.effect}'s own fit")
    aug = augment.set_values(aug, {n: p_c[model_c.param_index(n)] for n in free_c})
    return make_stage(aug, model_c, p_c, f["cost"], free_c, su.train, su.validate, su.outputs,
                      dict(zip(f["names"], f["stderr"]))), f


# -- step 4 -------------------------------------------------------------------------------
def conclude(su: Setup, b: Baseline, final: Stage, accepted: list[dict], rows: list[dict], skipped: list[dict],
             train_paths, validate_paths, t_start: float) -> dict:
    effects = ranking.by_importance(accepted)
    mismatch = None if effects else findings.unexplained(final.esr_validation, su.noise, b.located)
    verdict = "missing_physics" if effects else ("unexplained_mismatch" if mismatch else "none")
    data = {
        "machine": su.machine, "train": [str(p) for p in train_paths], "validate": [str(p) for p in validate_paths],
        "verdict": verdict,
        "effects": effects or ["none"],
        "located": b.located,
        "tests": {"whiteness": b.whiteness, "noise_esr_validation": su.noise, "n_eff": b.n_eff},
        "esr_train_base": b.stage.esr_train, "esr_validation_base": b.stage.esr_validation,
        "esr_train_final": final.esr_train, "esr_validation_final": final.esr_validation,
        "base_parameters": b.judged,
        "measurement_model": {s: {"sensed_node": n, **_param(b.judged, f"{s}.tau")} for s, n in su.sensors.items()},
        "nuisance_parameters": nuisance.report(su.nuisance, b.judged),
        "ranking": rows, "skipped": skipped,
        "accepted": [{k: v for k, v in a.items() if k != "key"} for a in accepted],
        "runtime_s": time.perf_counter() - t_start,
    }
    if mismatch:
        beyond = findings.beyond_training(travel.output_ranges(su.model, su.train), travel.output_ranges(su.model, su.validate))
        data["unexplained"] = {**mismatch, **({"beyond_training": beyond} if beyond else {})}
    if b.restrained is not None:
        rs = b.restrained
        data["restrained_base"] = {
            "why": f"{restrain.WHY}: tested which missing effect it stands for",
            "parameters": [{"name": n, "bounds": list(lim), "free_fit": float(b.stage.p[b.stage.model.param_index(n)]),
                            "restrained_fit": float(rs.p[rs.model.param_index(n)])} for n, lim in b.restraints.items()],
            "esr_train": rs.esr_train, "esr_validation": rs.esr_validation}
    return data


def diagnose(machine, train_paths, validate_paths, settings: Settings | None = None, progress=None) -> Diagnosis:
    st = settings or Settings()
    t_start = time.perf_counter()
    clock = StepClock(last=t_start)
    su, run = follow(prepare(machine, train_paths, validate_paths, st), progress)
    clock.lap("loading and the measurement model")
    b = baseline_step(su, st, progress, run)
    clock.lap("base fit" + (" and the restrained base" if b.restrained is not None else ""))
    stage, accepted, rows, skipped, history, ambiguous = b.stage, list(b.found), [], [], [], []
    built, withdrawn = {}, []      # the accepted candidates by key; the effects withdrawn since
    last = []                      # the rows of a round that accepted nothing: fitted on top of the final model
    stopped = None                 # why the last round fitted nothing: the model is at the noise floor
    parallel = st.jobs > 1 or st.scheduler
    with (executor(st.jobs, st.scheduler) if parallel else nullcontext(None)) as pool:
        for round_ in range(st.max_effects):
            rnd, drawn = None, None
            if round_ == 0 and b.restrained is not None:
                # which effect does the implausible value stand for? Tried first; when none
                # beats the free base, the round runs from the free base as usual
                rnd, b, accepted, tried = _restrained_first(su, b, stage, accepted, st, pool, progress, clock)
                rows.extend(tried)
                if rnd.accepted is None:
                    log(progress, "  nothing beats the free base with the implausible values restrained: "
                                  "the round runs from the free base")
                    rnd, drawn = None, rnd.rows
            if rnd is None:
                # the readings of a grown-volume finding on trial (from the restrained round), or
                # of the one-sided volume this stage's fit still shows: fitted whatever they screen
                readings = _readings(accepted) if drawn is not None else base_findings.volume_readings(su, b, stage)
                rnd = round_step(su, stage, accepted, round_, st, pool, b.located, progress,
                                 withdrawn=frozenset(w["key"] for w in withdrawn), readings=readings)
                clock.lap(f"round {round_ + 1}")
                rows.extend(rnd.rows)
                if drawn is not None:
                    accepted = _name_grown(accepted, drawn, rnd.rows, progress)
                if round_ == 0 and rnd.accepted is None and b.slow_spools:
                    spool, b_spool, acc = _spool_round(su, b, stage, accepted, st, pool, progress,
                                                       "nothing passes from the free base, whose spool time constant is pressed "
                                                       "against its tolerance's ceiling")
                    clock.lap("round 1 from the restrained spools")
                    if spool is not None:
                        rnd, b, accepted = spool, b_spool, acc
                        rows.extend(rnd.rows)
            if round_ == 0:
                skipped = rnd.skipped
            if rnd.ambiguous:
                ambiguous.append(rnd.ambiguous)
            if rnd.accepted is None:
                last, stopped = rnd.rows, rnd.stopped
                break
            accepted.append(rnd.accepted)
            built[rnd.accepted["key"]] = rnd.candidate
            history.append(stage)
            stage = rnd.stage
            stage, accepted, out = backward.backward(su, b, stage, accepted, built, st, progress)
            clock.lap(f"round {round_ + 1}: the earlier effects re-checked")
            withdrawn += out
        short = None      # the short-horizon test's record, when it ran
        if short_horizon.needed(st, accepted, stage.esr_validation, su.noise, b.located):
            entry, new, short = short_horizon.round_(su, stage, b.located, st, pool, progress)
            clock.lap("short-horizon test")
            if entry is not None:
                accepted.append(entry)
                history.append(stage)
                stage = new
    if stage is not b.stage:
        accepted = base_findings.still_found(su, b, stage, accepted, progress)
    accepted = accepted + base_findings.late_findings(su, b, stage, accepted, progress, last)
    clock.lap("base-fit findings re-checked")
    data = conclude(su, b, stage, accepted, rows, skipped, train_paths, validate_paths, t_start)
    data["timings"] = clock.report()
    if stopped:
        data["stopped_at_noise_floor"] = stopped
    if short is not None:
        data["short_horizon"] = short
    if withdrawn:
        data["withdrawn"] = [{k: v for k, v in w.items() if k != "key"} for w in withdrawn]
    if ambiguous:
        data["ambiguous"] = [{k: v for k, v in a.items() if k != "proposed_experiment_text"} for a in ambiguous]
    return Diagnosis(data, b.stage, stage, su.train, su.validate, su.outputs, history,
                     [a.get("proposed_experiment_text", "") for a in ambiguous])


def _restrained_first(su: Setup, b: Baseline, free: Stage, accepted: list[dict], st: Settings, pool, progress,
                      clock: StepClock):
    """Round 1 from the restrained base (:func:`_restrained_round`) and, when it names a slow
    transducer while a spool pressed against its ceiling stayed free and the model with the
    transducer still presses it beyond the datasheet's tolerance
    (:func:`restrain.lag_left_to_the_spool`), round 1 again with that spool restrained too
    (:func:`_spool_round`), whose answer stands when it accepts anything (a slow transducer
    among the candidates). Returns (the round, the baseline it ran from, the accepted list to
    carry on, every row fitted)."""
    rnd, acc = _restrained_round(su, b, free, accepted, st, pool, progress)
    clock.lap("round 1 from the restrained base")
    rows = list(rnd.rows)
    done = rnd.stage      # the model with the accepted effect: where its spool ended
    after = None if done is None else {n: float(done.p[done.model.param_index(n)])
                                       for n in b.slow_spools if n in done.model.param_names}
    if rnd.accepted is not None and restrain.lag_left_to_the_spool(rnd.accepted["effect"], b.slow_spools,
                                                                   b.restraints, after):
        why = (f"{rnd.accepted['effect']} explains the readings' lag, not the spool's pressed against its "
               "tolerance's ceiling, which delays the motion")
        spool, b_spool, acc_spool = _spool_round(su, b, free, accepted, st, pool, progress, why)
        clock.lap("round 1 from the restrained spools")
        if spool is not None:
            return spool, b_spool, acc_spool, rows + spool.rows
    return rnd, b, acc, rows


def _restrained_round(su: Setup, b: Baseline, free: Stage, accepted: list[dict], st: Settings, pool, progress):
    """Round 1 from the restrained base (:mod:`.restrain`): which effect does the implausible
    value stand for? Every candidate must beat the ``free`` base as well. Grown chamber volumes
    (the base fit's fluid-compliance finding) are among the implausible values: their finding
    steps aside while the candidates that could be that compliance (air, a hose) compete, and
    gives way when one wins. Returns (the round, the accepted list to carry on: the finding,
    when nothing won, still to be named by its readings' fits, :func:`_name_grown`)."""
    excess = [a for a in accepted if a.get("finding") == findings.EXCESS_FINDING]
    rest = [a for a in accepted if a not in excess]
    # the finding's readings (air, a hose) are fitted whatever they screen: the grown volumes
    # leave them nothing to screen for, and base_findings.labelled names the finding by their fits
    readings = _readings(excess)
    rnd = round_step(su, b.restrained, rest, 0, st, pool, b.located, progress, floor=free, readings=readings)
    if rnd.accepted is not None and excess:
        log(progress, f"  the chambers' grown volumes are explained by {rnd.accepted['effect']} on "
                      f"'{rnd.accepted['component']}': the volume finding gives way to it")
        file_bounds, _ = _bounds(b.stage.model, b.fit)
        # the volumes and the oil's bulk modulus behind them (restrain.grown_volumes)
        rnd.stage = restrained.released(su, rnd.stage, {n: file_bounds[n] for n in b.grown if n in file_bounds}, st, progress,
                                        also_from=free)
        rnd.accepted.update(esr_train_after=rnd.stage.esr_train, esr_validation_after=rnd.stage.esr_validation)
        return rnd, rest
    return rnd, accepted


def _readings(accepted: list[dict]) -> frozenset:
    """The effects a grown-volume finding may be (its effect and alternatives: air, a hose)."""
    return frozenset(e for a in accepted if a.get("finding") == findings.EXCESS_FINDING
                     for e in (a["effect"], *a.get("alternatives", [])))


def _name_grown(accepted: list[dict], drawn: list[dict], on_top: list[dict], progress) -> list[dict]:
    """The grown-volume finding named by its readings' fits from the drawn volumes (``drawn``:
    the restrained round's rows) and, when those do not decide, on top of the grown volumes
    (``on_top``: the free base's round, :func:`base_findings.labelled`)."""
    return [base_findings.labelled(a, drawn, progress, on_top=on_top) if a.get("finding") == findings.EXCESS_FINDING
            else a for a in accepted]


def _spool_round(su: Setup, b: Baseline, free: Stage, accepted: list[dict], st: Settings, pool, progress, why: str):
    """Round 1 again, from a base whose spool time constants are restrained to the datasheet's
    tolerance (:func:`restrain.slow_spools`), with the other restraints kept, when the round
    from the free base, with a spool pressed against its ceiling, accepted nothing — the slow
    spool may HIDE a lag the file lacks (a delayed command), predicting the held-out data so
    close to the noise that no candidate gains what it must — or when the round from the
    restrained base named a slow transducer, which cannot explain a slow spool
    (:func:`restrain.lag_left_to_the_spool`). ``why`` says which, in the log. Every candidate
    must beat the free base (:func:`_restrained_round`). Returns (the round, or None when the
    restrained base cannot be simulated or the round accepted nothing; the baseline it ran from;
    the accepted list to carry on)."""
    lim = {**b.restraints, **b.slow_spools}
    names = ", ".join(f"{n} = {free.p[free.model.param_index(n)]:.4g}" for n in b.slow_spools)
    log(progress, f"  {why} ({names}): re-identifying with the spool restrained to the datasheet's tolerance, to "
                  "test which missing lag it hides…")
    held = restrained.restrained_base(su, free, lim, st, progress)
    if held is None:
        return None, b, accepted
    b_spool = replace(b, restrained=held, restraints=lim)
    rnd, acc = _restrained_round(su, b_spool, free, accepted, st, pool, progress)
    if rnd.accepted is None:
        return None, b, accepted
    return rnd, b_spool, acc


def _param(judged, name):
    d = next((j for j in judged if j["name"] == name), None)
    return {"tau_s": d["value"], "stderr_s": d["stderr"]} if d else {}


def _new_params(c, f) -> list[dict]:
    est = dict(zip(f["names"], f["estimates"]))
    se = dict(zip(f["names"], f["stderr"]))
    return workers.parameter_rows(c.params, est, se, f.get("withdrawn") or ())


def _evidence(c, score, where) -> str:
    top = where["regimes"][0]["regime"] if where.get("regimes") else "all regimes"
    return (f"{c.description}: its signature explains {100 * score['dr2']:.1f} % of the remaining output residual "
            f"(score test p = {score['p_value']:.2g}); residual concentrates in '{top}'")
