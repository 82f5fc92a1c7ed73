"""Nuisance parameters of the base fit: values a machine file keeps FIXED that commonly differ
from the datasheet on a real machine — the spool time constant and rate limit of every
metering valve (its role's ``spool_dynamics`` slot; seed 004 eq. 1: a datasheet gives the
−3 dB frequency at one amplitude and the slew rate of one valve of a batch), and the areas or
displacements of every actuator within their manufacturing tolerance (±3 %).

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

SPAN = 1.43       # spool dynamics: file value / SPAN … × SPAN (≈ ±30 %)
AREA_SPAN = 1.03  # actuator areas/displacements: ±3 % (a bore or rod within ±1.5 % of its diameter)


@dataclass(frozen=True)
class Nuisance:
    name: str         # model parameter name
    file_value: float
    bounds: tuple[float, float]


def valve_dynamics(net: Netlist, already_free: set[str]) -> list[Nuisance]:
    """The fixed spool-dynamics parameters of every metering valve (positive values only)."""
    return _fixed(net, already_free, R.METERING_VALVE, "spool_dynamics", SPAN)


def actuator_areas(net: Netlist, already_free: set[str]) -> list[Nuisance]:
    """The fixed areas (displacements) of every actuator: a drawing's nominal bore and rod
    differ from the machine's by their tolerance, and on a load-holding cylinder a 1.5 % area
    error alone leaves a static pressure offset many times the sensor noise."""
    return _fixed(net, already_free, R.ACTUATOR, "displacements", AREA_SPAN)


def _fixed(net: Netlist, already_free: set[str], role_name: str, slot: str, span: float) -> list[Nuisance]:
    out = []
    for comp, decl in net.components.items():
        cls = registry.get(decl.type)
        role = cls.role(role_name) if cls is not None else None
        if role is None:
            continue
        for pname in role.params_of(slot):
            name = f"{comp}.{pname}"
            if name in already_free or pname not in decl.params:
                continue
            try:
                v = float(decl.params[pname].value)
            except (TypeError, ValueError):
                continue
            if v > 0:
                out.append(Nuisance(name, v, (v / span, v * span)))
    return out


def with_nuisance(net: Netlist, already_free: set[str]) -> tuple[Netlist, list[Nuisance]]:
    """The machine with every nuisance parameter free (log scale) from its file value."""
    found = valve_dynamics(net, already_free) + actuator_areas(net, already_free)
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
