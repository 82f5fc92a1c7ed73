"""Benchmark: full diagnosis of the EHA bench on each shared recording (wall time, verdict,
validation ESR before → after). Run: ``python tests/benchmarks/bench_diagnose.py [--jobs 2]``
(target < 5 min each on 2 cores). Expected: valve_overlap, pressure_dependent_friction, none."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).parents[2]
RECORDINGS = ROOT.parent / "shared" / "recordings"
EXPECTED = {"eha_valve_overlap": "valve_overlap", "eha_pressure_dependent_friction": "pressure_dependent_friction",
            "eha_none": "none"}


def _cpu() -> float:
    """CPU seconds of this process and its finished worker processes (wall time on a shared
    machine depends on the other load; CPU time does not)."""
    import resource
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", nargs="*", default=list(EXPECTED))
    ap.add_argument("--out", type=Path, default=Path("/tmp/bench_diagnose"))
    args = ap.parse_args(argv)
    from hydrocli.diagnose import Settings, diagnose
    from hydrocli.diagnose.summary import write_augmented, write_json
    ok = True
    for rec in args.only:
        t0 = time.perf_counter()
        c0 = _cpu()
        d = diagnose(ROOT / "machines" / "eha_testbench.yaml", [RECORDINGS / rec / "train.csv"],
                     [RECORDINGS / rec / "validate.csv"], Settings(jobs=args.jobs),
                     progress=lambda m: print(f"  [{rec} {time.perf_counter() - t0:6.1f} s] {m}", file=sys.stderr,
                                              flush=True))
        wall = time.perf_counter() - t0
        cpu = _cpu() - c0
        out = args.out / rec
        out.mkdir(parents=True, exist_ok=True)
        write_json(d, out / "diagnosis.json")
        write_augmented(d, out / "augmented.yaml")
        eff = d.data["effects"][0]
        b, a = d.data["esr_validation_base"], d.data["esr_validation_final"]
        esr = ", ".join(f"{o} {b[o]:.3g}→{a[o]:.3g}" for o in b)
        hit = eff == EXPECTED.get(rec, eff)
        ok &= hit
        print(f"{rec:36s} verdict {d.data['verdict']:16s} effect {eff:28s} {'OK ' if hit else 'BAD'} "
              f"{wall:6.0f} s wall ({cpu:.0f} s CPU incl. workers)  validation ESR % {esr}", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
