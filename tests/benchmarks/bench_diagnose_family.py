"""Score ``hydrocli.diagnose`` on the concealed-effect family (experiments/family).

    python tests/benchmarks/bench_diagnose_family.py --data DIR --split dev
        [--machines lift rotary ...] [--effects E ...] [--limit N] [--jobs 2]
        [--json OUT.json] [--per-case]

DIR is what ``python -m experiments.family.generate --out DIR`` wrote (DIR/<machine>/<case>/
with base.yaml, train.csv/json, validate.csv/json). Each case is diagnosed from its base.yaml
with train.csv for training and validate.csv held out; the sidecar is read only to score.

Prints the confusion matrix (true effect x named top-1), per-effect recall and precision,
the null false-positive rate, per-machine figures, recall by effect-ESR bucket (< 1 %,
>= 1 %; a case's effect ESR is the mean of its train and validate 'size'), the validation
ESR before -> after (and whether it came down to noise + 20 % of the before-gap), and the
time per case; writes a JSON of the results.

HELD-OUT DISCIPLINE: with ``--split heldout`` nothing case by case is printed or written
(no progress lines, no per-case rows, the JSON holds aggregates only) unless ``--per-case``
is given - the held-out part is scored when the work is done, never inspected while tuning.
"""
from __future__ import annotations

import argparse
import json
import re
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

GAP_FRACTION = 0.2          # "after <= noise + 20 % of the before-gap"
BUCKETS = (("<1%", 0.0, 1.0), (">=1%", 1.0, float("inf")))


def find_cases(data: Path, split: str, machines, effects, limit):
    out = []
    for side in sorted(data.glob("*/*/train.json")):
        if side.parent.name.startswith("."):      # a case the generator is still writing
            continue
        d = json.loads(side.read_text())
        if split != "all" and d.get("split") != split:
            continue
        if machines and d["machine"] not in machines:
            continue
        if effects and d["effect"] not in effects:
            continue
        out.append(side.parent)
    out = _round_robin(out)
    return out[:limit] if limit else out


def _round_robin(folders: list[Path]) -> list[Path]:
    """The cases one machine after another (eha, lift, rotary, eha, …), each machine's in name
    order: a run stopped early has covered every machine alike."""
    by = {}
    for f in folders:
        by.setdefault(f.parent.name, []).append(f)
    queues = [by[k] for k in sorted(by)]
    return [q[i] for i in range(max((len(q) for q in queues), default=0)) for q in queues if i < len(q)]


def top1(data: dict) -> str:
    """The diagnosis' first named effect; 'none' / 'unexplained_mismatch' from the verdict."""
    eff = [e for e in (data.get("effects") or []) if e != "none"]
    if eff:
        return eff[0]
    v = data.get("verdict", "none")
    return "unexplained_mismatch" if v == "unexplained_mismatch" else "none"


def case_truth(folder: Path) -> dict:
    tr = json.loads((folder / "train.json").read_text())
    va = json.loads((folder / "validate.json").read_text())
    size = 0.5 * (tr["effect_esr_percent"]["size"] + va["effect_esr_percent"]["size"])
    vm = va.get("signal_map", {"P1": "P1", "P2": "P2", "x": "x", "v": "v"})
    noise = {vm[k]: v for k, v in va["noise_esr_percent"].items() if k in vm}
    return {"effect": tr["effect"], "form": tr["form"], "machine": tr["machine"], "case": tr["case"],
            "size": size, "noise": noise}


def _closes(before: float, after: float, noise: float) -> bool:
    """after <= noise + GAP_FRACTION (before - noise)."""
    return bool(after <= noise + GAP_FRACTION * max(before - noise, 0.0) + 1e-12)


def gap_closed(before: dict, after: dict, noise: dict) -> bool:
    """:func:`_closes` on every output that has a noise figure."""
    return all(_closes(before[o], after[o], n) for o, n in noise.items() if o in before and o in after)


def gap_closed_mean(before: dict, after: dict, noise: dict) -> bool:
    """The same rule on the case's ESR averaged over its outputs (a second, looser reading of the
    criterion: an output where the effect barely shows no longer decides on the last per cent
    of its noise estimate). Printed beside the per-output figure, which stays the headline."""
    outs = [o for o in noise if o in before and o in after]
    if not outs:
        return False
    return _closes(*(statistics.mean(d[o] for o in outs) for d in (before, after, noise)))


def model_before(data: dict) -> dict:
    """Validation ESR of the model WITHOUT the first named effect: the base fit's, or, when the
    base fit itself found the effect (``source: base_fit``: a leak coefficient moved from 0, a
    chamber volume grown), the base fit with that finding's parameters back at the file's
    values — the base already contains the finding, and its ESR is the 'after'."""
    first = (data.get("accepted") or [{}])[0]
    return first.get("esr_validation_before") or data.get("esr_validation_base", {})


def run_case(folder: Path, jobs: int, progress, screen_always: bool = False) -> dict:
    from hydrocli.diagnose import Settings, diagnose
    t = case_truth(folder)
    t0 = time.perf_counter()
    try:
        d = diagnose(folder / "base.yaml", [folder / "train.csv"], [folder / "validate.csv"],
                     Settings(jobs=jobs, screen_always=screen_always), progress=progress)
        data = d.data
        err = None
    except Exception as exc:                      # one failing case must not stop the bench
        data, err = {}, f"{type(exc).__name__}: {exc}"
    wall = time.perf_counter() - t0
    before = model_before(data)
    after = data.get("esr_validation_final", {})
    named = top1(data) if err is None else "error"
    return {**t, "named": named, "named_all": data.get("effects", []), "verdict": data.get("verdict"),
            "ambiguous": data.get("ambiguous", []), "esr_before": before, "esr_after": after,
            "base_parameters": [{k: b.get(k) for k in ("name", "value", "initial", "stderr")}
                                for b in data.get("base_parameters", [])],
            "gap_closed": gap_closed(before, after, t["noise"]) if err is None else False,
            "gap_closed_mean": gap_closed_mean(before, after, t["noise"]) if err is None else False,
            "resolvable": resolvable(data) if err is None else None,
            "seconds": wall, "error": err, "candidates": _candidate_rows(data), "timings": data.get("timings", []),
            "noise_validation": (data.get("tests") or {}).get("noise_esr_validation", {}),
            "n_eff_validation": {o: w.get("n_eff") for o, w in
                                 ((data.get("tests") or {}).get("whiteness") or {}).items()}}


def resolvable(data: dict) -> bool:
    """Whether the base fit leaves an effect room to pass on the held-out data at all: the
    engine's own test (``accept.within_reach``) on the base fit's summed validation ESR and the
    held-out noise floor. A case whose effect the machine file's free parameters absorb (a
    winch's pressure-loaded seal friction taken into its Coulomb friction under a constant hook
    load) is not; its effect ESR, measured with every base parameter at the truth's, says
    nothing of that. Reported beside the effect-ESR figures, not instead of them."""
    from hydrocli.diagnose.accept import within_reach
    base = data.get("esr_validation_base") or {}
    noise = (data.get("tests") or {}).get("noise_esr_validation") or {}
    return within_reach(sum(base.values()), sum(noise.get(o, 0.0) for o in base))


def _candidate_rows(data: dict) -> list[dict]:
    """Every fitted candidate's acceptance figures and fitted values (dev study of acceptance rules
    offline; the parameter names tell the forms of one effect apart)."""
    keep = ("effect", "component", "round", "passed", "reasons", "delta_bic", "validation_gain",
            "noise_band", "esr_validation_after", "screening_explained")
    return [{**{k: r.get(k) for k in keep}, "parameters": {q["name"]: q.get("value") for q in r.get("parameters") or []}}
            for r in data.get("ranking", []) if r.get("fitted")]


def _pct(a, b):
    return f"{100.0 * a / b:5.1f} % ({a}/{b})" if b else "   —"


def aggregate(rows: list[dict]) -> dict:
    eff_rows = [r for r in rows if r["effect"] != "none"]
    nulls = [r for r in rows if r["effect"] == "none"]
    truths = sorted({r["effect"] for r in rows})
    named = sorted({r["named"] for r in rows})
    conf = {t: dict(Counter(r["named"] for r in rows if r["effect"] == t)) for t in truths}
    per_effect = {}
    for e in sorted(set(truths) | set(named)):
        tp = sum(1 for r in rows if r["effect"] == e and r["named"] == e)
        n_true = sum(1 for r in rows if r["effect"] == e)
        n_named = sum(1 for r in rows if r["named"] == e)
        # a null has no gap to close: counted for effects only
        closed = None if e == "none" else sum(1 for r in rows if r["effect"] == e and r["named"] == e and r["gap_closed"])
        per_effect[e] = {"n": n_true, "recall": tp / n_true if n_true else None,
                         "precision": tp / n_named if n_named else None, "tp": tp, "named": n_named,
                         "closed": closed}
    by_machine = {}
    for m in sorted({r["machine"] for r in rows}):
        er = [r for r in eff_rows if r["machine"] == m]
        nr = [r for r in nulls if r["machine"] == m]
        big = [r for r in er if r["size"] >= 1.0]
        room = [r for r in big if r.get("resolvable")]
        mr = [r for r in rows if r["machine"] == m]
        by_machine[m] = {"effect_cases": len(er), "top1": sum(r["named"] == r["effect"] for r in er),
                         "effect_cases_ge1": len(big), "top1_ge1": sum(r["named"] == r["effect"] for r in big),
                         "resolvable_ge1": len(room), "top1_resolvable_ge1": sum(r["named"] == r["effect"] for r in room),
                         "nulls": len(nr), "nulls_none": sum(r["named"] == "none" for r in nr),
                         "closed": sum(bool(r["gap_closed"]) for r in er if r["named"] == r["effect"]),
                         "seconds_mean": statistics.mean(r["seconds"] for r in mr)}
    buckets = {}
    for name, lo, hi in BUCKETS:
        b = [r for r in eff_rows if lo <= r["size"] < hi]
        buckets[name] = {"n": len(b), "top1": sum(r["named"] == r["effect"] for r in b)}
    right = [r for r in eff_rows if r["named"] == r["effect"]]
    secs = [r["seconds"] for r in rows]
    return {
        "n_cases": len(rows), "n_effect_cases": len(eff_rows), "n_null": len(nulls),
        "top1_correct": len(right),
        "null_false_positive_rate": (sum(r["named"] != "none" for r in nulls) / len(nulls)) if nulls else None,
        "confusion": conf, "per_effect": per_effect, "per_machine": by_machine, "esr_buckets": buckets,
        "gap_closed_among_right": {"n": len(right), "closed": sum(r["gap_closed"] for r in right),
                                   "closed_mean": sum(bool(r.get("gap_closed_mean")) for r in right)},
        "errors": sum(r["error"] is not None for r in rows),
        "seconds": {"mean": statistics.mean(secs) if secs else None,
                    "median": statistics.median(secs) if secs else None,
                    "max": max(secs) if secs else None, "total": sum(secs)},
        "seconds_by_step": seconds_by_step(rows),
    }


def step_kind(step: str) -> str:
    """A diagnosis's step (diagnosis.json ``timings``) by kind: every "round N" is a round,
    every restrained base's round one kind, every re-check of earlier effects one kind."""
    if step.startswith("base fit"):
        return "base fit"
    if step.startswith("round 1 from the restrained"):
        return "rounds from a restrained base"
    if step.startswith("round") and "re-checked" in step:
        return "earlier effects re-checked"
    if re.fullmatch(r"round \d+", step):
        return "rounds"
    return step


def seconds_by_step(rows) -> dict[str, float]:
    """Total wall seconds of every case's steps, by :func:`step_kind`, largest first."""
    tot: dict[str, float] = {}
    for r in rows:
        for t in r.get("timings") or []:
            k = step_kind(t["step"])
            tot[k] = tot.get(k, 0.0) + t["seconds"]
    return dict(sorted(tot.items(), key=lambda kv: -kv[1]))


def print_report(agg: dict):
    conf, pe = agg["confusion"], agg["per_effect"]
    cols = sorted({n for row in conf.values() for n in row})
    short = {c: c[:10] for c in cols}
    print("\nConfusion matrix (rows: true effect, columns: named top-1)")
    print(f"{'':30s}" + "".join(f"{short[c]:>11s}" for c in cols))
    for t in sorted(conf):
        print(f"{t:30s}" + "".join(f"{conf[t].get(c, 0) or '.':>11}" for c in cols))
    print("\nPer effect: recall (top-1) / precision / held-out gap closed among those named right")
    for e, s in pe.items():
        if s["n"] or s["named"]:
            rec = f"{s['recall']:.2f}" if s["recall"] is not None else "—"
            pre = f"{s['precision']:.2f}" if s["precision"] is not None else "—"
            gap = "" if s["closed"] is None else f"  gap closed {s['closed']}/{s['tp']}"
            print(f"  {e:30s} n={s['n']:3d}  recall {rec:>5s}  precision {pre:>5s}{gap}")
    fp = agg["null_false_positive_rate"]
    print(f"\nNull cases: {agg['n_null']}, false-positive rate "
          f"{'—' if fp is None else f'{100 * fp:.1f} %'}")
    print("\nPer machine: top-1 on effect cases | on effect ESR >= 1 % | nulls answered none | gap closed "
          "among those named right | mean time | on ESR >= 1 % where the base fit left room (within reach)")
    for m, s in agg["per_machine"].items():
        print(f"  {m:10s} {_pct(s['top1'], s['effect_cases'])} | {_pct(s['top1_ge1'], s['effect_cases_ge1'])} | "
              f"{_pct(s['nulls_none'], s['nulls'])} | {_pct(s['closed'], s['top1'])} | {s['seconds_mean']:.0f} s | "
              f"{_pct(s.get('top1_resolvable_ge1', 0), s.get('resolvable_ge1', 0))}")
    print("\nBy effect ESR bucket (top-1):")
    for b, s in agg["esr_buckets"].items():
        print(f"  {b:5s} {_pct(s['top1'], s['n'])}")
    g = agg["gap_closed_among_right"]
    print(f"\nValidation ESR after <= noise + {int(GAP_FRACTION * 100)} % of the before-gap, among cases "
          f"named right: {_pct(g['closed'], g['n'])} on every output; "
          f"{_pct(g.get('closed_mean', 0), g['n'])} on the ESR averaged over the outputs")
    s = agg["seconds"]
    if s["mean"] is not None:
        print(f"Time per case: mean {s['mean']:.0f} s, median {s['median']:.0f} s, max {s['max']:.0f} s "
              f"(total {s['total'] / 60:.1f} min); errors: {agg['errors']}")
    by = agg.get("seconds_by_step") or {}
    if by:
        whole = sum(by.values())
        print("Where the time goes: " + ", ".join(f"{k} {100 * v / whole:.0f} %" for k, v in by.items()
                                                 if v >= 0.005 * whole))


def _fmt_esr(before, after):
    return ", ".join(f"{k} {before[k]:.2f}→{after.get(k, float('nan')):.2f}" for k in list(before)[:4])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, required=True)
    ap.add_argument("--split", choices=["dev", "heldout", "all"], default="dev")
    ap.add_argument("--machines", nargs="+", default=None)
    ap.add_argument("--effects", nargs="+", default=None)
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--cases", nargs="+", default=None, help="only cases whose name contains one of these")
    ap.add_argument("--skip", type=Path, nargs="+", default=None, help="skip the cases of these results JSONs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path, default=None, help="results JSON (default DATA/bench_<split>.json)")
    ap.add_argument("--per-case", action="store_true", help="held-out: print and store per-case rows too")
    ap.add_argument("--screen-always", action="store_true",
                    help="dev study: fit round 1's candidates even where no effect could pass (null margins)")
    a = ap.parse_args(argv)
    blind = a.split == "heldout" and not a.per_case
    cases = find_cases(a.data, a.split, a.machines, a.effects, None)
    if a.cases:
        cases = [c for c in cases if any(k in c.name for k in a.cases)]
    if a.skip:
        missing = [str(f) for f in a.skip if not f.is_file()]
        if missing:   # e.g. `--skip rotary`: a machine is not a results file (use --machines)
            ap.error(f"--skip takes results JSONs of earlier runs; not a file: {', '.join(missing)}")
        done = {r["case"] for f in a.skip for r in json.loads(f.read_text()).get("cases", [])}
        cases = [c for c in cases if c.name not in done]
    cases = cases[:a.limit] if a.limit else cases
    if not cases:
        print(f"no {a.split} cases under {a.data}", file=sys.stderr)
        return 2
    print(f"{len(cases)} {a.split} case(s) under {a.data}" + (" (held-out: aggregates only)" if blind else ""),
          flush=True)
    rows = []
    out = a.json or (a.data / f"bench_{a.split}.json")
    for k, folder in enumerate(cases, 1):
        prog = None if blind else (lambda m, c=folder.name: print(f"  [{c}] {m}", file=sys.stderr, flush=True))
        r = run_case(folder, a.jobs, prog, a.screen_always)
        rows.append(r)
        if blind:
            print(f"  {k}/{len(cases)} done", flush=True)
        else:
            mark = "OK " if r["named"] == r["effect"] else "-- "
            print(f"{mark}{r['case']:60s} size {r['size']:5.2f} % named {r['named']:28s} "
                  f"{_fmt_esr(r['esr_before'], r['esr_after'])}  {r['seconds']:.0f} s"
                  + (f"  ERROR {r['error']}" if r["error"] else ""), flush=True)
        _write(out, a, rows, blind, done=k == len(cases))   # after every case: a stopped run keeps its figures
    print_report(aggregate(rows))
    print(f"\nresults → {out}")
    return 0


def _write(out: Path, a, rows: list[dict], blind: bool, done: bool) -> None:
    payload = {"split": a.split, "data": str(a.data), "complete": done, "aggregate": aggregate(rows)}
    if not blind:
        payload["cases"] = rows
    from hydrocli.fileio import write_text_atomic
    write_text_atomic(out, json.dumps(payload, indent=1, default=str) + "\n")


if __name__ == "__main__":
    sys.exit(main())
