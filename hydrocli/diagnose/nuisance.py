"""Nuisance parameters of the base fit: values a machine file keeps FIXED that commonly differ
from the datasheet on a real machine — the spool time constant and rate limit of every
metering valve (its role's ``spool_dynamics`` slot; seed 004 eq. 1: a datasheet gives the
−3 dB frequency at one amplitude and the slew rate of one valve of a batch).

Left fixed at a wrong value they leave a structured residual at every fast command change
that dynamic candidates (a delay, a line, a compliance, a hysteresis) absorb, and they raise
the floor under which small effects hide. The diagnosis frees them within ``SPAN`` of the
file's value (log scale) with the base model, like the pressure-sensor lags, and reports
them under ``nuisance_parameters``: a ±30 % window covers a datasheet's tolerance and a ±15 %
perturbation with margin, but cannot turn a spool lag into a 10 ms transport delay or a
hysteresis loop.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..components import registry
from ..components import roles as R
from ..netlist.model import Netlist
from . import augment as A

SPAN = 1.43     # bounds: file value / SPAN … × SPAN (≈ ±30 %)


@dataclass(frozen=True)
class Nuisance:
    name: str         # model parameter name
    file_value: float
    bounds: tuple[float, float]


def valve_dynamics(net: Netlist, already_free: set[str]) -> list[Nuisance]:
    """The fixed spool-dynamics parameters of every metering valve (positive values only)."""
    out = []
    for comp, decl in net.components.items():
        cls = registry.get(decl.type)
        role = cls.role(R.METERING_VALVE) if cls is not None else None
        if role is None:
            continue
        for pname in role.params_of("spool_dynamics"):
            name = f"{comp}.{pname}"
            if name in already_free or pname not in decl.params:
                continue
            try:
                v = float(decl.params[pname].value)
            except (TypeError, ValueError):
                continue
            if v > 0:
                out.append(Nuisance(name, v, (v / SPAN, v * SPAN)))
    return out


def with_nuisance(net: Netlist, already_free: set[str]) -> tuple[Netlist, list[Nuisance]]:
    """The machine with every nuisance parameter free (log scale) from its file value."""
    found = valve_dynamics(net, already_free)
    for n in found:
        net = A.free(net, n.name, n.file_value, n.bounds, True)
    return net, found


def report(found: list[Nuisance], judged: list[dict]) -> dict:
    """{name: file value, estimate, stderr, at_bound} for diagnosis.json."""
    by_name = {j["name"]: j for j in judged}
    out = {}
    for n in found:
        j = by_name.get(n.name)
        if j is None:
            continue
        lo, hi = n.bounds
        at = "lower" if j["value"] <= lo * 1.001 else "upper" if j["value"] >= hi / 1.001 else None
        out[n.name] = {"file_value": n.file_value, "value": j["value"], "stderr": j["stderr"],
                       "change_percent": 100.0 * (j["value"] / n.file_value - 1.0),
                       "at_bound": at}
    return out
