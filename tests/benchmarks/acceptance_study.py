"""What other validation bands would name in round 1, read offline from a family bench's results.

    python tests/benchmarks/acceptance_study.py RESULTS.json [--kappa 1 0.5 0.25 0]

RESULTS.json is what ``bench_diagnose_family.py --split dev --json RESULTS.json`` wrote (it
keeps every fitted candidate's ΔBIC, validation gain and per-output validation ESR). For each
factor κ the held-out rule of ``diagnose.accept`` is replayed with the band

    need = max(κ · Σ noise ESR, MIN_REL · (val0 − Σ noise ESR))

(κ = 1 is the diagnosis' rule) and every other reason a candidate failed is kept; among the
round-1 candidates that pass, the lowest ΔBIC is named. Only round 1 is replayed (later
rounds start from a model the bench did not keep), and val0 is the base's validation ESR
(the engine uses the better of the base and its control re-fit), so κ = 1 may differ from
the bench's own answer on a few cases. Dev results only: never run it on held-out results.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from hydrocli.diagnose.accept import MIN_REL  # noqa: E402


def passes(cand: dict, row: dict, kappa: float) -> bool:
    if [r for r in (cand.get("reasons") or []) if "noise band" not in r]:
        return False                               # BIC, plausibility, precision, ceiling
    before, noise = row["esr_before"], row.get("noise_validation") or {}
    val0 = sum(before.values())
    floor = sum(noise.get(o, 0.0) for o in before)
    return cand["validation_gain"] > max(kappa * floor, MIN_REL * max(val0 - floor, 0.0))


def named(row: dict, kappa: float) -> str:
    ok = [c for c in row.get("candidates") or [] if c.get("round") == 1 and passes(c, row, kappa)]
    return min(ok, key=lambda c: c["delta_bic"])["effect"] if ok else "none"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", type=Path)
    ap.add_argument("--kappa", type=float, nargs="+", default=[1.0, 0.5, 0.25, 0.0])
    a = ap.parse_args(argv)
    payload = json.loads(a.results.read_text())
    if payload.get("split") == "heldout":
        print("held-out results: not replayed (tune on dev only)", file=sys.stderr)
        return 2
    rows = [r for r in payload.get("cases", []) if not r.get("error") and "candidates" in r]
    if not rows:
        print(f"{a.results}: no per-case candidate rows (rerun the bench with this version)", file=sys.stderr)
        return 2
    ref = {r["case"]: named(r, 1.0) for r in rows}
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
    return 0


if __name__ == "__main__":
    sys.exit(main())
