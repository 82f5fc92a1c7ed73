"""Result files (HDF5), exactly as DESIGN.md lays them out, written atomically.

``/meta`` (attrs: tool version, machine, netlist sha256, command line, timestamp, solver
statistics; dataset ``netlist`` = normalised YAML), ``/time``, ``/inputs/<name>``,
``/outputs/<name>``, ``/states/<name>``, ``/measured/<name>``, ``/parameters`` (name, SI
value, unit), every dataset with a ``unit`` attribute (SI) and, where the machine gives one,
``display_unit``; identification adds ``/identify``.
"""
from __future__ import annotations

import datetime as _dt
import sys
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from .version import __version__
from .errors import DataError, Location, Problem
from .fileio import atomic_path, note_input
from .units import si_unit


@dataclass
class RunResult:
    """One simulated experiment, ready to be written or reported."""

    machine: str
    netlist_sha: str
    netlist_text: str
    experiment: str
    t: np.ndarray
    inputs: dict[str, np.ndarray]
    outputs: dict[str, np.ndarray]
    states: dict[str, np.ndarray]
    measured: dict[str, np.ndarray] = field(default_factory=dict)
    parameters: list[tuple[str, float, str]] = field(default_factory=list)
    units: dict[str, str] = field(default_factory=dict)            # "outputs/P1" → SI unit
    display_units: dict[str, str] = field(default_factory=dict)    # "outputs/P1" → bar
    solver_stats: dict = field(default_factory=dict)
    identify: dict | None = None
    command: str = ""


def run_result(model, experiment, traj, p, command: str = "") -> RunResult:
    """Bundle a model, an experiment and a trajectory."""
    t = traj.t
    U = np.column_stack([np.interp(t, experiment.inputs.t, experiment.inputs.U[:, j])
                         for j in range(experiment.inputs.U.shape[1])]) if model.input_names else np.zeros((t.size, 0))
    units, disp = {}, {}
    for j, name in enumerate(model.input_names):
        units[f"inputs/{name}"] = si_unit(model.input_units.get(name, "1"))
        disp[f"inputs/{name}"] = model.input_units.get(name, "1")
    for name in model.output_names:
        units[f"outputs/{name}"] = units[f"measured/{name}"] = model.output_unit_si(name)
        if model.output_units.get(name):
            disp[f"outputs/{name}"] = disp[f"measured/{name}"] = model.output_units[name]
    for s in model.states:
        units[f"states/{s.name}"] = s.unit
    measured = {}
    for k, v in experiment.measured.items():
        measured[k] = v if v.shape == t.shape else np.interp(t, experiment.t_out, v)
    return RunResult(
        machine=model.name, netlist_sha=model.netlist_sha, netlist_text=model.netlist_text,
        experiment=experiment.name, t=t,
        inputs={n: U[:, j] for j, n in enumerate(model.input_names)},
        outputs={n: traj.Y[:, j] for j, n in enumerate(model.output_names)},
        states={s: traj.X[:, j] for j, s in enumerate(model.state_names)},
        measured=measured,
        parameters=[(pi.name, float(v), pi.unit) for pi, v in zip(model.params, p)],
        units=units, display_units=disp, solver_stats=dict(traj.stats),
        command=command or " ".join(sys.argv))


def write_result(path: str | Path, res: RunResult) -> None:
    """Write through a temporary file in the same folder, then rename (never a half file)."""
    with atomic_path(path) as tmp:
        with h5py.File(tmp, "w") as h:
            _write(h, res)


def _dataset(group, name: str, data, unit: str, display: str | None = None):
    ds = group.create_dataset(name, data=np.asarray(data, dtype=float))
    ds.attrs["unit"] = unit or "1"
    if display:
        ds.attrs["display_unit"] = display
    return ds


def _write(h: h5py.File, res: RunResult) -> None:
    meta = h.create_group("meta")
    meta.attrs.update({"tool": "hydrocli", "tool_version": __version__, "machine": res.machine,
                       "netlist_sha256": res.netlist_sha, "command": res.command, "experiment": res.experiment,
                       "timestamp": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")})
    for k, v in res.solver_stats.items():
        if isinstance(v, (int, float, str, np.integer, np.floating)):
            meta.attrs[f"solver_{k}"] = v
    meta.create_dataset("netlist", data=res.netlist_text, dtype=h5py.string_dtype())
    _dataset(h, "time", res.t, "s")
    for group, values in (("inputs", res.inputs), ("outputs", res.outputs), ("states", res.states),
                          ("measured", res.measured)):
        if not values and group == "measured":
            continue
        g = h.create_group(group)
        for name, data in values.items():
            key = f"{group}/{name}"
            _dataset(g, name, data, res.units.get(key, ""), res.display_units.get(key))
    dt = np.dtype([("name", h5py.string_dtype()), ("value", "f8"), ("unit", h5py.string_dtype())])
    h.create_dataset("parameters", data=np.array(res.parameters, dtype=dt))
    if res.identify:
        _write_tree(h.create_group("identify"), res.identify)


def _write_tree(g, tree: dict) -> None:
    """Write nested dicts: arrays/lists → datasets, scalars/strings → attributes."""
    for k, v in tree.items():
        if isinstance(v, dict):
            _write_tree(g.create_group(k), v)
        elif isinstance(v, str) or np.isscalar(v) or v is None:
            g.attrs[k] = "" if v is None else v
        else:
            arr = np.asarray(v)
            if arr.dtype.kind in "USO":
                g.create_dataset(k, data=[str(x) for x in arr.ravel()], dtype=h5py.string_dtype())
            else:
                g.create_dataset(k, data=arr.astype(float))


def read_result(path: str | Path) -> RunResult:
    """Read a result file back (for report and validate)."""
    path = Path(path)
    note_input(path)
    try:
        h = h5py.File(path, "r")
    except (OSError, FileNotFoundError) as exc:
        raise DataError(Problem(f"cannot open result file {path}: {exc}", Location(str(path)),
                                "give an HDF5 file written by 'hydro simulate' or 'hydro identify'")) from None
    with h:
        if "meta" not in h or "time" not in h:
            raise DataError(Problem(f"{path} is not a hydrocli result file (no /meta or /time)", Location(str(path))))
        meta = h["meta"]
        units, disp = {}, {}

        def grab(group):
            out = {}
            if group in h:
                for name, ds in h[group].items():
                    out[name] = ds[()]
                    units[f"{group}/{name}"] = ds.attrs.get("unit", "")
                    if "display_unit" in ds.attrs:
                        disp[f"{group}/{name}"] = ds.attrs["display_unit"]
            return out

        params = [(r["name"].decode() if isinstance(r["name"], bytes) else r["name"], float(r["value"]),
                   r["unit"].decode() if isinstance(r["unit"], bytes) else r["unit"]) for r in h["parameters"][()]]
        ident = _read_tree(h["identify"]) if "identify" in h else None
        text = meta["netlist"][()]
        return RunResult(
            machine=str(meta.attrs.get("machine", "")), netlist_sha=str(meta.attrs.get("netlist_sha256", "")),
            netlist_text=text.decode() if isinstance(text, bytes) else str(text),
            experiment=str(meta.attrs.get("experiment", "")), t=h["time"][()],
            inputs=grab("inputs"), outputs=grab("outputs"), states=grab("states"), measured=grab("measured"),
            parameters=params, units=units, display_units=disp,
            solver_stats={k[7:]: v for k, v in meta.attrs.items() if k.startswith("solver_")},
            identify=ident, command=str(meta.attrs.get("command", "")))


def _read_tree(g) -> dict:
    out: dict = dict(g.attrs)
    for k, v in g.items():
        if isinstance(v, h5py.Group):
            out[k] = _read_tree(v)
        else:
            data = v[()]
            if v.dtype.kind == "O":
                data = [x.decode() if isinstance(x, bytes) else x for x in data]
            out[k] = data
    return out
