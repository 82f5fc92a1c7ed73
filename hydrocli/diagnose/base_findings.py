"""The base fit's own findings (:mod:`.findings`): judged on the base fit, judged again on the
final model (a value that stood in for an effect a candidate then modelled is withdrawn),
and the late ones the final model's fit still shows."""
from __future__ import annotations

from dataclasses import replace

from ..components import roles as R
from . import accept, findings, residuals
from .candidates import catalogue
from .sides import feeders, file_value
from .stage import Baseline, Setup, Stage, context, log


def base_fit_findings(su: Setup, stage: Stage, judged: list[dict], late: bool = False) -> list[dict]:
    """Effects whose parameter the file already has free from "off" and the fit moved, and
    entrained air the fit put into the chambers' volumes (:mod:`.findings`), judged on
    ``stage`` (the base fit, or the final model: :func:`still_found`). ``late``: instead the
    findings judged only on the final model, after the candidates (:func:`late_findings`)."""
    ctx = replace(context(su, stage), net=su.net, free=set())
    val = residuals.total(stage.esr_validation)
    model = stage.model

    tables = {}

    def gain_at(values: dict[str, float]):
        Y = residuals.simulate_outputs(model, su.validate, model.param_vector(values, base=stage.p))
        tables[frozenset(values)] = residuals.esr_table(model, su.validate, Y, su.outputs)
        off_total = residuals.total(tables[frozenset(values)])
        return off_total - val, accept.need(off_total, su.noise_total, selected=False)
    sides = feeders(replace(ctx, free=set(stage.free)))
    chambers = [findings.Chambers(a.name, tuple(a.params("dead_volumes")), a.param("bulk_modulus"), sides[a.name],
                                  file_value(ctx, a.param("bulk_modulus")))
                for a in ctx.parts(R.ACTUATOR)]
    if late:
        found = findings.undrawn_volume(judged, chambers, gain_at)
    else:
        offs = findings.off_values(catalogue(ctx)[0])
        found = (findings.base_fit_findings(judged, offs, lambda names: gain_at({n: offs[n].ref for n in names}))
                 + findings.fluid_compliance_excess(judged, chambers, gain_at))
    for f in found:
        # like a candidate's: the held-out ESR without the finding (its parameters back at the
        # file's values) and with it, the model the base fit (or the final one) is
        f["esr_validation_before"] = tables.get(frozenset(q["name"] for q in f["parameters"]), {})
        f["esr_validation_after"] = dict(stage.esr_validation)
    return found


def still_found(su: Setup, b: Baseline, final: Stage, accepted: list[dict], progress=None) -> list[dict]:
    """The base fit's findings (:func:`base_fit_findings`) judged again, by the same rules, on
    the final model. A base-fit value may stand in for an effect a candidate then modelled:
    chamber volumes grown ×4 to mimic a delayed command go back to the drawing's once the
    delay is in (dev EHA input delay: V_A0 ×4.3 → ×1.15). The finding is kept only while
    the final model still needs it; a finding that lets the base model run at all (stops at
    the recorded ends, :mod:`.runaway`) is not re-judged."""
    again = {finding_key(f) for f in base_fit_findings(su, final, judged_on(b, final))}
    keep = []
    for a in accepted:
        if a.get("source") == "base_fit" and "validation_gain" in a and finding_key(a) not in again:
            log(progress, f"  the base fit's {a['effect']} on '{a['component']}' is withdrawn: the final model "
                          "no longer needs it (it stood in for an effect the candidates then modelled)")
            continue
        keep.append(a)
    return keep


def finding_key(f: dict) -> tuple[str, str]:
    """What a base-fit finding is, whatever it was named (:func:`labelled`): its kind (grown
    volumes) or its effect (a parameter moved from "off"), and where."""
    return f.get("finding", f["effect"]), f["component"]


def judged_on(b: Baseline, final: Stage) -> list[dict]:
    """The base fit's parameter rows with the final model's values and standard errors."""
    return [dict(j, value=float(final.p[final.model.param_index(j["name"])]), stderr=final.stderr[j["name"]])
            for j in b.judged if j["name"] in final.stderr and j["name"] in final.model.param_names]


def late_findings(su: Setup, b: Baseline, final: Stage, accepted: list[dict], progress=None,
                  rows: list[dict] = ()) -> list[dict]:
    """Findings the final model's own fit still shows once the candidates had their chance
    (:func:`findings.undrawn_volume`): listed after them, never in place of one, and not when an
    accepted effect already adds fluid compliance (a line on the valve that feeds it, air).
    ``rows``: the last round's candidate rows, fitted on top of ``final`` (the model WITH the
    grown volume); they name the finding's reading (:func:`labelled`)."""
    judged = b.judged if final is b.stage else judged_on(b, final)
    if {a["effect"] for a in accepted} & {"line_dynamics", "entrained_air"}:
        return []
    out = []
    for f in base_fit_findings(su, final, judged, late=True):
        f = labelled(f, list(rows), progress, basis=ON_TOP)
        log(progress, f"  the fit found {f['effect']} on '{f['component']}' (validation gain "
                      f"{f['validation_gain']:.3g} % > {f['noise_band']:.3g} %)")
        out.append(f)
    return out


def volume_readings(su: Setup, b: Baseline, stage: Stage) -> frozenset:
    """The readings (a hose on that line, air trapped in that chamber) of the one-sided chamber
    volume ``stage``'s fit shows (:func:`late_findings` would list it), empty when it shows
    none. A round from ``stage`` is then fitted even when no effect could pass on the held-out
    data (:func:`accept.within_reach`), and fits each reading whatever it screens (``shortlist``'s
    ``readings``): the grown volume already holds most of what either does, so neither may
    screen among the best, and a finding whose readings were not both fitted keeps its default
    name unexamined (dev EHA, a pocket of air in chamber A, seed 136: V_A0 grown, the held-out
    error at the noise, no line fitted in the round, named ``line_dynamics`` unexamined)."""
    judged = b.judged if stage is b.stage else judged_on(b, stage)
    return frozenset(e for f in base_fit_findings(su, stage, judged, late=True)
                     for e in (f["effect"], *f.get("alternatives", [])))


FROM_DRAWING = ("from the drawn volumes", "fits the training data better than the grown volumes")
# ΔBIC beyond which one reading's evidence over the other's is "very strong" (Kass & Raftery
# 1995, J. Am. Stat. Assoc. 90, §3.2: a Bayes factor above 150)
DECISIVE_BIC = 10.0
ON_TOP = ("on top of the grown volume", "improves the training fit")


def labelled(finding: dict, rows: list[dict], progress=None, basis: tuple[str, str] = FROM_DRAWING,
             on_top: list[dict] = ()) -> dict:
    """A fluid-compliance finding named by what the training data say of its two readings.
    Grown volumes are a constant, pressure-independent compliance; free air softens with
    falling pressure, a hose adds its volume behind an inertance and a resistance. Each
    reading was fitted as a candidate (``rows``: its ΔBIC), either from the drawn volumes
    against the grown ones (``FROM_DRAWING``: the excess in every chamber,
    :func:`findings.fluid_compliance_excess`) or on top of the grown volume (``ON_TOP``: the
    one-sided excess found last, :func:`findings.undrawn_volume`). When held-out data cannot
    tell them apart (the grown volumes already predict to the noise, so no candidate passes),
    the form still can: the finding is named after its alternative when that one improves the
    training fit (ΔBIC < 0) and the finding's own effect does not. Dev rotary hose, single
    T-section, from the drawn volumes: line ΔBIC −1621, air +835 (the finding had said air).
    Dev rotary polytropic air (seed 34), one chamber ×1.55: on top of it air −1424, a line +66
    (the finding had said line: the softening at low pressure is what the volume lacks).
    ``on_top``: when neither improves from the drawn volumes, the readings fitted on top of
    the grown volumes (the round from the free base) decide by the same rule — what the
    constant compliance still lacks: a hose's inertance and loss, or air's softening at low
    pressure. Dev winch distributed hose (seed 44, motor volumes ×1.5–1.6): from the drawn
    volumes air +2105, the line +49; on top of the grown volumes the line −59, air +37.
    When neither decides, the name stays and the description says so (dev rotary distributed
    hose, seed 32: air +41, line +42).

    On top of the grown volume both readings are ADDITIONS to a constant compliance the model
    already has, so each one's ΔBIC measures what it adds that the constant lacks — and when
    both improve, the one whose evidence is decisively stronger (:data:`DECISIVE_BIC`) names
    the finding: dev EHA, a pocket of air in chamber A (seed 136, V_A0 ×2.7, held-out error at
    the noise): air −1131, a hose −58 (the finding had said hose). From the drawn volumes each
    reading must REPLACE the grown compliance, and the more flexible one may win by fitting
    other residual besides; there the name changes only against a reading that does not
    improve at all.

    When no reading improves anywhere (:func:`_replaces`), the grown volumes — a constant
    compliance — predict as well as anything, and the readings' ΔBIC from the drawn volumes
    still say which one REPRODUCES a constant compliance: a hose's volume is one, air's
    softens with falling pressure. The decisively lower names the finding (dev winch,
    distributed hose, seed 167, motor volumes ×1.7: the line +311, air +491; seed 44's hose
    above, decided on top, ranks the same from the drawing: +49 against +2105)."""
    def best(effect, rows_):
        fitted = [r for r in rows_ if r["effect"] == effect and r.get("fitted") and r.get("delta_bic") is not None]
        return min((r["delta_bic"] for r in fitted), default=None)
    alike = None
    improved = False
    for rows_, (where, better) in ((rows, basis), (on_top, ON_TOP)):
        own = best(finding["effect"], rows_)
        if own is None:
            continue
        fitted = [(alt, d) for alt in finding.get("alternatives", []) if (d := best(alt, rows_)) is not None]
        improved = improved or own < 0 or any(d < 0 for _, d in fitted)
        for alt, d_alt in fitted:
            if d_alt < 0 and (own >= 0 or (d_alt < own - DECISIVE_BIC and (where, better) == ON_TOP)):
                why = (f"{where} {alt} {better} (ΔBIC {d_alt:+.0f}), {finding['effect']} "
                       f"{'does not' if own >= 0 else 'decisively less'} ({own:+.0f})")
                log(progress, f"  the grown volumes are {alt} rather than {finding['effect']}: {why}")
                return _renamed(finding, alt, why)
        both = [(alt, d) for alt, d in fitted if d >= 0 and own >= 0]
        if both and alike is None:
            alike = (where, better, own, *both[0])
    if alike:
        where, better, own, alt, d_alt = alike
        if not improved and (where, better) == FROM_DRAWING:
            replaced = _replaces(finding, own, alt, d_alt, progress)
            if replaced is not None:
                return replaced
        # both readings fitted and neither improves on the grown volumes: the default name
        # stands, and the finding says the training data do not choose either
        return dict(finding, description=f"{finding['description']}; {where} neither reading {better} "
                                         f"({finding['effect']} ΔBIC {own:+.0f}, {alt} {d_alt:+.0f}): the "
                                         "training data do not tell them apart either")
    return finding


# what each reading's compliance is, said when it reproduces the grown volumes decisively better
CONSTANCY = {"line_dynamics": "a constant compliance, as a hose's volume is",
             "entrained_air": "a compliance that softens with falling pressure, as air's does"}


def _replaces(finding: dict, own: float, alt: str, d_alt: float, progress) -> dict | None:
    """The finding named by the reading that reproduces the grown volumes decisively better
    from the drawn volumes (ΔBIC more than :data:`DECISIVE_BIC` lower), when neither improves
    on them (:func:`labelled`); None when they are within the margin."""
    if abs(d_alt - own) <= DECISIVE_BIC:
        return None
    name = alt if d_alt < own else finding["effect"]
    other = finding["effect"] if name == alt else alt
    lo, hi = min(own, d_alt), max(own, d_alt)
    why = (f"from the drawn volumes neither reading fits the training data better than the grown volumes, "
           f"but {name} reproduces them decisively better (ΔBIC {lo:+.0f} against {other} {hi:+.0f}): the excess "
           f"is {CONSTANCY.get(name, name)}")
    log(progress, f"  the grown volumes are {name}: {why}")
    if name == finding["effect"]:
        return dict(finding, description=f"{finding['description']}; {why}")
    return _renamed(finding, alt, why)


def _renamed(finding: dict, alt: str, why: str) -> dict:
    """The finding named after its alternative ``alt``, its own effect now an alternative, and
    the description saying why."""
    others = [e for e in finding["alternatives"] if e != alt]
    return dict(finding, effect=alt, alternatives=[finding["effect"], *others],
                description=f"{finding['description']}; named {alt}: {why}")
