"""Diagnose every case of ``experiments/concealed`` (the project's own truth recordings) and
write the README table: effect, named correctly?, validation ESR before → after, wall time.

Run: ``python tests/benchmarks/bench_diagnose_concealed.py [--only CASE …] [--jobs 2]
[--markdown docs/concealed_results.md]``. Each case starts from its ``base.yaml`` (the
machine without the concealed effect) with ``train.csv`` for training and ``validate.csv``
held out; the truth is read from the JSON sidecar only to score the answer.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).parents[2]
CASES = ROOT / "experiments" / "concealed"
KEY_OUTPUTS = ("dp", "v", "P1", "x")


def cases() -> list[str]:
    return sorted(p.name for p in CASES.iterdir() if (p / "train.json").exists())


def _esr_pair(before: dict, after: dict) -> str:
    keys = [k for k in KEY_OUTPUTS if k in before][:2] or list(before)[:2]
    return ", ".join(f"{k} {before[k]:.2f} → {after.get(k, float('nan')):.2f}" for k in keys)


def run_case(case: str, jobs: int, out_root: Path) -> dict:
    from hydrocli.diagnose import Settings, diagnose
    from hydrocli.diagnose.summary import write_augmented, write_json

    folder = CASES / case
    truth = json.loads((folder / "train.json").read_text())["effect"]
    t0 = time.perf_counter()
    d = diagnose(folder / "base.yaml", [folder / "train.csv"], [folder / "validate.csv"], Settings(jobs=jobs),
                 progress=lambda m: print(f"  [{case}] {m}", file=sys.stderr, flush=True))
    wall = time.perf_counter() - t0
    out = out_root / case
    out.mkdir(parents=True, exist_ok=True)
    write_json(d, out / "diagnosis.json")
    write_augmented(d, out / "augmented.yaml")
    named = list(d.data["effects"])
    return {"case": case, "truth": truth, "named": named, "correct": truth in named if truth != "none" else named == ["none"],
            "first_correct": named[:1] == [truth], "esr": _esr_pair(d.data["esr_validation_base"], d.data["esr_validation_final"]),
            "seconds": wall}


def markdown(rows: list[dict]) -> str:
    lines = ["| case | concealed effect | named | correct? | validation ESR % before → after | time |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        mark = "yes" if r["first_correct"] else ("yes (not first)" if r["correct"] else "no")
        lines.append(f"| {r['case']} | {r['truth']} | {', '.join(r['named'])} | {mark} | {r['esr']} | {r['seconds']:.0f} s |")
    n_ok = sum(r["correct"] for r in rows)
    lines.append(f"\n{n_ok} of {len(rows)} named correctly.")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path("/tmp/bench_concealed"))
    ap.add_argument("--markdown", type=Path, default=None)
    args = ap.parse_args(argv)
    rows = []
    for case in args.only or cases():
        rows.append(run_case(case, args.jobs, args.out))
        print(markdown(rows[-1:]).splitlines()[2], flush=True)
    table = markdown(rows)
    print(table)
    if args.markdown:
        args.markdown.write_text(table)
    return 0 if all(r["correct"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
