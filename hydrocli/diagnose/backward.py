"""Backward elimination: an earlier effect a later one makes unnecessary is withdrawn."""
from __future__ import annotations

from ..errors import HydroError
from ..model.builder import build_model
from ..netlist.model import Netlist
from . import accept, augment, baseline, residuals, workers
from .candidates import Candidate, catalogue
from .stage import Baseline, Settings, Setup, Stage, context_of, fit_status, log, make_stage


def backward(su: Setup, b: Baseline, stage: Stage, accepted: list[dict], built: dict, st: Settings,
             progress=None) -> tuple[Stage, list[dict], list[dict]]:
    """Backward elimination: once a later effect is in, every earlier one must still pass the
    presence test (:func:`accept.presence`: ΔBIC < 0 and a held-out gain beyond a later
    effect's band) against the model with the others only, re-identified with all its
    parameters free. The rounds add effects greedily, and the first round's winner is the best
    SINGLE stand-in for whatever is missing: a delay that lags the whole machine through a
    chain of first-order elements is first mimicked by a flexible mount (dev rotary lag
    cascade: mount ΔBIC −986 from the base, then the delay −8204 on top of it); once the delay
    is in, the mount explains nothing it does not. An earlier effect the data no longer need is
    withdrawn, the model without it carried on, and it is reported under ``withdrawn`` with
    its test. Two forms of one effect on one component build on each other and are not split.
    Returns (stage, accepted, withdrawn)."""
    acc = [a for a in accepted if a.get("source") == "candidate"]
    if len(acc) < 2:
        return stage, accepted, []
    later = acc[-1]
    for a in acc[:-1]:
        if a["effect"] == later["effect"] and a["component"] == later["component"]:
            continue
        reduced = without(su, b.stage.net, stage, [built[x["key"]] for x in acc if x is not a], st, progress,
                          f"{a['effect']} on '{a['component']}' beside {later['effect']}")
        if reduced is None:
            continue
        n_eff = residuals.effective_n(reduced.model, su.train, reduced.Y_train, su.outputs)
        val0, val1 = residuals.total(reduced.esr_validation), residuals.total(stage.esr_validation)
        dbic, gain, band, reasons = accept.presence(reduced.cost, stage.cost, len(built[a["key"]].params), n_eff,
                                                    val0, val1, su.noise_total, later=True)
        if not reasons:
            a["removal_gain"] = gain      # what it is worth beside the later ones (ranking.by_importance)
            continue
        log(progress, f"  withdrawn {a['effect']} on '{a['component']}': beside {later['effect']} "
                      f"{'; '.join(reasons)}")
        i = accepted.index(a)
        rest = accepted[:i] + accepted[i + 1:]
        nxt = next((x for x in rest[i:] if x.get("source") == "candidate"), None)
        if nxt is not None:           # the next effect now starts where the withdrawn one did
            nxt.update(esr_train_before=a["esr_train_before"], esr_validation_before=a["esr_validation_before"])
        later.update(esr_train_after=reduced.esr_train, esr_validation_after=reduced.esr_validation)
        gone = {"key": a["key"], "effect": a["effect"], "component": a["component"],
                "why": f"not needed beside {later['effect']} on '{later['component']}': {'; '.join(reasons)}",
                "delta_bic": dbic, "validation_gain": gain, "noise_band": band}
        return reduced, rest, [gone]
    return stage, accepted, []


def without(su: Setup, base_net: Netlist, stage: Stage, keep: list[Candidate], st: Settings, progress,
            what: str) -> Stage | None:
    """The base machine with the candidates ``keep`` only, re-identified with every parameter
    free from ``stage``'s values; None when they cannot be built without the one left out (a
    later effect built on its components) or cannot be simulated without it."""
    try:
        net = base_net
        for c in keep:
            net = _built_on(su, net, c)
        model = build_model(net)
    except Exception:
        return None
    log(progress, f"  is {what} still needed? re-identifying without it…")
    try:
        fit = baseline.identify(model, su.train, p_start=workers.warm_vector(model, stage.model.param_names, stage.p),
                                iterations=st.base_evals, threads=st.jobs, progress=fit_status(progress, "backward step"))
        net = augment.set_values(net, {n: fit.p[model.param_index(n)] for n in model.free_params})
        out = make_stage(net, model, fit.p, fit.cost, list(model.free_params), su.train, su.validate, su.outputs)
    except HydroError as exc:
        # without it the machine leaves its valid range on these records (a stroke overrun):
        # it is kept, as an effect the others cannot stand in for
        log(progress, f"  without it the model cannot simulate ({exc.problems[0].message}): kept")
        return None
    out.stderr = dict(zip(fit.names, baseline.inflated_stderr(
        fit, residuals.effective_n(model, su.train, out.Y_train, su.outputs))))
    return out


def _built_on(su: Setup, net: Netlist, c: Candidate) -> Netlist:
    """``net`` with candidate ``c`` added. A candidate offered on a machine that held the
    effect now left out can hang on that effect's components: a seal friction offered after a
    compliant mount acts between the rod and the mount's frame, a node the machine without the
    mount does not have. The same candidate (its key: effect, component, law) is then offered
    again by the catalogue on ``net`` and added as offered there; its parameters keep their
    names, so the fit starts from their fitted values. Without this the earlier effect could
    never be tested (dev lift, a seal pressed by both chambers: the mount accepted first stood
    in for it, the seal in round 2 took the held-out P1 from 0.347 to 0.023 %, and the mount,
    left untested, was named first)."""
    try:
        out = augment.reload(net, augment.text_of(c.build(net)))
        build_model(out)
        return out
    except Exception:
        model = build_model(net)
        ctx = context_of(su, net, set(model.free_params), model)
        again = next((x for x in catalogue(ctx)[0] if x.key == c.key), None)
        if again is None:
            raise
        return augment.reload(net, augment.text_of(again.build(net)))
