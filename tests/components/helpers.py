"""Test helpers: evaluate a component's named variables with its ports held at given values."""
from __future__ import annotations

import numpy as np

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text


def pinned_model(component_yaml: str, pinned: dict[str, str], extra: str = ""):
    """A machine where each node in ``pinned`` (node → input name) is held by a pressure
    source driven by that input; ``component_yaml`` is indented under ``components:``."""
    inputs = "\n".join(f"  {inp}: {{unit: Pa}}" for inp in pinned.values())
    sources = "\n".join(f"  src_{node}:\n    type: pressure_source\n    ports: {{P: {node}, ref: {inp}}}"
                        for node, inp in pinned.items())
    text = f"name: pinned\ninputs:\n{inputs}\ncomponents:\n{component_yaml}\n{sources}\n{extra}"
    return build_model(load_netlist_text(text))


def evaluate(model, values: dict[str, np.ndarray], x=None) -> dict:
    """Every named variable for input columns ``values`` (arrays of equal length)."""
    n = len(next(iter(values.values())))
    U = np.column_stack([np.broadcast_to(np.asarray(values[k], float), (n,)) for k in model.input_names])
    X = np.zeros((n, len(model.state_names))) if x is None else np.broadcast_to(x, (n, len(model.state_names)))
    return model.evaluate_along(np.zeros(n), X, U, model.p0)
