"""Outputs of a diagnosis: diagnosis.json, augmented.yaml and the plain-language console
summary (which output, where, which regime, which effect, ESR before → after)."""
from __future__ import annotations

import math
from pathlib import Path

from ..fileio import json_text
from ..netlist import yamldoc as Y
from . import augment, clock
from .findings import Z_MIN


def write_json(diag, path: Path) -> None:
    """diagnosis.json, strict JSON (NaN and ±inf as null), written atomically."""
    Y.write_atomic(path, json_text(diag.data))


def write_proposals(diag, out_dir: Path) -> list[Path]:
    """Each proposed discriminating experiment as ``proposed_experiment_N.yaml`` (named in
    diagnosis.json's ``ambiguous`` entries)."""
    paths = []
    for i, (amb, text) in enumerate(zip(diag.data.get("ambiguous", []), diag.proposed_experiments), 1):
        if not text:
            continue
        path = Path(out_dir) / f"proposed_experiment_{i}.yaml"
        Y.write_atomic(path, text)
        amb.setdefault("proposed_experiment", {})["file"] = path.name
        paths.append(path)
    return paths


def write_augmented(diag, path: Path) -> None:
    """The final machine (accepted effects as real components/options, identified values)."""
    text = augment.text_of(diag.final.net)
    head = (f"# augmented by 'hydro diagnose': effects {', '.join(diag.data['effects'])}; pressure sensors carry\n"
            f"# their identified lag (measurement model). Base machine: {diag.data['machine']}\n")
    Y.write_atomic(path, head + text)


TWO_MASS = ("Both put a spring between the actuator and a second mass: with the masses free they give the actuator's "
            "own transducers the same force-to-motion response (one two-mass system), so no input separates them; a "
            "sensor on the far side of the spring does: an accelerometer or position on the load (hook, tip) or on "
            "the actuator's housing.")


def console_summary(diag) -> str:
    d = diag.data
    lines = []
    loc = d["located"]
    outs = sorted(loc["outputs"].items(), key=lambda kv: -kv[1])
    if outs:
        o, share = outs[0]
        lines.append(f"Base model re-identified: validation ESR {_tab(d['esr_validation_base'])}.")
        conc = [r for r in loc["regimes"] if r["concentration"] > 1.2][:2]
        where = " and ".join(f"{r['regime']} ({100 * r['share']:.0f} % of the error in {100 * r['time_share']:.0f} % "
                             f"of the time)" for r in conc)
        lines.append(f"The error is largest in {o} ({100 * share:.0f} % of the residual) and "
                     + (f"concentrates in {where}." if where else "is spread over all regimes."))
        eq = loc.get("equations") or {}
        if eq:
            s, e = max(eq.items(), key=lambda kv: kv[1]["relative_rms"])
            lines.append(f"The {e['balance']} carries the largest equation error (RMS {e['relative_rms']:.2g} × the "
                         f"RMS of the measured rate).")
    bad = [p for p in d["base_parameters"] if p["implausible"]]
    for p in bad[:4]:
        lines.append(f"Parameter {p['name']} = {p['value']:.4g}: {p['why']}.")
    for m, info in d.get("measurement_model", {}).items():
        if "tau_s" in info:
            lines.append(f"Pressure sensor on '{info['sensed_node']}': lag {1e3 * info['tau_s']:.2f} ms "
                         "(measurement model, not counted as an effect).")
    lines += nuisance_lines(d.get("nuisance_parameters", {}))
    if d["accepted"]:
        for a in d["accepted"]:
            if a.get("source") == "base_fit" and "validation_gain" not in a:     # stops needed to simulate at all
                pars = ", ".join(f"{p['name']} = {p['value']:.3g}" + (" (withdrawn: never pressed)" if p.get("withdrawn")
                                                                      else f" ± {p['stderr']:.2g}")
                                 for p in a["parameters"])
                lines.append(f"{a['effect'].replace('_', ' ').capitalize()} on '{a['component']}' is present: "
                             f"{a['description']} ({pars}).")
                continue
            if a.get("source") == "base_fit":
                pars = ", ".join(f"{p['name']} = {p['value']:.3g} ± {p['stderr']:.2g} (file: {p['file_value']:.3g})"
                                 for p in a["parameters"])
                lines.append(f"{a['effect'].replace('_', ' ').capitalize()} on '{a['component']}' is present: the base "
                             f"fit found it ({pars}); switching it off costs {a['validation_gain']:.3g} % validation "
                             f"ESR (noise band {a['noise_band']:.3g} %).")
                if a.get("finding"):      # grown chamber volumes: what they are, and what else they could be
                    lines.append(f"  {a['description'][0].upper()}{a['description'][1:]}.")
                    for alt in a.get("alternatives", []):
                        lines.append(f"  It could also be {alt.replace('_', ' ')} (the held-out data do not tell them apart).")
                continue
            if a.get("source") == "short_horizon":
                lines.extend(_short_horizon(a))
                continue
            o = max(a["esr_validation_before"], key=lambda k: a["esr_validation_before"][k]
                    - a["esr_validation_after"][k])
            pars = ", ".join(f"{p['name']} = {p['value']:.3g} ± {p['stderr']:.2g}" for p in a["parameters"])
            lines.append(f"{a['effect'].replace('_', ' ').capitalize()} on '{a['component']}' was missing "
                         f"({pars}); adding it cut validation ESR of {o} from "
                         f"{a['esr_validation_before'][o]:.3g} % to {a['esr_validation_after'][o]:.3g} % "
                         f"(ΔBIC {a['delta_bic']:+.0f}).")
            if a.get("size_poorly_determined"):
                lines.append(f"  Its size is poorly determined ({'; '.join(a['size_poorly_determined'])}): these "
                             "data show the effect is there, not how large it is.")
            if a.get("ended_at_bound"):
                lines.append(f"  It fits best with a value at the end of its plausible range "
                             f"({'; '.join(a['ended_at_bound'])}): the effect is there, its lumped form renders "
                             "it only approximately; no candidate within its range did as well.")
            if a.get("below_naming_floor"):
                lines.append(f"  Its size is below what is usually worth naming ({'; '.join(a['below_naming_floor'])}), "
                             "but it explains these data better than every effect of a nameable size.")
            if a.get("specific_gain"):
                g = a["specific_gain"]
                lines.append(f"  Its held-out gain ({g['gain']:.3g} %) is smaller than the look-elsewhere margin but "
                             f"specific to it: no other effect fitted gained more than {g['other']:.3g} % "
                             f"(band {g['band']:.3g} %).")
            if a.get("held_out_over"):
                h = a["held_out_over"]
                lines.append(f"  {h['effect'].replace('_', ' ').capitalize()} on '{h['component']}' fits the training "
                             f"data better (ΔBIC {h['delta_bic']:+.0f}) but predicts the held-out data worse (summed "
                             f"validation ESR {sum(h['esr_validation_after'].values()):.3g} %, noise band "
                             f"{h['noise_band']:.3g} %): the held-out data decide.")
            for alt in a.get("alternatives", []):
                lines.append(f"  Nearly as good: {alt['effect'].replace('_', ' ')} on '{alt['component']}' "
                             f"(ΔBIC {alt['delta_bic']:+.0f}); these data barely tell the two apart.")
    for w in d.get("withdrawn", []):
        lines.append(f"{w['effect'].replace('_', ' ').capitalize()} on '{w['component']}', accepted in an earlier "
                     f"round, was withdrawn: {w['why']}.")
    for amb in d.get("ambiguous", []):
        a, b = amb["effects"]
        prop = amb.get("proposed_experiment")
        lines.append(f"Ambiguous: {a.replace('_', ' ')} and {b.replace('_', ' ')} explain these data about equally "
                     f"well (ΔBIC {amb['delta_bic'][0]:+.0f} against {amb['delta_bic'][1]:+.0f}).")
        if prop:
            z = ", ".join(f"{o} {v:.1f} σ" for o, v in sorted(prop["z"].items(), key=lambda kv: -kv[1])[:3])
            held = prop.get("discrimination_held")
            how = (f" even after re-fitting {b.replace('_', ' ')} to it (χ² {prop['discrimination']:.3g}; "
                   f"{held:.3g} with both held at their fits)") if held is not None else ""
            if prop.get("decisive", True):
                lines.append(f"  A test that separates them: {prop['description']} ({prop.get('file', '')}); predicted "
                             f"difference between the two models: {z}{how}. Record it and diagnose again with it added.")
            else:
                lines.append(f"  No designed test separates them beyond the noise band once {b.replace('_', ' ')} is "
                             f"re-fitted: the best, {prop['description']} ({prop.get('file', '')}), would leave an ESR "
                             f"gap of {prop['esr_gap']:.2g} % against a band of {prop['band']:.2g} %{how}. "
                             + (TWO_MASS if amb.get("two_mass") else
                                "With these inputs the two are not distinguishable; a test at other operating points "
                                "(pressure levels, loads) is needed."))
    if not d["accepted"] and d["verdict"] == "unexplained_mismatch":
        u = d.get("unexplained", {})
        outs = ", ".join(f"{o} {v['esr_validation']:.3g} % (noise {v['noise_floor']:.2g} %)"
                         for o, v in u.get("outputs", {}).items())
        regs = ", ".join(r["regime"] for r in u.get("regimes", []))
        lines.append(f"Unexplained mismatch: no candidate passes, yet the validation error stays above the noise in "
                     f"{outs}" + (f", concentrated in {regs}" if regs else "") + ". The model misses something the "
                     "catalogue cannot express (or a fixed parameter is far off).")
        for o, r in u.get("beyond_training", {}).items():
            lines.append(f"  The held-out recordings reach {o} {r['validate'][0]:.4g} … {r['validate'][1]:.4g}, beyond "
                         f"the training's {r['train'][0]:.4g} … {r['train'][1]:.4g}: what is missing may act only "
                         "where training never went (an end stop, a position-dependent load) — no fit to these "
                         "training data can find it. Add a training recording that covers that range.")
    elif not d["accepted"] and d.get("stopped_at_noise_floor"):
        stop = d["stopped_at_noise_floor"]
        lines.append(f"No missing physics found: the base model predicts the held-out data to the noise (validation "
                     f"ESR {stop['esr_validation']:.3g} % against a noise floor of {stop['noise_floor']:.3g} %), so no "
                     f"effect could gain the {stop['noise_band']:.3g} % it must; no candidate was screened.")
    elif not d["accepted"]:
        best = d["ranking"][0] if d["ranking"] else None
        tail = f" (best candidate {best['effect']}: {'; '.join(best.get('reasons', [])) or 'not re-identified'})" \
            if best else ""
        lines.append("No missing physics found: no candidate improved both BIC and held-out validation ESR beyond "
                     f"the noise band{tail}.")
    lines.append(f"Verdict: {d['verdict']} ({', '.join(d['effects'])}); {d['runtime_s']:.0f} s.")
    if d.get("timings"):
        lines.append(clock.line(d["timings"], d["runtime_s"]))
    return "\n".join(lines)


def nuisance_lines(params: dict) -> list[str]:
    """The summary's advice on the nuisance parameters (:func:`.nuisance.report`) the base fit
    moved more than 10 % or to a bound: correct the file where the move is determined
    (``Z_MIN`` standard errors), say the data are silent where it is not (a valve the
    recordings never command, a crane's idle jib, ended at a bound with no sensitivity)."""
    lines = []
    for n, info in params.items():
        if not (info.get("at_bound") or abs(info["change_percent"]) > 10):
            continue
        se = info.get("stderr")
        if se is None or not math.isfinite(se) or se <= 0 or abs(info["value"] - info["file_value"]) < Z_MIN * se:
            lines.append(f"Nuisance parameter {n}: not determined by these data (keep the file's value).")
        else:
            bound = f", at its {info['at_bound']} bound" if info.get("at_bound") else ""
            lines.append(f"Nuisance parameter {n}: {info['value']:.3g} against the file's {info['file_value']:.3g} "
                         f"({info['change_percent']:+.0f} %{bound}): consider correcting the file.")
    return lines


def _short_horizon(a: dict) -> list[str]:
    """An effect named by the short-horizon test (:mod:`.short_horizon`)."""
    sh = a["short_horizon"]
    pars = ", ".join(f"{p['name']} = {p['value']:.3g}" for p in a["parameters"])
    before, after = (sum(a[k].values()) for k in ("esr_validation_before", "esr_validation_after"))
    lines = [f"{a['effect'].replace('_', ' ').capitalize()} on '{a['component']}' was missing ({pars}): over "
             f"{sh['windows_validation']} held-out windows of {1e3 * sh['window_s']:.0f} ms, each started from the "
             f"measured state, it predicts {100 * sh['gain_validation']:.0f} % better than the base model (paired "
             f"t-test p = {sh['p_value']:.2g}).",
             f"  Over the whole record no simulation follows the machine (validation ESR {before:.3g} % → "
             f"{after:.3g} %): the motion is a cycle (stick–slip, say) whose phase a replay of the whole record loses."]
    for alt in a.get("alternatives", []):
        lines.append(f"  Also better on the windows, by less: {alt['effect'].replace('_', ' ')} on "
                     f"'{alt['component']}' ({100 * alt['gain_validation']:.0f} %).")
    return lines


def _tab(t: dict) -> str:
    return ", ".join(f"{k} {v:.3g} %" for k, v in t.items())
