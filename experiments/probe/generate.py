"""Concealed effects on machine types the family does not cover (issue 10: "shown on more
than one machine type"): the shipped files of seed 001's SARCOS elbow and seed 000's
knuckle-boom crane, each with one effect added.

A probe of GENERALITY, not an independent benchmark: the truth is hydrocli's own simulator,
the effect built from library components (a laminar leak to tank, a Padé delay on the command,
hoses, pressure-loaded seals, a compliant housing). What it tests is that the diagnosis finds
where an effect attaches on machines it was never tuned to — a jet-pipe servovalve or a
load-sensing valve as the metering valve, a vane or a cylinder in a serial chain as the
actuator, components inside template instances of an included file — and names it. Every
case, the nulls too, perturbs parameters the file keeps fixed by up to ±15 % (one draw per
seed and machine, shared by its effects). The truth starts settled (``initial: steady``), so
the recordings carry no start-up transient that no model of the machine can follow.

    python -m experiments.probe.generate --out DIR [--machines sarcos crane] [--seeds 1 2]
                                         [--effects ...]

writes ``DIR/<machine>/<case>/{base.yaml, train.csv, validate.csv, train.json, validate.json}``
(and the machine's included files) in the family's layout, so
``tests/benchmarks/bench_diagnose_family.py --data DIR --split all`` scores it; the split
(``experiments.family.split.split_of``) is recorded as the family's is.
"""
from __future__ import annotations

import argparse
import copy
import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

import hydrocli as hy
from experiments.family.split import split_of
from experiments.probe.machines import SPECS, Spec


def truth_doc(spec: Spec, effect: str, seed: int) -> tuple[dict, dict]:
    """The truth machine (the shipped file, fixed parameters perturbed, the effect added) and
    what was drawn: the magnitude factor and the perturbed values."""
    fixed = np.random.default_rng([1, seed])          # the machine's: one per seed, every effect alike
    size = np.random.default_rng([3, seed, sorted(spec.cases).index(effect)])
    doc = copy.deepcopy(yaml.safe_load(spec.base.read_text()))
    c = doc["components"]
    drawn = {}
    for name, v0 in spec.fixed.items():
        drawn[name] = float(v0 * fixed.uniform(0.85, 1.15))
        _set(c, name, drawn[name])
    k = float(size.uniform(0.7, 1.4))
    spec.cases[effect][1](c, k)
    return doc, {"magnitude_factor": k, "fixed_parameters": drawn}


def _set(components: dict, name: str, value: float) -> None:
    """Write parameter ``comp.param`` on its component, or (``inst.comp.param``) as the
    override ``comp.param`` of its template instance."""
    comp, par = name.rsplit(".", 1)
    if comp in components:
        components[comp][par] = value
    else:
        inst, _, inner = comp.partition(".")
        components[inst][f"{inner}.{par}"] = value


def _copy_includes(spec: Spec, folder: Path) -> None:
    inc = yaml.safe_load(spec.base.read_text()).get("include") or []
    for rel in [inc] if isinstance(inc, str) else inc:
        dst = folder / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(spec.base.parent / rel, dst)


def _simulate(doc: dict, exp: dict, folder: Path, tag: str):
    """(outputs, inputs) DataFrames of ``doc`` on ``exp`` (written beside the case's includes)."""
    m_path, e_path = folder / f".{tag}.yaml", folder / f".{tag}_exp.yaml"
    m_path.write_text(yaml.safe_dump(doc, sort_keys=False))
    e_path.write_text(yaml.safe_dump(exp, sort_keys=False))
    try:
        r = hy.load_machine(str(m_path)).simulate(str(e_path))
        return r.to_pandas("outputs"), r.to_pandas("inputs")
    finally:
        m_path.unlink()
        e_path.unlink()


def esr(y: np.ndarray, ref: np.ndarray) -> float:
    """100·Σ(y − ref)² / Σ(y − ȳ)² (%): the effect's size, offsets included. NOT the family's
    (``hydrocli.metrics.esr``, 100·var(y − ref)/var(y), seed 004 eq. 14), which ignores a
    constant shift — most of what a leak does to a held pressure (SARCOS leaks: 1.2–1.8 % here,
    0.05–0.07 % by the family's); docs/diagnose.md § Session 46 gives both."""
    return float(100.0 * np.sum((y - ref) ** 2) / np.sum((y - y.mean()) ** 2))


def make_case(spec: Spec, out: Path, effect: str, seed: int) -> Path:
    form = spec.cases[effect][0]
    case = f"{spec.name}__{effect}__{form}__s{seed}"
    folder = out / spec.name / case
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "base.yaml").write_text(spec.base.read_text())
    _copy_includes(spec, folder)
    doc, drawn = truth_doc(spec, effect, seed)
    off, _ = truth_doc(spec, "none", seed)            # the same machine, the effect switched off
    rng = np.random.default_rng([2, seed, sorted(spec.cases).index(effect)])
    for kind, exp in spec.experiments.items():
        y, u = _simulate(doc, dict(exp, name=kind), folder, "truth")
        y0 = _simulate(off, dict(exp, name=kind), folder, "off")[0] if effect != "none" else y
        e = {o: esr(y[o].to_numpy(), y0[o].to_numpy()) for o in spec.sensors}
        e["size"] = max(e.values())
        noise = {o: float(100.0 * s ** 2 / np.var(y[o].to_numpy())) for o, (s, _) in spec.sensors.items()}
        t = y.index.to_numpy()
        cols = {"t[s]": t, **{f"{n}[{spec.inputs[n]}]": u[n].to_numpy() for n in spec.inputs}}
        for o, (s, unit) in spec.sensors.items():
            cols[f"{o}[{unit}]"] = y[o].to_numpy() + rng.normal(0.0, s, len(t))
        pd.DataFrame(cols).to_csv(folder / f"{kind}.csv", index=False, float_format="%.7g")
        side = {"effect": effect, "form": form, "machine": spec.name, "case": case, "seed": seed,
                "split": split_of(spec.name, effect, form, seed), "experiment": kind, "csv": f"{kind}.csv",
                "generator": "experiments/probe (hydrocli's own simulator: a generality probe, not independent)",
                "signal_map": {o: o for o in spec.sensors}, "effect_esr_percent": e,
                "noise_esr_percent": noise, "noise_sigma_si": {o: s for o, (s, _) in spec.sensors.items()},
                "drawn": drawn}
        (folder / f"{kind}.json").write_text(json.dumps(side, indent=1) + "\n")
    return folder


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--machines", nargs="+", choices=sorted(SPECS), default=sorted(SPECS))
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--effects", nargs="+", default=None, help="default: every effect the machine's spec offers")
    a = ap.parse_args(argv)
    for name in a.machines:
        spec = SPECS[name]
        unknown = set(a.effects or []) - set(spec.cases)
        effects = [e for e in sorted(spec.cases) if a.effects is None or e in a.effects]
        if unknown and not effects:
            ap.error(f"{name} offers {', '.join(sorted(spec.cases))}")
        for seed in a.seeds:
            for effect in effects:
                folder = make_case(spec, a.out, effect, seed)
                side = json.loads((folder / "train.json").read_text())
                print(f"{folder.name}: effect ESR {side['effect_esr_percent']['size']:.3g} % (train)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
