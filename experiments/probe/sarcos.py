"""Concealed effects on a machine type the family does not cover: seed 001's SARCOS elbow
(``machines/sarcos_elbow.yaml``: a jet-pipe servovalve with hysteresis behind supply and
return lines and an accumulator, a vane actuator, a torsion shaft, a gravity load).

A probe of GENERALITY, not an independent benchmark: the truth is hydrocli's own simulator
with one effect added to the shipped file, built from library components (a laminar leak to
tank, a Padé delay on the current, hoses between valve and vane, pressure-loaded vane seals,
a compliant housing). What it tests is that the diagnosis finds where an effect attaches on a
machine it was never tuned to (roles, not type names: a ``servovalve_jet`` is the metering
valve, the vane the actuator) and names it. Every case, the nulls too, perturbs fixed
parameters of the file (vane inertia, valve damping, vane viscous friction) by up to ±15 %.
The truth starts settled (``initial: steady``), so the recordings carry no start-up transient
that no model of the machine can follow.

Entrained air, an end stop, internal leakage and friction laws the file already frees are left
out: at the elbow's 100 bar mean chamber pressure 1 % of free air is compressed to 0.01 % of the
volume (nothing to find), the vane has no stops, and R_v and the Coulomb terms are free in the
file (a changed value is a fit, not missing physics).

    python -m experiments.probe.sarcos --out DIR [--seeds 1 2] [--effects ...]

writes ``DIR/sarcos/<case>/{base.yaml, train.csv, validate.csv, train.json, validate.json}`` in
the family's layout, so ``tests/benchmarks/bench_diagnose_family.py --data DIR --split all``
scores it. The split (``experiments.family.split.split_of``) is recorded as the family's is.
"""
from __future__ import annotations

import argparse
import copy
import json
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

import hydrocli as hy

from experiments.family.split import split_of

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "machines" / "sarcos_elbow.yaml"
MACHINE = "sarcos"
FS = 1000.0
SENSORS = {"P1": 2.0e4, "P2": 2.0e4, "theta": 2.0e-4}   # noise σ: Pa, Pa, rad (0.2 bar, 0.01°)
SIGNAL_MAP = {"P1": "P1", "P2": "P2", "x": "theta"}
EXPERIMENTS = {
    # a chirp through the valve's and the load's band, then steps of either sign (held-out)
    "train": {"duration": "20 s", "rate": "1 kHz", "initial": "steady", "settle": "2 s",
              "inputs": {"i": {"chirp": {"amplitude": "0.1 A", "f0": "0.05 Hz", "f1": "2.5 Hz", "duration": "20 s"}}}},
    "validate": {"duration": "15 s", "rate": "1 kHz", "initial": "steady", "settle": "2 s",
                 "inputs": {"i": {"table": {"t": [0, 1, 1.01, 4, 4.01, 7, 7.01, 10, 10.01, 15],
                                            "values": [0, 0, 0.08, 0.08, -0.06, -0.06, 0.03, 0.03, -0.09, -0.09]}}}},
}


def _leak(c, k):
    c["leak"] = {"type": "laminar_resistance", "ports": {"A": "port_1", "B": "tank_node"}, "R": 2.0e13 / k}


def _delay(c, k):
    c["delay"] = {"type": "pade_delay", "ports": {"in": "i", "out": "i_delayed"}, "T": 0.02 * k}
    c["servovalve"]["ports"]["cmd"] = "i_delayed"


def _hoses(c, k):
    c["servovalve"]["ports"].update({"A": "valve_A", "B": "valve_B"})
    for name, a, b in (("hose_A", "valve_A", "port_1"), ("hose_B", "valve_B", "port_2")):
        c[name] = {"type": "hose", "ports": {"A": a, "B": b}, "l": 3.0 * k, "d": 0.006}


def _seals(c, k):
    c["seal"] = {"type": "rotary_seal_friction", "ports": {"a": "vane_node", "b": "ground", "pa": "port_1", "pb": "port_2"},
                 "mu_d": 0.15 * k, "D_p": 3.0e-6}


def _mount(c, k):
    c["vane"]["ports"]["body"] = "housing_node"
    c["housing"] = {"type": "inertia", "ports": {"r": "housing_node"}, "J": 0.02}
    c["mount"] = {"type": "shaft", "ports": {"a": "housing_node", "b": "ground"}, "k": 150.0 / k, "b": 0.5}


# effect → (form, edit(components, magnitude factor k))
CASES = {
    "none": ("fixed_parameters_perturbed", lambda c, k: None),
    "external_leakage": ("laminar_port_to_tank", _leak),
    "input_delay": ("pade_current", _delay),
    "line_dynamics": ("hoses_both_ports", _hoses),
    "pressure_dependent_friction": ("vane_seal_dp", _seals),
    "structural_flexibility": ("housing_on_torsion_mount", _mount),
}


def truth_doc(effect: str, seed: int) -> tuple[dict, dict]:
    """The truth machine (the shipped file, fixed parameters perturbed, the effect added) and
    what was drawn: the magnitude factor and the perturbations."""
    fixed = np.random.default_rng([1, seed])          # the machine's: one per seed, every effect alike
    size = np.random.default_rng([3, seed, sorted(CASES).index(effect)])
    doc = copy.deepcopy(yaml.safe_load(BASE.read_text()))
    c = doc["components"]
    drawn = {"vane_inertia.J": 1e-3, "servovalve.zeta": 1.0, "vane_friction.b": 0.5}
    for name, v0 in list(drawn.items()):
        comp, par = name.split(".")
        drawn[name] = c[comp][par] = float(v0 * fixed.uniform(0.85, 1.15))
    k = float(size.uniform(0.7, 1.4))
    CASES[effect][1](c, k)
    return doc, {"magnitude_factor": k, "fixed_parameters": drawn}


def _simulate(doc: dict, exp: dict, folder: Path, tag: str):
    """(outputs, inputs) DataFrames of ``doc`` on ``exp``."""
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
    """100·Σ(y − ref)² / Σ(y − ȳ)² (%), the family's effect ESR."""
    return float(100.0 * np.sum((y - ref) ** 2) / np.sum((y - y.mean()) ** 2))


def make_case(out: Path, effect: str, seed: int) -> Path:
    form = CASES[effect][0]
    case = f"{MACHINE}__{effect}__{form}__s{seed}"
    folder = out / MACHINE / case
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "base.yaml").write_text(BASE.read_text())
    doc, drawn = truth_doc(effect, seed)
    off, _ = truth_doc("none", seed)                  # the same machine, the effect switched off
    rng = np.random.default_rng([2, seed, sorted(CASES).index(effect)])
    for kind, exp in EXPERIMENTS.items():
        y, u = _simulate(doc, dict(exp, name=kind), folder, "truth")
        y0 = _simulate(off, dict(exp, name=kind), folder, "off")[0] if effect != "none" else y
        e = {o: esr(y[o].to_numpy(), y0[o].to_numpy()) for o in SENSORS}
        e["size"] = max(e.values())
        noise = {o: float(100.0 * s ** 2 / np.var(y[o].to_numpy())) for o, s in SENSORS.items()}
        t = y.index.to_numpy()
        cols = {"t[s]": t, "i[A]": u["i"].to_numpy()}
        units = {"P1": "Pa", "P2": "Pa", "theta": "rad"}
        for o, s in SENSORS.items():
            cols[f"{o}[{units[o]}]"] = y[o].to_numpy() + rng.normal(0.0, s, len(t))
        pd.DataFrame(cols).to_csv(folder / f"{kind}.csv", index=False, float_format="%.7g")
        side = {"effect": effect, "form": form, "machine": MACHINE, "case": case, "seed": seed,
                "split": split_of(MACHINE, effect, form, seed), "experiment": kind, "csv": f"{kind}.csv",
                "generator": "experiments/probe/sarcos.py (hydrocli's own simulator: a generality probe, not independent)",
                "sampling_rate_hz": FS, "signal_map": SIGNAL_MAP, "effect_esr_percent": e,
                "noise_esr_percent": noise, "noise_sigma_si": SENSORS, "drawn": drawn}
        (folder / f"{kind}.json").write_text(json.dumps(side, indent=1) + "\n")
    return folder


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--effects", nargs="+", choices=sorted(CASES), default=sorted(CASES))
    a = ap.parse_args(argv)
    for seed in a.seeds:
        for effect in a.effects:
            folder = make_case(a.out, effect, seed)
            side = json.loads((folder / "train.json").read_text())
            print(f"{folder.name}: effect ESR {side['effect_esr_percent']['size']:.3g} % (train)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
