"""The normalised netlist: a canonical YAML text (SI values, sorted keys) whose sha256
identifies a machine in result files regardless of comments, units or layout."""
from __future__ import annotations

import hashlib

import io

from ruamel.yaml import YAML

from .model import Netlist


def normalised_text(net: Netlist) -> str:
    doc = {
        "name": net.name,
        "inputs": {k: {"unit": v.unit, "hold": v.hold} for k, v in sorted(net.inputs.items())},
        "outputs": {k: {"expr": v.expr, "unit": v.unit} for k, v in sorted(net.outputs.items())},
        "components": {
            name: {"type": c.type, "ports": dict(sorted(c.ports.items())),
                   "parameters": {k: _plain(v.value) for k, v in sorted(c.params.items())},
                   "free": sorted(k for k, v in c.params.items() if v.free)}
            for name, c in sorted(net.components.items())},
        "initial": {k: _plain(v.value) for k, v in sorted(net.initial.items())},
    }
    y = YAML(typ="safe", pure=True)
    y.default_flow_style = False
    buf = io.StringIO()
    y.dump(doc, buf)
    return buf.getvalue()


def _plain(v):
    if isinstance(v, list):
        return [float(x) for x in v]
    return float(v) if isinstance(v, (int, float)) else str(v)


def netlist_sha256(net: Netlist) -> str:
    """sha256 of the normalised netlist text (the /meta attribute of every result)."""
    return hashlib.sha256(normalised_text(net).encode()).hexdigest()
