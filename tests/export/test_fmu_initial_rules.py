"""An exported FMU starts from the machine file's initial RULES, not from the bare numbers:
a mass hung on a spring whose force is a ``balance`` rule starts at rest inside the FMU
(fmpy's own co-simulation master runs it), while without the rule it drops and rings by the
closed form x(t) = −(m g/k)(1 − cos ωt)."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.api import load_machine

fmpy = pytest.importorskip("fmpy")

M, K, G = 20.0, 8.0e4, 9.81
HANG = f"""
name: hanging_mass
inputs: {{F: {{unit: N}}}}
components:
  mass: {{type: mass, ports: {{m: load}}, m: {M}, F_const: {-M * G}}}
  spring: {{type: spring, ports: {{a: load, b: ground}}, k: {K}}}
  push: {{type: force_source, ports: {{a: load, F: F}}}}
outputs:
  x: load.x
"""


def _run(tmp_path, text: str, name: str):
    machine = tmp_path / f"{name}.yaml"
    machine.write_text(text)
    fmu = load_machine(machine).export_fmu(tmp_path / f"{name}.fmu")
    res = fmpy.simulate_fmu(str(fmu), start_time=0.0, stop_time=0.1, output_interval=1e-4,
                            start_values={"F": 0.0}, output=["x"], relative_tolerance=1e-9)
    return res["time"], res["x"]


def test_a_balance_rule_starts_the_exported_mass_at_rest(tmp_path):
    t, x = _run(tmp_path, HANG + "initial:\n  spring.dF: {balance: load.v}\n", "balanced")
    assert np.abs(x).max() < 1e-8
    t, x = _run(tmp_path, HANG, "relaxed")
    assert x.min() == pytest.approx(-2 * M * G / K, rel=2e-3)     # lowest point 2 m g/k below the start
    w = np.sqrt(K / M)
    assert np.allclose(x, -(M * G / K) * (1 - np.cos(w * t)), atol=1e-3 * M * G / K)
