"""What other validation bands would name in round 1, read offline from a family bench's results.

    python tests/benchmarks/acceptance_study.py RESULTS.json [--kappa 1 0.5 0.25 0]

RESULTS.json is what ``bench_diagnose_family.py --split dev --json RESULTS.json`` wrote (it
keeps every fitted candidate's ΔBIC, validation gain and per-output validation ESR). For each
factor κ the held-out rule of ``diagnose.accept`` is replayed with the band

    need = max(κ · Σ noise ESR, MIN_REL · (val0 − Σ noise ESR))

(κ = ``accept.LOOK_ELSEWHERE`` is the diagnosis' rule) and every other reason a candidate
failed is kept, and a candidate failing that band passes on a gain specific to it as the
engine's does (``accept.specific_need``, against the best gain of another effect's round-1
candidate); among the round-1 candidates that pass, the lowest ΔBIC is named. Only round 1
is replayed (later rounds start from a model the bench did not keep), and val0 is the base's
validation ESR (the engine uses the better of the base and its control re-fit), so the rule's
κ may differ from the bench's own answer on a few cases.

The specific margin: every round-1 candidate that fails only on the look-elsewhere band, of a
WRONG effect or of a null, with its gain beyond the other effects' best as a share of the floor —
what ``accept.SPECIFIC`` must stay above.

The null cases' margin: for each null, the largest held-out gain, as a share of the noise
floor, of a round-1 candidate that passes everything but the band — what the look-elsewhere
margin must stay above. A null the engine did not screen (its base already within reach of
the floor) has no candidates: run the bench with ``--screen-always`` to fit them anyway.
Dev results only: never run it on held-out results.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from hydrocli.diagnose.accept import LOOK_ELSEWHERE, MIN_REL, SPECIFIC, other_gain, specific_need  # noqa: E402


def other_reasons(cand: dict) -> list[str]:
    """Why a candidate failed, the held-out band aside: BIC, plausibility, precision, ceiling."""
    return [r for r in (cand.get("reasons") or []) if "noise band" not in r]


def noise_floor(row: dict) -> float:
    """The case's summed held-out noise ESR over the outputs its base was scored on."""
    noise = row.get("noise_validation") or {}
    return sum(noise.get(o, 0.0) for o in row["esr_before"])


def round1(row: dict) -> list[dict]:
    return [c for c in row.get("candidates") or [] if c.get("round") == 1 and c.get("validation_gain") is not None]


def passes(cand: dict, row: dict, kappa: float, specific: bool = True) -> bool:
    if other_reasons(cand):
        return False
    val0, floor = sum(row["esr_before"].values()), noise_floor(row)
    if cand["validation_gain"] > max(kappa * floor, MIN_REL * max(val0 - floor, 0.0)):
        return True
    return specific and cand["validation_gain"] > specific_need(val0, floor, other_gain(cand["effect"], round1(row)))


def specific_margins(rows: list[dict]) -> list[tuple[float, str, str]]:
    """(gain beyond the other effects' best / floor, case, effect) of every round-1 candidate
    of a wrong effect or of a null that the engine judged on the look-elsewhere band alone: it
    failed on the band only, or passed with a band below the margin (on a specific gain). One
    that passed the margin itself is the ordinary rule's business (and its case's val0 may not
    be the base's: a grown-volume finding's round starts from the finding)."""
    out = []
    for r in rows:
        floor, cands = noise_floor(r), round1(r)
        if floor <= 0:
            continue
        for c in cands:
            on_band = not c.get("passed") or c.get("noise_band", 0.0) < 0.9 * LOOK_ELSEWHERE * floor
            if c["effect"] == r["effect"] or other_reasons(c) or not on_band:
                continue
            out.append(((c["validation_gain"] - other_gain(c["effect"], cands)) / floor, r["case"], c["effect"]))
    return sorted(out, reverse=True)


def null_margin(row: dict) -> float | None:
    """The largest round-1 held-out gain / noise floor of a candidate that passes everything but
    the band (None: no such candidate was fitted)."""
    floor = noise_floor(row)
    gains = [c["validation_gain"] for c in row.get("candidates") or [] if c.get("round") == 1
             and c.get("validation_gain") is not None and not other_reasons(c)]
    return max(gains) / floor if gains and floor > 0 else None


def named(row: dict, kappa: float) -> str:
    ok = [c for c in row.get("candidates") or [] if c.get("round") == 1 and passes(c, row, kappa)]
    return min(ok, key=lambda c: c["delta_bic"])["effect"] if ok else "none"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", type=Path)
    ap.add_argument("--kappa", type=float, nargs="+", default=[LOOK_ELSEWHERE, 0.15, 0.1, 0.05, 0.0])
    a = ap.parse_args(argv)
    payload = json.loads(a.results.read_text())
    if payload.get("split") == "heldout":
        print("held-out results: not replayed (tune on dev only)", file=sys.stderr)
        return 2
    rows = [r for r in payload.get("cases", []) if not r.get("error") and "candidates" in r]
    if not rows:
        print(f"{a.results}: no per-case candidate rows (rerun the bench with this version)", file=sys.stderr)
        return 2
    ref = {r["case"]: named(r, LOOK_ELSEWHERE) for r in rows}
    for kappa in a.kappa:
        eff = [r for r in rows if r["effect"] != "none"]
        nulls = [r for r in rows if r["effect"] == "none"]
        right = sum(named(r, kappa) == r["effect"] for r in eff)
        clean = sum(named(r, kappa) == "none" for r in nulls)
        print(f"kappa {kappa:4.2f}: round-1 effect cases named right {right}/{len(eff)}, nulls none {clean}/{len(nulls)}")
        for r in rows:
            n = named(r, kappa)
            if n != ref[r["case"]]:
                print(f"    {r['case']}: {ref[r['case']]} -> {n}{'  (right)' if n == r['effect'] else ''}")
    spec = specific_margins(rows)
    print(f"specific margin (SPECIFIC = {SPECIFIC}): largest gain beyond the other effects' of a wrong "
          f"effect's or a null's candidate, / noise floor:")
    for m, case, effect in spec[:5]:
        print(f"    {m:+7.4f}  {case}  {effect}")
    margins = sorted(((m, r["case"]) for r in rows if r["effect"] == "none"
                      for m in [null_margin(r)] if m is not None), reverse=True)
    print(f"nulls with a candidate passing all but the band: {len(margins)}; largest held-out gain / noise floor:")
    for m, case in margins[:10]:
        print(f"    {m:7.4f}  {case}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
