"""The machine types of the family: nominal truth parameters, which are perturbed and by how
much, bench settings (supply, controller, setpoint range) and the CSV column names.

Every base parameter is perturbed by a seeded factor, INCLUDING those the machine files keep
fixed (spool time constant ``tau_v``, rate limit ``s_max``): +-15 %; areas / displacement
within a manufacturing tolerance of +-1.5 %. Parameters in one ``tie`` group share a factor
(the rotary and winch friction is symmetric in the machine file; a motor's two "areas" are its
one displacement).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from experiments.concealed.truth.eha import NOMINAL_BASE as EHA_NOMINAL
from experiments.concealed.truth.eha import PERTURBED as EHA_PERTURBED

G = 9.81


@dataclass(frozen=True)
class MachineType:
    name: str
    truth: str                     # "eha" (concealed/truth/eha.py) or "actuator" (actuator.py)
    machine_file: str              # machines/<file>, the base machine of every case
    nominal: dict
    perturb: dict                  # name -> (half-range, tie group or "")
    bench: dict
    columns: dict = field(default_factory=dict)   # internal signal -> (CSV name, unit)
    with_fext: bool = False

    def csv_header(self) -> str:
        cols = [("t", "s"), ("u", "%"), ("Ps", "Pa")] + ([("Fext", "N")] if self.with_fext else [])
        cols += [self.columns[k] for k in ("P1", "P2", "x", "v")]
        return ",".join(f"{n}[{u}]" for n, u in cols)


_STD = 0.15
_TOL = 0.015

LIFT_NOMINAL = {
    "kind": "linear", "cbv": 0, "Kv": 3.5e-7, "tau_v": 0.008, "s_max": 1000.0,
    "A_A": 5.0265e-3, "A_B": 3.4361e-3, "V10": 4.0e-4, "V20": 2.12e-3, "beta": 1.5e9,
    "c_il": 0.0, "c_el": 0.0, "m": 1500.0, "W": 1500.0 * G, "theta0": 0.0,
    "kv_p": 6000.0, "kv_m": 7000.0, "kc_p": 500.0, "kc_m": 600.0, "ks_p": 0.0, "ks_m": 0.0,
    "taus_p": 0.005, "taus_m": 0.005, "eps": 1e-4, "Pd": 1e5, "dp_lam": 5e4,
}
LIFT_PERTURB = {**{k: (_STD, "") for k in ("Kv", "tau_v", "s_max", "V10", "V20", "beta", "m",
                                          "kv_p", "kv_m", "kc_p", "kc_m")},
                "A_A": (_TOL, ""), "A_B": (_TOL, "")}
LIFT_BENCH = {"Ps0": 1.6e7, "ripple_amp": 8e4, "ripple_freq": 30.0, "slow_amp": 5e4,
              "droop_gain": 1.5e8, "droop_tau": 0.03, "ctrl_Kp": 3000.0, "ctrl_Ki": 1500.0,
              "u_max": 100.0, "x_home": 0.15, "setpoint_range": [0.08, 0.42],
              "x_bounds": [0.0, 0.5], "speed_big": [0.06, 0.14], "speed_slow": [0.005, 0.02],
              "step_small": [0.001, 0.008], "step_slow": [0.01, 0.04],
              "dither_amp": 4.0, "P0": 3.5e6, "PB0": 0.8e6, "Fext_amp": 0.0}
LIN_COLS = {"P1": ("P1", "Pa"), "P2": ("P2", "Pa"), "x": ("x", "m"), "v": ("v", "m/s")}

CBV_EXTRA = {"cbv": 1, "V_lA": 3.0e-4, "p_cr": 4.2e6, "C1": 3.0, "A0": 1.5e-3, "A1": 5e-4,
             "n0": 0.5, "Cv_check": 3.33e-6}

ROT_NOMINAL = {
    "kind": "rotary", "cbv": 0, "Kv": 3.0e-8, "tau_v": 0.008, "s_max": 1000.0,
    "A_A": 2.0e-5, "A_B": 2.0e-5, "V10": 6.0e-5, "V20": 6.0e-5, "beta": 1.5e9,
    "c_il": 0.0, "c_el": 0.0, "m": 0.8, "W": 60.0, "theta0": 0.0,
    "kv_p": 0.5, "kv_m": 0.5, "kc_p": 2.0, "kc_m": 2.0, "ks_p": 0.0, "ks_m": 0.0,
    "taus_p": 0.05, "taus_m": 0.05, "eps": 1e-3, "Pd": 1e5, "dp_lam": 5e4,
}
ROT_PERTURB = {**{k: (_STD, "") for k in ("Kv", "tau_v", "s_max", "V10", "V20", "beta", "m", "W")},
               "kv_p": (_STD, "kv"), "kv_m": (_STD, "kv"), "kc_p": (_STD, "kc"),
               "kc_m": (_STD, "kc"), "A_A": (_TOL, "D"), "A_B": (_TOL, "D")}
ROT_BENCH = {"Ps0": 1.0e7, "ripple_amp": 5e4, "ripple_freq": 25.0, "slow_amp": 3e4,
             "droop_gain": 2e9, "droop_tau": 0.03, "ctrl_Kp": 180.0, "ctrl_Ki": 90.0,
             "u_max": 100.0, "x_home": 0.0, "setpoint_range": [-0.8, 0.8],
             "x_bounds": [-1.4, 1.4], "speed_big": [0.8, 1.6], "speed_slow": [0.05, 0.2],
             "step_small": [0.01, 0.06], "step_slow": [0.08, 0.3],
             "dither_amp": 4.0, "P0": 5.0e6, "PB0": 5.0e6, "Fext_amp": 0.0}
ROT_COLS = {"P1": ("P1", "Pa"), "P2": ("P2", "Pa"), "x": ("theta", "rad"), "v": ("w", "rad/s")}

# hoist winch (machines/hoist_winch.yaml): a 500 cm^3/rev motor on a 0.15 m drum holding a
# 400 kg hook load, W = m g r (constant), J = m r^2 + 1 kg m^2; A_A = A_B = D [m^3/rad]; the
# valve's centre leakage G_leak (per edge, measured: fixed in the machine file, in the truth
# within +-1.5 % like the displacement) damps the hydraulic mode (~9 Hz) and holds the
# pressure level at rest. At rest it acts as a cross-port leak G (P1 - P2) that the spool's
# offset makes up for: a +-15 % error in it is an internal leakage of its own (a null case
# with G 10 % off was diagnosed internal_leakage). Small dither: the mode is light.
WINCH_D = 500e-6 / (2.0 * math.pi)
WINCH_NOMINAL = {
    "kind": "winch", "cbv": 0, "Kv": 4.0e-7, "G_leak": 3.0e-12, "tau_v": 0.008, "s_max": 1000.0,
    "A_A": WINCH_D, "A_B": WINCH_D, "V10": 6.0e-4, "V20": 6.0e-4, "beta": 1.5e9,
    "c_il": 0.0, "c_el": 0.0, "m": 400.0 * 0.15 ** 2 + 1.0, "W": 400.0 * G * 0.15, "theta0": 0.0,
    "kv_p": 20.0, "kv_m": 20.0, "kc_p": 25.0, "kc_m": 25.0, "ks_p": 0.0, "ks_m": 0.0,
    "taus_p": 0.05, "taus_m": 0.05, "eps": 1e-3, "Pd": 1e5, "dp_lam": 5e4,
}
WINCH_PERTURB = {**ROT_PERTURB, "G_leak": (_TOL, "")}      # the rotary drive's, plus the centre leakage
WINCH_BENCH = {"Ps0": 1.6e7, "ripple_amp": 8e4, "ripple_freq": 30.0, "slow_amp": 5e4,
               "droop_gain": 2e8, "droop_tau": 0.03, "ctrl_Kp": 40.0, "ctrl_Ki": 20.0,
               "u_max": 100.0, "x_home": 0.0, "setpoint_range": [-15.0, 15.0],
               "x_bounds": [-40.0, 40.0], "speed_big": [2.0, 4.0], "speed_slow": [0.1, 0.4],
               "step_small": [0.02, 0.15], "step_slow": [0.2, 0.8],
               "dither_amp": 1.5, "P0": 1.17e7, "PB0": 4.3e6, "Fext_amp": 0.0,
               # no move shorter than 0.6 s: a short fast move (0.4 rad in 0.2 s) takes a
               # torque J a ~ W and drives a chamber below 0 bar (the truth has no cavitation)
               "T_min": 0.6}

EHA_BENCH = {"Ps0": 1.0e7, "ripple_amp": 5.0e4, "ripple_freq": 25.0, "slow_amp": 3e4,
             "droop_gain": 3.0e8, "droop_tau": 0.02, "ctrl_Kp": 500.0, "ctrl_Ki": 250.0,
             "u_max": 60.0, "x_home": 0.07, "setpoint_range": [0.045, 0.195],
             "x_bounds": [-0.08, 0.25], "speed_big": [0.08, 0.14], "speed_slow": [0.008, 0.02],
             "step_small": [0.001, 0.006], "step_slow": [0.008, 0.025],
             "dither_amp": 2.2, "P0": 5.0e6, "PB0": 5.0e6, "Fext_amp": 1450.0}

MACHINES = {
    "lift": MachineType("lift", "actuator", "luffing_cylinder.yaml", LIFT_NOMINAL, LIFT_PERTURB,
                        LIFT_BENCH, LIN_COLS),
    "lift_cbv": MachineType("lift_cbv", "actuator", "luffing_cylinder_cbv.yaml",
                            {**LIFT_NOMINAL, **CBV_EXTRA},
                            {**LIFT_PERTURB, "p_cr": (0.08, ""), "A0": (_STD, "")},
                            LIFT_BENCH, LIN_COLS),
    "rotary": MachineType("rotary", "actuator", "rotary_drive.yaml", ROT_NOMINAL, ROT_PERTURB,
                          ROT_BENCH, ROT_COLS),
    "eha": MachineType("eha", "eha", "eha_testbench.yaml", dict(EHA_NOMINAL),
                       {**{k: (_STD, "") for k in EHA_PERTURBED}, "s_max": (_STD, ""),
                        "A": (_TOL, "")}, EHA_BENCH, LIN_COLS, with_fext=True),
    "winch": MachineType("winch", "actuator", "hoist_winch.yaml", WINCH_NOMINAL, WINCH_PERTURB,
                         WINCH_BENCH, ROT_COLS),
}


def perturbed_params(mt: MachineType, rng) -> tuple[dict, dict]:
    """Seeded perturbation of the nominal parameters; returns (params, factors)."""
    p = dict(mt.nominal)
    fac, groups = {}, {}
    for k in sorted(mt.perturb):
        half, tie = mt.perturb[k]
        if tie and tie in groups:
            f = groups[tie]
        else:
            f = float(rng.uniform(1.0 - half, 1.0 + half))
            if tie:
                groups[tie] = f
        fac[k] = f
        p[k] = mt.nominal[k] * f
    if mt.name.startswith("lift"):
        p["W"] = p["m"] * G          # the load's weight follows its (perturbed) mass
    return p, fac
