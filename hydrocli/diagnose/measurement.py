"""The measurement model: pressure sensors with a first-order lag, always part of the
model the diagnosis fits.

Real pressure transducers (and every recording of ../shared/recordings) lag the chamber
pressure by about a millisecond. Left out, that lag shows up as a structured residual at
every fast pressure transient, and the diagnosis would "discover" it (or blame something
else). So each hydraulic node read by an output gets a ``pressure_sensor`` whose time
constant is a NUISANCE parameter, identified with the base model within
``PRESSURE_TAU_BOUNDS`` (what a typical transducer does) and reported separately. Only
when a lag far beyond that is needed (the ``sensor_lag`` candidate widens the bounds and
must pass the same acceptance tests) is ``sensor_lag`` reported as the missing physics.
"""
from __future__ import annotations

from ..netlist.model import Netlist
from . import augment as A

PRESSURE_TAU_BOUNDS = (1e-4, 3e-3)     # s: typical transducer + amplifier (≤ a few ms)
PRESSURE_TAU_START = 1e-3
PRESSURE_TAU_TYPICAL = 1.5e-3          # s: a transducer's lag with its amplifier, as datasheets give it;
                                       # a fit that presses the ceiling above stands for a lag the machine
                                       # file lacks, and is restrained to this (:mod:`.restrain`)
SENSOR_TYPE = "pressure_sensor"
RESONANT_SENSOR_TYPE = "pressure_sensor_2nd"   # a ringing transducer: the ``sensor_lag`` candidate's variant
SENSOR_TYPES = (SENSOR_TYPE, RESONANT_SENSOR_TYPE)   # every pressure transducer law
EFFECTS = frozenset({"sensor_lag"})   # vocabulary effects of the measurement, not of the machine: they cannot move it


def pressure_nodes(net: Netlist) -> list[str]:
    """Hydraulic nodes whose pressure an output reads (``node.p``)."""
    hyd = {n for n, ports in net.nodes().items() if any(_is_hydraulic(net, c, p) for c, p in ports)}
    out = []
    for o in net.outputs:
        for s in sorted(A.output_symbols(net, o)):
            node, _, q = s.rpartition(".")
            if q == "p" and node in hyd and node not in out:
                out.append(node)
    return out


def _is_hydraulic(net: Netlist, comp: str, port: str) -> bool:
    from ..components import registry
    from ..components.base import Domain
    spec = registry.get(net.components[comp].type).port(port)
    return spec is not None and spec.domain == Domain.HYDRAULIC


def with_pressure_sensors(net: Netlist) -> tuple[Netlist, dict[str, str]]:
    """The machine with a lagging sensor on every measured pressure; returns the new
    machine and {sensor component: sensed node}."""
    sensors: dict[str, str] = {}
    mapping = {}
    for node in pressure_nodes(net):
        name = A.unique_name(net, f"{node}_sensor")
        net = A.add(net, name, SENSOR_TYPE, {"P": node},
                    {"tau": {"value": PRESSURE_TAU_START, "free": True, "bounds": list(PRESSURE_TAU_BOUNDS), "log": True}})
        sensors[name] = node
        mapping[f"{node}.p"] = f"{name}.p"
    if mapping:
        net = A.rewrite_outputs(net, mapping)
    return net, sensors


def sensor_components(net: Netlist) -> list[str]:
    return [n for n, c in net.components.items() if c.type == SENSOR_TYPE]
