"""The probe's machines: each a shipped file, its sensors, its designed experiments, the
parameters it keeps fixed that the probe perturbs, and the effects it can carry (an edit of
the machine's components, given a magnitude factor k drawn in 0.7–1.4).

Left out, and why: on the SARCOS elbow entrained air (at its ~100 bar mean chamber pressure
1 % of free air is compressed to 0.01 % of the volume: nothing to find), end stops (the vane
has none in the file) and internal leakage or Coulomb friction (R_v and the Coulomb terms are
free in the file: a changed value is a fit, not missing physics); on the crane hoses, mounts
and stops (they would rewrite the jib-circuit template itself) and friction (its static force
is already in the file)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Spec:
    name: str
    base: Path
    inputs: dict[str, str]                                  # input → unit written in the CSV header
    sensors: dict[str, tuple[float, str]]                   # output → (noise σ in SI, unit)
    experiments: dict[str, dict]                            # "train"/"validate" → experiment mapping
    fixed: dict[str, float]                                 # comp.param → file value (perturbed ±15 %)
    cases: dict[str, tuple[str, Callable[[dict, float], None]]] = field(default_factory=dict)


def _none(c, k):
    return None


# -- seed 001's SARCOS elbow ----------------------------------------------------------------
def _sarcos_leak(c, k):
    c["leak"] = {"type": "laminar_resistance", "ports": {"A": "port_1", "B": "tank_node"}, "R": 2.0e13 / k}


def _sarcos_delay(c, k):
    c["delay"] = {"type": "pade_delay", "ports": {"in": "i", "out": "i_delayed"}, "T": 0.02 * k}
    c["servovalve"]["ports"]["cmd"] = "i_delayed"


def _sarcos_hoses(c, k):
    c["servovalve"]["ports"].update({"A": "valve_A", "B": "valve_B"})
    for name, a, b in (("hose_A", "valve_A", "port_1"), ("hose_B", "valve_B", "port_2")):
        c[name] = {"type": "hose", "ports": {"A": a, "B": b}, "l": 3.0 * k, "d": 0.006}


def _sarcos_seals(c, k):
    c["seal"] = {"type": "rotary_seal_friction", "ports": {"a": "vane_node", "b": "ground", "pa": "port_1", "pb": "port_2"},
                 "mu_d": 0.15 * k, "D_p": 3.0e-6}


def _sarcos_mount(c, k):
    c["vane"]["ports"]["body"] = "housing_node"
    c["housing"] = {"type": "inertia", "ports": {"r": "housing_node"}, "J": 0.02}
    c["mount"] = {"type": "shaft", "ports": {"a": "housing_node", "b": "ground"}, "k": 150.0 / k, "b": 0.5}


SARCOS = Spec(
    name="sarcos", base=ROOT / "machines" / "sarcos_elbow.yaml", inputs={"i": "A"},
    sensors={"P1": (2.0e4, "Pa"), "P2": (2.0e4, "Pa"), "theta": (2.0e-4, "rad")},   # 0.2 bar, 0.01°
    experiments={
        # a chirp through the valve's and the load's band; held out: steps of either sign
        "train": {"duration": "20 s", "rate": "1 kHz", "initial": "steady", "settle": "2 s",
                  "inputs": {"i": {"chirp": {"amplitude": "0.1 A", "f0": "0.05 Hz", "f1": "2.5 Hz",
                                             "duration": "20 s"}}}},
        "validate": {"duration": "15 s", "rate": "1 kHz", "initial": "steady", "settle": "2 s",
                     "inputs": {"i": {"table": {"t": [0, 1, 1.01, 4, 4.01, 7, 7.01, 10, 10.01, 15],
                                                "values": [0, 0, 0.08, 0.08, -0.06, -0.06, 0.03, 0.03, -0.09, -0.09]}}}},
    },
    fixed={"vane_inertia.J": 1e-3, "servovalve.zeta": 1.0, "vane_friction.b": 0.5},
    cases={"none": ("fixed_parameters_perturbed", _none),
           "external_leakage": ("laminar_port_to_tank", _sarcos_leak),
           "input_delay": ("pade_current", _sarcos_delay),
           "line_dynamics": ("hoses_both_ports", _sarcos_hoses),
           "pressure_dependent_friction": ("vane_seal_dp", _sarcos_seals),
           "structural_flexibility": ("housing_on_torsion_mount", _sarcos_mount)})


# -- seed 000's knuckle-boom crane (template instances of an included file) -------------------
def _crane_leak(c, k):
    c["leak"] = {"type": "laminar_resistance", "ports": {"A": "outer.p3", "B": "p_return"}, "R": 5.0e11 / k}


def _crane_bypass(c, k):
    c["bypass"] = {"type": "laminar_resistance", "ports": {"A": "outer.p2", "B": "outer.p3"}, "R": 1.5e12 / k}


def _crane_delay(c, k):
    c["delay"] = {"type": "pade_delay", "ports": {"in": "u_outer", "out": "u_outer_delayed"}, "T": 0.06 * k}
    c["outer"]["ports"]["cmd"] = "u_outer_delayed"


def _crane_air(c, k):
    c["outer"]["cyl.air"] = 0.03 * k


CRANE = Spec(
    name="crane", base=ROOT / "machines" / "knuckle_boom_crane.yaml",
    inputs={"u_inner": "1", "u_inter": "1", "u_outer": "1"},
    sensors={"l_outer": (2.0e-4, "m"), "p2_outer": (5.0e4, "Pa"), "p3_outer": (5.0e4, "Pa"),
             "l_inner": (2.0e-4, "m"), "p2_inner": (5.0e4, "Pa")},                   # 0.2 mm, 0.5 bar
    experiments={
        # the outer jib swept by a chirp while the inner jib lifts; held out: outer steps, inner lowers
        "train": {"duration": "12 s", "rate": "100 Hz", "initial": "steady", "settle": "2 s",
                  "inputs": {"u_inner": {"table": {"t": [0, 1, 2, 4, 5, 12], "values": [0, 0, 0.3, 0.3, 0, 0]}},
                             "u_inter": 0,
                             "u_outer": {"chirp": {"amplitude": 0.5, "f0": "0.1 Hz", "f1": "1.0 Hz",
                                                   "duration": "12 s"}}}},
        "validate": {"duration": "10 s", "rate": "100 Hz", "initial": "steady", "settle": "2 s",
                     "inputs": {"u_inner": {"table": {"t": [0, 5, 6, 8, 9, 10], "values": [0, 0, -0.25, -0.25, 0, 0]}},
                                "u_inter": 0,
                                "u_outer": {"table": {"t": [0, 1, 1.5, 3, 3.5, 6, 6.5, 8, 8.5, 10],
                                                      "values": [0, 0, 0.5, 0.5, 0, 0, -0.4, -0.4, 0, 0]}}}},
    },
    fixed={"outer.dcv.tau": 0.0333, "outer.dcv.zeta": 0.8, "inner.dcv.tau": 0.004},
    cases={"none": ("fixed_parameters_perturbed", _none),
           "external_leakage": ("laminar_rod_side_to_tank", _crane_leak),
           "internal_leakage": ("laminar_piston_bypass", _crane_bypass),
           "input_delay": ("pade_joystick", _crane_delay),
           "entrained_air": ("polytropic_outer_cylinder", _crane_air)})

SPECS = {s.name: s for s in (SARCOS, CRANE)}
