"""Record a designed experiment on a family case's TRUTH: what the test rig would give when an
engineer runs the discriminating experiment ``hydro diagnose`` proposed (issue 10: "diagnosing
again with that recording added must decide").

    python -m experiments.family.record CASE_DIR proposed_experiment_1.yaml OUT.csv [--seed 5]

The case's sidecar names the truth (machine, effect, form, seed, effect scale); the designed
signals are read with hydrocli's own experiment loader (against the case's base machine, for
the input units) and replayed open loop through the independent truth simulator after a 2 s
settling pre-roll at the first input values, from the case's home state. The sensors are the
case's (noise, quantisation, the 1 ms pressure lag inside the truth). The CSV has the header
of the case's own recordings, so it is diagnosed like train.csv.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from experiments.concealed.truth.eha import Inputs
from experiments.family.generate import FS, PREROLL, CaseRunner, _quant, _truth, sensors_of


def designed_inputs(case: Path, experiment: Path) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Time grid (1 kHz from 0) and each machine input in SI, from the designed experiment."""
    from hydrocli.experiments.experiment_file import load_all
    from hydrocli.model.builder import build_model
    from hydrocli.netlist.loader import load_netlist
    model = build_model(load_netlist(case / "base.yaml"))
    e = load_all(experiment, model)[0]
    t_in = np.asarray(e.inputs.t, float)
    t = np.arange(0.0, t_in[-1] - t_in[0] + 0.5 / FS, 1.0 / FS)
    return t, {n: np.interp(t + t_in[0], t_in, e.inputs.U[:, j]) for j, n in enumerate(model.input_names)}


def record(case: Path, experiment: Path, out: Path, seed: int = 5) -> dict:
    from hydrocli.units import from_si
    side = json.loads((case / "train.json").read_text())
    cr = CaseRunner(side["machine"], side["effect"], side["form"], side["seed"], 20.0)
    mt = cr.mt
    units = {c.split("[")[0]: c.split("[")[1].rstrip("]") for c in mt.csv_header().split(",")}
    t, U = designed_inputs(case, experiment)
    n0 = int(round(PREROLL * FS))
    held = lambda a: np.concatenate([np.full(n0, a[0]), a])          # pre-roll at the first values
    sig = {k: held(from_si(np.asarray(U[k]), units[k]) if k in U else np.zeros(len(t)))
           for k in ("u", "Ps", "Fext")}
    if "Ps" not in U:
        sig["Ps"] = np.full(len(t) + n0, mt.bench["Ps0"])
    t_grid = np.concatenate([t[0] - (np.arange(n0, 0, -1)) / FS, t])
    inputs = Inputs(t_grid[0], 1.0 / FS, sig["u"], sig["Ps"], sig["Fext"])
    model = _truth(mt, cr.p, cr.effect_obj(float(side["effect_scale"])), inputs)
    sol = model.simulate(t_grid, cr.y0(model))
    on = {k: v[n0:] for k, v in model.measured(sol.y).items()}
    sens = sensors_of(mt)
    rng = np.random.default_rng(seed)
    N = len(t)
    meas = {"P1": _quant(on["P1"] + sens["P_sigma"] * rng.standard_normal(N), sens["P_quant"]),
            "P2": _quant(on["P2"] + sens["P_sigma"] * rng.standard_normal(N), sens["P_quant"]),
            "x": _quant(on["x"] + sens["x_sigma"] * rng.standard_normal(N), sens["x_quant"]),
            "v": _quant(on["v"] + sens["v_sigma"] * rng.standard_normal(N), sens["v_quant"])}
    with open(out, "w") as f:
        f.write(mt.csv_header() + "\n")
        for i in range(N):
            row = [f"{t[i]:.3f}", f"{sig['u'][n0 + i]:.4f}", f"{sig['Ps'][n0 + i]:.0f}"]
            if mt.with_fext:
                row.append(f"{sig['Fext'][n0 + i]:.1f}")
            row += [f"{meas['P1'][i]:.0f}", f"{meas['P2'][i]:.0f}", f"{meas['x'][i]:.6f}", f"{meas['v'][i]:.5f}"]
            f.write(",".join(row) + "\n")
    return {"ok": bool(sol.success), "samples": N, "x_range": (float(on["x"].min()), float(on["x"].max()))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", type=Path)
    ap.add_argument("experiment", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--seed", type=int, default=5)
    a = ap.parse_args(argv)
    print(record(a.case, a.experiment, a.out, a.seed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
