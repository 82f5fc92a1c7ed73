"""Which effects each machine carries, in which truth forms, at which nominal size.

``FORMS[effect][form] = (class, {machine: params}, scale)``: ``scale`` maps a parameter to
how it follows the size factor s chosen by the generator's calibration: an exponent
(value * s**e; e = -1 for a stiffness: softer is a larger effect) or ``"d"`` for a gain
ratio (1 + (value - 1) s). An empty ``scale`` means the size is not calibrated (end stops:
the size is set by how often the setpoints reach the stop). ``LIMITS`` clips parameters that
have a physical ceiling. Machines without an entry for a form do not carry it. The third forms
(``THIRD``, classes in truth/third_forms.py; ``THIRD_FORMS``: form -> effect) follow each
effect's first two and are generated only when named (``--forms``); so are the fourth forms
(``FOURTH``, truth/fourth_forms.py; ``FOURTH_FORMS``), appended after the third, and the fifth
(``FIFTH``, truth/fifth_forms.py; ``FIFTH_FORMS``), appended after the fourth.
"""
from __future__ import annotations

import math

from experiments.concealed.truth import effects as C

from .machines import MACHINES
from .truth import fifth_forms as VF
from .truth import forms as F
from .truth import fourth_forms as QF
from .truth import third_forms as TF
from .truth import winch as WN

_ALL = ("lift", "lift_cbv", "rotary", "eha")
_NO_CBV = ("lift", "rotary", "eha")


def _per(lift, rotary, eha, machines=_ALL, winch=None):
    """{machine: params} of one form; ``winch`` (keyword, optional) adds the hoist winch's
    parameters to the machines listed (a form without them is not carried by the winch)."""
    table = {"lift": lift, "lift_cbv": lift, "rotary": rotary, "eha": eha, "winch": winch}
    if winch is not None:
        machines = tuple(machines) + ("winch",)
    return {m: table[m] for m in machines}


def _same(params, winch=None):
    """One parameter set for every machine (valve, command and sensor effects, in % and s);
    the winch's own when given."""
    return _per(params, params, params, winch=params if winch is None else winch)


FORMS = {
    "internal_leakage": {
        "laminar": (F.LaminarInternalLeakage, _per({"c": 3e-12}, {"c": 5e-13}, {"c": 2e-11}, winch={"c": 5e-13}),
                    {"c": 1}),
        "orifice": (C.InternalLeakage, _per({"K_t": 7.5e-9, "dp_t": 2e5}, {"K_t": 1e-9, "dp_t": 2e5},
                                            {"K_t": 2.5e-8, "dp_t": 2e5}, winch={"K_t": 6.8e-10, "dp_t": 2e5}),
                    {"K_t": 1}),
    },
    "external_leakage": {
        "rod_seal_laminar": (F.RodSealLeakage, _per({"c": 3e-12}, {"c": 5e-13}, {"c": 2e-11}, winch={"c": 5.7e-13}),
                             {"c": 1}),
        "orifice_both": (C.ExternalLeakage, _per({"K_e1": 7e-9, "K_e2": 3e-9, "dp_t": 1e5},
                                                 {"K_e1": 9e-10, "K_e2": 4e-10, "dp_t": 1e5},
                                                 {"K_e1": 1.1e-8, "K_e2": 4e-9, "dp_t": 1e5},
                                                 winch={"K_e1": 6.7e-10, "K_e2": 2.9e-10, "dp_t": 1e5}),
                         {"K_e1": 1, "K_e2": 1}),
    },
    "viscous_friction": {
        "linear": (F.LinearViscous, _per({"b": 6000.0}, {"b": 0.5}, {"b": 12000.0}, winch={"b": 8.5}), {"b": 1}),
        "shear_thinning": (F.ThinningViscous, _per({"b": 6000.0, "v1": 0.02}, {"b": 0.5, "v1": 0.3},
                                                   {"b": 12000.0, "v1": 0.02}, winch={"b": 10.0, "v1": 1.0}),
                           {"b": 1}),
    },
    "coulomb_friction": {
        "tanh_wide": (F.TanhCoulomb, _per({"Fc": 550.0, "v_c": 0.004}, {"Fc": 2.0, "v_c": 0.04},
                                          {"Fc": 1100.0, "v_c": 0.004}, winch={"Fc": 6.8, "v_c": 0.05}),
                      {"Fc": 1}),
        "atan_asym": (F.AtanCoulomb, _per({"Fc_p": 500.0, "Fc_m": 600.0, "v_c": 0.002},
                                          {"Fc_p": 2.0, "Fc_m": 2.4, "v_c": 0.02},
                                          {"Fc_p": 380.0, "Fc_m": 480.0, "v_c": 0.002},
                                          winch={"Fc_p": 6.5, "Fc_m": 7.8, "v_c": 0.02}),
                      {"Fc_p": 1, "Fc_m": 1}),
    },
    "stribeck_friction": {
        "gaussian": (C.StribeckFriction, _per({"Fs_p": 800.0, "Fs_m": 600.0, "vs_p": 0.006, "vs_m": 0.004},
                                              {"Fs_p": 3.0, "Fs_m": 2.5, "vs_p": 0.05, "vs_m": 0.04},
                                              {"Fs_p": 600.0, "Fs_m": 450.0, "vs_p": 0.006, "vs_m": 0.004},
                                              winch={"Fs_p": 18.0, "Fs_m": 13.0, "vs_p": 0.1, "vs_m": 0.08}),
                     {"Fs_p": 1, "Fs_m": 1}),
        "lugre": (F.LuGreStribeck, _per({"Fs": 800.0, "vs": 0.005, "F0": 50.0, "s0": 1e8, "s1": 3000.0},
                                        {"Fs": 3.0, "vs": 0.05, "F0": 0.2, "s0": 3e4, "s1": 5.0},
                                        {"Fs": 600.0, "vs": 0.005, "F0": 40.0, "s0": 1e8, "s1": 2000.0},
                                        winch={"Fs": 25.0, "vs": 0.1, "F0": 1.2, "s0": 3e5, "s1": 60.0}),
                  {"Fs": 1, "F0": 1}),
    },
    "pressure_dependent_friction": {
        "dp_seal": (F.DiffPressureFriction, _per({"mu": 0.03, "eps2": 0.002}, {"mu": 0.03, "eps2": 0.02},
                                                 {"mu": 0.22, "eps2": 0.001}, winch={"mu": 0.025, "eps2": 0.02}),
                    {"mu": 1}),
        "rod_seal": (F.RodSealPressureFriction, _per({"mu": 0.05, "eps2": 0.002}, {"mu": 0.05, "eps2": 0.02},
                                                     {"mu": 0.1, "eps2": 0.001}, winch={"mu": 0.032, "eps2": 0.02}),
                     {"mu": 1}),
    },
    "entrained_air": {
        "isothermal_dissolving": (C.EntrainedAir, _per({"alpha0": 0.5, "P_sat": 1.5e7},
                                                       {"alpha0": 0.5, "P_sat": 1.5e7},
                                                       {"alpha0": 0.8, "P_sat": 1.5e7},
                                                       winch={"alpha0": 0.047, "P_sat": 1.7e7}), {"alpha0": 1}),
        "polytropic": (F.PolytropicAir, _per({"alpha0": 0.1}, {"alpha0": 0.1}, {"alpha0": 0.15}, winch={"alpha0": 0.013}),
                       {"alpha0": 1}),
    },
    "line_dynamics": {
        "single_T": (C.LineDynamics, _per({"V_h": 4.5e-4, "I": 3.1e7, "R_l": 3.1e8, "R_t": 1e10},
                                          {"V_h": 8.5e-5, "I": 9.2e7, "R_l": 3.8e9, "R_t": 1e12},
                                          {"V_h": 1.7e-4, "I": 1.85e8, "R_l": 7.6e9, "R_t": 1.2e12},
                                          _NO_CBV, winch={"V_h": 1.7e-4, "I": 1.3e7, "R_l": 1.3e8, "R_t": 4.3e9}),
                     {"V_h": 1, "I": 1, "R_l": 1, "R_t": 1}),
        "distributed_3": (F.DistributedLines, _per({"V_h": 4.5e-4, "I": 3.1e7, "R_l": 3.1e8},
                                                   {"V_h": 8.5e-5, "I": 9.2e7, "R_l": 3.8e9},
                                                   {"V_h": 1.7e-4, "I": 1.85e8, "R_l": 7.6e9}, _NO_CBV,
                                                   winch={"V_h": 1.6e-4, "I": 1.2e7, "R_l": 1.2e8}),
                          {"V_h": 1, "I": 1, "R_l": 1}),
    },
    "valve_overlap": {
        "rounded": (C.ValveOverlap, _same({"overlap": 1.5, "edge_radius": 0.6},
                                          {"overlap": 0.42, "edge_radius": 0.17}), {"overlap": 1, "edge_radius": 1}),
        "sharp_unequal": (F.SharpAsymOverlap, _same({"o_p": 1.5, "o_m": 0.8}, {"o_p": 0.31, "o_m": 0.17}), {"o_p": 1, "o_m": 1}),
    },
    "valve_hysteresis": {
        "dahl": (F.DahlHysteresis, _same({"h": 0.8, "sigma": 6.0, "eps": 0.5},
                                         {"h": 0.15, "sigma": 6.0, "eps": 0.5}), {"h": 1}),
        "play": (F.PlayHysteresis, _same({"h": 0.5}, {"h": 0.035}), {"h": 1}),
    },
    "valve_asymmetry": {
        "four_edges": (F.EdgeAsymmetry, _same({"g_PA": 1.25, "g_BT": 1.15, "g_PB": 0.8, "g_AT": 0.85},
                                              {"g_PA": 1.08, "g_BT": 1.048, "g_PB": 0.936, "g_AT": 0.952}),
                       {"g_PA": "d", "g_BT": "d", "g_PB": "d", "g_AT": "d"}),
        "solenoid_gain": (F.SolenoidAsymmetry, _same({"g_p": 1.15, "g_m": 0.88}, {"g_p": 1.132, "g_m": 0.894}),
                          {"g_p": "d", "g_m": "d"}),
    },
    "input_delay": {
        "pure": (C.InputDelay, _same({"T_d": 0.01}, {"T_d": 0.005}), {"T_d": 1}),
        "lag_cascade": (F.LagCascadeDelay, _same({"T_d": 0.015}, {"T_d": 0.005}), {"T_d": 1}),
    },
    "load_compliance": {
        "cubic_split_mass": (C.LoadCompliance, _per({"frac_p": 0.35, "k": 2.4e6, "k3": 5e11, "c": 2000.0},
                                                    {"frac_p": 0.35, "k": 1900.0, "k3": 3.8e6, "c": 1.0},
                                                    {"frac_p": 0.35, "k": 8e5, "k3": 1.6e11, "c": 700.0},
                                                    # winch: a torsionally compliant shaft/gearbox
                                                    winch={"frac_p": 0.2, "k": 1.5e5, "k3": 1e9, "c": 50.0}),
                             {"k": -1, "k3": -1}),
        "linear_dry_joint": (F.FrictionJointCompliance,
                             _per({"frac_p": 0.1, "k": 2.4e6, "c": 500.0, "Fd": 300.0, "vd": 1e-3},
                                  {"frac_p": 0.15, "k": 1900.0, "c": 0.3, "Fd": 1.0, "vd": 0.01},
                                  {"frac_p": 0.3, "k": 8e5, "c": 200.0, "Fd": 150.0, "vd": 1e-3},
                                  winch={"frac_p": 0.15, "k": 5.9e4, "c": 3.0, "Fd": 10.0, "vd": 0.01}),
                             {"k": -1}),
    },
    "structural_flexibility": {
        "mount_linear": (F.CompliantMount, _per({"m_b": 300.0, "k_b": 1e7, "c_b": 1.1e4},
                                                {"m_b": 0.2, "k_b": 3e3, "c_b": 2.0},
                                                {"m_b": 30.0, "k_b": 5e6, "c_b": 4000.0},
                                                winch={"m_b": 2.0, "k_b": 2.6e5, "c_b": 20.0}), {"k_b": -1}),
        "bushing_cubic": (F.CompliantMount, _per({"m_b": 300.0, "k_b": 1e7, "k3": 1e13, "c_b": 5000.0},
                                                 {"m_b": 0.2, "k_b": 3e3, "k3": 3e7, "c_b": 1.0},
                                                 {"m_b": 30.0, "k_b": 5e6, "k3": 5e12, "c_b": 2000.0},
                                                 winch={"m_b": 2.0, "k_b": 2e3, "k3": 2e7, "c_b": 10.0}),
                          {"k_b": -1, "k3": -1}),
    },
    "payload_swing": {
        "rope_pendulum": (F.RopePendulum, {"rotary": {"m_p": 3.0, "r": 0.6, "L": 0.5, "c_r": 0.05}},
                          {"m_p": 1}),
        "tip_spring_mass": (F.TangentialSpringPayload,
                            {"rotary": {"m_p": 3.0, "r": 0.6, "k": 170.0, "c": 1.5}}, {"m_p": 1}),
        # a hook load on the lifting cylinder's rope (session 40): part of the load bounces
        "rope_bounce": (F.RopeBouncePayload, _per({"m_frac": 0.3, "f_hz": 1.2, "zeta": 0.01}, None, None,
                                                  machines=("lift", "lift_cbv")), {"m_frac": 1}),
        "sheave_friction": (F.SheaveFrictionPayload,
                            _per({"m_frac": 0.4, "f_hz": 1.8, "zeta": 0.005, "mu": 0.003}, None, None,
                                 machines=("lift", "lift_cbv")), {"m_frac": 1}),
        # the winch's hook load on the rope its drum pays out (rope stiffness EA/L, L = L0 - r theta)
        "drum_rope": (WN.DrumRopeBounce, {"winch": {"m_frac": 0.85, "r": 0.15, "L0": 6.0, "f_hz": 24.0,
                                                    "zeta": 0.02}}, {"f_hz": -1}),
        "drum_sheave": (WN.DrumSheaveFriction, {"winch": {"m_frac": 0.85, "r": 0.15, "L0": 6.0, "f_hz": 16.0,
                                                          "zeta": 0.005, "mu": 0.003}}, {"f_hz": -1}),
    },
    "end_stop": {
        "hunt_crossley": (C.EndStop, _per({"x_stop": 0.34, "k": 1e11, "lam": 15.0},
                                          {"x_stop": 0.50, "k": 1e7, "lam": 15.0},
                                          {"x_stop": 0.128, "k": 6e10, "lam": 15.0}), {}),
        "bumper_linear": (F.LinearBumper, _per({"x_stop": 0.34, "k": 5e6, "c": 2e4},
                                               {"x_stop": 0.50, "k": 3e3, "c": 10.0},
                                               {"x_stop": 0.128, "k": 2e6, "c": 5e3}), {}),
    },
    "supply_pressure_drop": {
        "turbulent_accumulator": (C.SupplyPressureDrop,
                                  _per({"K_s": 8.2e-7, "P0": 9.6e6, "Vg0": 1e-4, "n": 1.4, "V_l": 1e-3, "Pv0": 1.6e7},
                                       {"K_s": 2e-8, "P0": 6e6, "Vg0": 5e-6, "n": 1.4, "V_l": 5e-5, "Pv0": 1e7},
                                       {"K_s": 1e-7, "P0": 6e6, "Vg0": 2e-5, "n": 1.4, "V_l": 2e-4, "Pv0": 1e7},
                                       winch={"K_s": 4.1e-7, "P0": 9.6e6, "Vg0": 1e-4, "n": 1.4, "V_l": 1e-3,
                                              "Pv0": 1.6e7}),
                                  {"K_s": -1}),
        "laminar_line": (F.LaminarSupplyLine, _per({"R_s": 1.5e9, "V_l": 1e-3, "C_w": 1e-13, "Pv0": 1.6e7},
                                                   {"R_s": 5e10, "V_l": 5e-5, "C_w": 1e-14, "Pv0": 1e7},
                                                   {"R_s": 1e10, "V_l": 2e-4, "C_w": 0.0, "Pv0": 1e7},
                                                   winch={"R_s": 8.8e8, "V_l": 1e-3, "C_w": 1e-13, "Pv0": 1.6e7}),
                         {"R_s": 1}),
    },
    "sensor_lag": {
        "velocity_2nd_order": (C.SensorLag, _same({"f_c": 5.0, "zeta": 0.7}, {"f_c": 0.55, "zeta": 0.7}), {"f_c": -1}),
        "pressure_1st_order": (F.PressureSensorLag, _same({"tau_p": 0.005}, {"tau_p": 0.008}), {"tau_p": 1}),
    },
}

# the scored band: the middle third of each machine's setpoint range (lift [0.08, 0.42] m,
# vane [-0.8, 0.8] rad, EHA [0.045, 0.195] m), logistic edges d ~ 1 % of the stroke
# third forms (session 48, truth/third_forms.py): appended after each effect's two forms; the
# generator writes them only when --forms names them (generate.all_cases).
THIRD = {
    "entrained_air": {
        "pocket_chamber_A": (TF.AirPocketChamberA, _per({"V_g0": 2.0e-4}, {"V_g0": 2.0e-5}, {"V_g0": 1.5e-4}),
                             {"V_g0": 1}),
    },
    "internal_leakage": {
        "scored_bore": (TF.ScoredBoreLeakage, _per({"c": 9e-12, "x1": 0.193, "x2": 0.307, "d": 0.005},
                                                   {"c": 1.5e-12, "x1": -0.267, "x2": 0.267, "d": 0.03},
                                                   {"c": 6e-11, "x1": 0.095, "x2": 0.145, "d": 0.003}),
                        {"c": 1}),
    },
    "pressure_dependent_friction": {
        "both_seals_gauge": (TF.BothSealsGaugeFriction, _per({"mu": 0.02, "eps2": 0.002}, {"mu": 0.01, "eps2": 0.02},
                                                             {"mu": 0.015, "eps2": 0.001}), {"mu": 1}),
    },
    "stribeck_friction": {
        "exponential": (TF.ExponentialStribeck, _per({"Fs": 800.0, "vs": 0.005, "v_eps": 5e-4},
                                                     {"Fs": 3.0, "vs": 0.05, "v_eps": 5e-3},
                                                     {"Fs": 600.0, "vs": 0.005, "v_eps": 5e-4}), {"Fs": 1}),
    },
    "input_delay": {
        "sampled_controller": (TF.SampledController, _per({"T_s": 0.01}, {"T_s": 0.01}, {"T_s": 0.01}),
                               {"T_s": 1}),
    },
    "sensor_lag": {
        # not on the vane: its rate is a tachometer's, and a lagged angle alone leaves the
        # signals the size is measured on (P1, P2, v) unchanged
        "position_1st_order": (TF.PositionSensorLag, _per({"tau_x": 0.015}, None, {"tau_x": 0.015}, ("lift", "lift_cbv", "eha")),
                               {"tau_x": 1}),
    },
    "line_dynamics": {
        "hose_A_only": (TF.HoseALine, _per({"V_h": 4.5e-4, "beta_h": 6e8, "I": 3.1e7, "R_l": 3.1e8},
                                           {"V_h": 8.5e-5, "beta_h": 6e8, "I": 9.2e7, "R_l": 3.8e9},
                                           {"V_h": 1.7e-4, "beta_h": 6e8, "I": 1.85e8, "R_l": 7.6e9}, _NO_CBV),
                        {"V_h": 1, "I": 1, "R_l": 1}),
    },
    "structural_flexibility": {
        # the dry damper's slip force is a fraction of the force swings the mount carries (a
        # larger one locks the bushing: no deflection whatever its stiffness), its slope F_d/v_d
        # about half the critical damping 2 sqrt(k_b m_b)
        "mount_dry_damped": (TF.DryDampedMount, _per({"m_b": 300.0, "k_b": 1e7, "c_b": 3000.0, "F_d": 100.0, "v_d": 2e-3},
                                                     {"m_b": 0.2, "k_b": 3e3, "c_b": 0.5, "F_d": 0.5, "v_d": 0.02},
                                                     {"m_b": 30.0, "k_b": 5e6, "c_b": 1000.0, "F_d": 100.0,
                                                      "v_d": 5e-3}), {"k_b": -1}),
    },
    "end_stop": {
        "hydraulic_cushion": (TF.HydraulicCushion, _per({"x_stop": 0.34, "L_c": 0.008, "K_end": 5e-9, "k": 1e11, "lam": 15.0},
                                                        {"x_stop": 0.50, "L_c": 0.05, "K_end": 4.5e-10, "k": 1e7,
                                                         "lam": 15.0},
                                                        {"x_stop": 0.128, "L_c": 0.005, "K_end": 3.3e-9, "k": 6e10,
                                                         "lam": 15.0}), {}),
    },
}
for _e, _forms in THIRD.items():
    FORMS[_e].update(_forms)
THIRD_FORMS = {f: e for e, fs in THIRD.items() for f in fs}

# fourth forms (session 54, truth/fourth_forms.py): physically different again from every form
# above, the winch included where the physics fits; appended after the third, generated only
# when --forms names them (generate.all_cases), like the third
_LIFT_W = MACHINES["lift"].nominal["W"]      # the lift's static load [N] (its mount's knee)
_WINCH_W = MACHINES["winch"].nominal["W"]    # the winch's static load torque [N m]
FOURTH = {
    # the cracking pressures sit near the median chamber pressure of each bench's recordings
    "external_leakage": {
        "cracking_drain": (QF.CrackingDrainLeakage,
                           _per({"K_r": 3.3e-15, "P_cr": 8.5e6}, {"K_r": 2.8e-16, "P_cr": 5.4e6},
                                {"K_r": 7.5e-15, "P_cr": 5.0e6}, winch={"K_r": 9.4e-15, "P_cr": 1.15e7}),
                           {"K_r": 1}),
    },
    "internal_leakage": {
        "elastic_gap": (QF.ElasticGapLeakage,
                        _per({"c0": 2e-12, "p_h": 3e6}, {"c0": 3e-13, "p_h": 1e6}, {"c0": 1e-11, "p_h": 1.5e6},
                             winch={"c0": 2.3e-14, "p_h": 5e6}), {"c0": 1}),
    },
    "coulomb_friction": {
        "tight_spot": (QF.TightSpotCoulomb,
                       _per({"Fc_p": 500.0, "Fc_m": 600.0, "a": 2.0, "x1": 0.25, "x2": 0.33, "d": 0.005, "v_c": 0.004},
                            {"Fc_p": 2.0, "Fc_m": 2.4, "a": 2.0, "x1": 0.2, "x2": 0.55, "d": 0.03, "v_c": 0.04},
                            {"Fc_p": 500.0, "Fc_m": 600.0, "a": 2.0, "x1": 0.12, "x2": 0.16, "d": 0.003,
                             "v_c": 0.004},
                            # the winch: once per drum revolution (an eccentric bearing)
                            winch={"Fc_p": 6.5, "Fc_m": 7.8, "a": 2.0, "x1": 0.0, "period": 2.0 * math.pi,
                                   "v_c": 0.05}),
                       {"Fc_p": 1, "Fc_m": 1}),
    },
    "entrained_air": {
        "dissolving_free_air": (QF.DissolvingAir,
                                _per(*[{"alpha0": a0, "B": 0.09, "P_sat": 1e5, "tau_r": 0.2, "tau_a": 30.0}
                                       for a0 in (0.05, 0.2, 0.03)],
                                     winch={"alpha0": 0.01, "B": 0.09, "P_sat": 1e5, "tau_r": 0.2, "tau_a": 30.0}),
                                {"alpha0": 1}),
    },
    "line_dynamics": {
        "rigid_pipes_fdf": (QF.RigidPipesFDF,
                            _per(*[{"r": r, "L": L, "rho": 870.0, "nu": 4.6e-5}
                                   for r, L in ((0.006, 5.0), (0.002, 1.5), (0.003, 3.0))], _NO_CBV,
                                 winch={"r": 0.008, "L": 4.0, "rho": 870.0, "nu": 4.6e-5}),
                            {"L": 1}),
    },
    "valve_overlap": {
        "underlap": (QF.UnderlapSpool, _same({"U": 1.0}, {"U": 0.3}), {"U": 1}),
    },
    "input_delay": {
        "network_jitter": (QF.JitterDelay, _same({"T_d": 0.01, "j": 0.4, "seed": 54},
                                                 {"T_d": 0.005, "j": 0.4, "seed": 54}), {"T_d": 1}),
    },
    # a transducer on a long test-point hose: a Helmholtz resonance at tens of Hz (at the 150-300 Hz
    # of a bare transducer the recordings carry too little content to show it)
    "sensor_lag": {
        "resonant_pressure": (QF.ResonantPressureSensor, _same({"f_n": 40.0, "zeta": 0.05}), {"f_n": -1}),
    },
    # the flow limits sit near the top percent of each bench's supply flow: a pump a little too
    # small for the fastest moves. The effect is steep in Q_max (nothing above the largest
    # demand, a drifting replay a little below): the size goes as its fourth root, so that the
    # calibration's secant (slopes clipped to 0.3-4) can bracket the target
    "supply_pressure_drop": {
        "flow_limited_pump": (QF.FlowLimitedPump,
                              _per({"Q_max": 6e-4, "V_l": 1e-3, "tau_c": 0.02},
                                   {"Q_max": 4e-6, "V_l": 5e-5, "tau_c": 0.02},
                                   {"Q_max": 2.5e-4, "V_l": 2e-4, "tau_c": 0.02},
                                   winch={"Q_max": 2.5e-4, "V_l": 1e-3, "tau_c": 0.02}),
                              {"Q_max": -0.25}),
    },
    "structural_flexibility": {
        "bilinear_mount": (QF.BilinearMount,
                           _per({"m_b": 300.0, "k_b": 1e7, "r": 3.0, "c_b": 1.1e4, "F_k": _LIFT_W},
                                {"m_b": 0.2, "k_b": 3e3, "r": 3.0, "c_b": 2.0, "F_k": 0.0},
                                {"m_b": 30.0, "k_b": 5e6, "r": 3.0, "c_b": 4000.0, "F_k": 0.0},
                                winch={"m_b": 2.0, "k_b": 2.6e5, "r": 3.0, "c_b": 20.0, "F_k": _WINCH_W}),
                           {"k_b": -1}),
    },
}
for _e, _forms in FOURTH.items():
    FORMS[_e].update(_forms)
FOURTH_FORMS = {f: e for e, fs in FOURTH.items() for f in fs}

# fifth forms (session 64, truth/fifth_forms.py): physically different again from every form
# above; appended after the fourth, generated only when --forms names them (generate.all_cases)
_WARM = {"dT_max": 20.0, "k_T": 0.03, "tau_T": 15.0}       # 20 K over a record, tau 15 s, HLP oil
FIFTH = {
    # the rod side of the single-rod lifts; both seals of the double-rod EHA, the vane, the motor
    "external_leakage": {
        "film_drag_out": (VF.FilmDragLeakage,
                          _per({"c": 1.3e-12, "v_ref": 0.1, "v_eps": 1e-3, "both": 0},
                               {"c": 1e-13, "v_ref": 1.0, "v_eps": 0.01, "both": 1},
                               {"c": 3e-12, "v_ref": 0.1, "v_eps": 1e-3, "both": 1},
                               winch={"c": 3.5e-13, "v_ref": 3.0, "v_eps": 0.03, "both": 1}),
                          {"c": 1}),
    },
    "internal_leakage": {
        "warming_bypass": (VF.WarmingBypassLeakage,
                           _per({"c0": 2.5e-12, **_WARM}, {"c0": 3e-13, **_WARM}, {"c0": 7e-12, **_WARM},
                                winch={"c0": 7.5e-13, **_WARM}), {"c0": 1}),
    },
    "viscous_friction": {
        "warming_viscous": (VF.WarmingViscous,
                            _per({"b0": 25000.0, **_WARM}, {"b0": 5.0, **_WARM}, {"b0": 9000.0, **_WARM},
                                 winch={"b0": 6.0, **_WARM}), {"b0": 1}),
    },
    # the branch's corner 1/(2 pi R C_g) at 1-6 Hz at the chamber's typical pressure; the size
    # scales the gas AND the bore's conductance (R / s), so the corner stays where it is: with R
    # fixed a larger pocket only moves the corner below the band and the effect saturates at the
    # restriction's (rotary s173 went to 50 x V_g: 1.3 l of gas on a 60 cm3 chamber, for 8 %)
    "entrained_air": {
        "pocket_behind_orifice": (VF.BranchGasPocket,
                                  _per({"V_gA": 1.7e-4, "R_A": 5e10, "V_gB": 3.4e-5, "R_B": 5e10},
                                       {"V_gA": 2.6e-5, "R_A": 3.7e11, "V_gB": 2.6e-5, "R_B": 3.7e11},
                                       {"V_gA": 1.4e-4, "R_A": 7.5e10, "V_gB": 1.4e-4, "R_B": 7.5e10},
                                       winch={"V_gA": 1e-4, "R_A": 4e11, "V_gB": 3e-5, "R_B": 2e11}),
                                  {"V_gA": 1, "V_gB": 1, "R_A": -1, "R_B": -1}),
    },
    # a stiff steel pin / key (k: a joint mode near 370-550 Hz, damping ratio ~0.1 in contact).
    # Not on the lifts nor the winch: their hanging load presses the joint one way (its weight far
    # above the inertial forces of the moves), so the clearance never opens, only the pin's
    # stiffness would show and the size b could not set the effect
    "load_compliance": {
        "pin_clearance": (VF.ClearanceJoint,
                          _per(None, {"frac_p": 0.35, "k": 1e6, "c": 85.0, "b": 6e-3},
                               {"frac_p": 0.35, "k": 2e8, "c": 1.16e4, "b": 1e-4}, ("rotary", "eha")),
                          {"b": 1}),
    },
    "input_delay": {
        "moving_average": (VF.MovingAverageDelay, _per({"T": 0.03}, {"T": 0.006}, {"T": 0.03}, winch={"T": 0.012}),
                           {"T": 1}),
    },
    # not on the winch: its drum speed changes over seconds, so a window of at most 50 ms changes
    # its recorded rate by an effect ESR of 0.2-0.4 % (seeds 172, 173), below the generator's range
    "sensor_lag": {
        "differenced_velocity": (VF.DifferencedVelocity, _per({"T": 0.04}, {"T": 0.03}, {"T": 0.03}), {"T": 1}),
    },
    # the compensator's lag: 0.15 s on the lifts (their flow demand changes over ~1 s moves: a
    # faster compensator would need a gain dipping > 100 bar on a step to show), 0.1 s elsewhere;
    # k q of a full-flow step: 60 bar (lifts), 10-20 bar (vane, EHA, winch)
    "supply_pressure_drop": {
        "compensator_dip": (VF.CompensatorDip,
                            _per({"k": 1.2e10, "tau_c": 0.15}, {"k": 6e10, "tau_c": 0.1}, {"k": 3.3e9, "tau_c": 0.1},
                                 winch={"k": 6e9, "tau_c": 0.1}), {"k": 1}),
    },
}
for _e, _forms in FIFTH.items():
    FORMS[_e].update(_forms)
FIFTH_FORMS = {f: e for e, fs in FIFTH.items() for f in fs}
# the probes of forms nothing was tuned on: generated only when --forms names them
NAMED_ONLY = {**THIRD_FORMS, **FOURTH_FORMS, **FIFTH_FORMS}

LIMITS = {"alpha0": (0.0, 0.9), "frac_p": (0.05, 0.9), "m_frac": (0.002, 0.85),
          # a sampled controller no slower than 20 Hz (at 8 Hz the lift_cbv loop limit-cycles)
          "T_s": (1e-3, 0.05),
          # a transducer's resonance no lower than 15 Hz (the calibration would take it to 1 Hz:
          # a low-pass, not a resonance)
          "f_n": (15.0, 1e4),
          # a moving-average / differencing window of at least one sample, at most 50 ms
          "T": (1e-3, 0.05)}

# truth parameters the effect needs ZEROED in the truth base, and the machine-file edits that
# remove the same term from the case's base.yaml: machine -> effect -> [(truth key, yaml key,
# yaml value)]. (Effects whose classes carry ``base_overrides`` add theirs.)
_FRICTION_LIN = {
    "viscous_friction": [("kv_p", "kv_p", "{value: 0.0, free: false}"),
                         ("kv_m", "kv_m", "{value: 0.0, free: false}")],
    "coulomb_friction": [("kc_p", "kc_p", "{value: 0.0, free: false}"),
                         ("kc_m", "kc_m", "{value: 0.0, free: false}")],
}
_FRICTION_ROT = {
    "viscous_friction": [("kv_p", "b", "{value: 0.0, free: false}"), ("kv_m", None, None)],
    "coulomb_friction": [("kc_p", "tau_c", "{value: 0.0, free: false}"), ("kc_m", None, None)],
}
BASE_ZERO = {
    "lift": _FRICTION_LIN, "lift_cbv": _FRICTION_LIN, "rotary": _FRICTION_ROT, "winch": _FRICTION_ROT,
    "eha": {**_FRICTION_LIN,
            "internal_leakage": [("c_il", "c_il", "{value: 0.0, free: false}")],
            "stribeck_friction": [("ks_p", "ks_p", "{value: 0.0, free: false}"),
                                  ("ks_m", "ks_m", "{value: 0.0, free: false}"),
                                  (None, "vs_p", "{value: 3.41e-3, free: false}"),
                                  (None, "vs_m", "{value: 1.96e-3, free: false}")]},
}


def forms_of(machine: str, effect: str) -> list[str]:
    return [f for f, (_, per, _) in FORMS[effect].items() if machine in per]


def scaled_params(machine: str, effect: str, form: str, s: float) -> dict:
    _, per, scale = FORMS[effect][form]
    p = dict(per[machine])
    for k, e in scale.items():
        p[k] = 1.0 + (p[k] - 1.0) * s if e == "d" else p[k] * s ** e
        if k in LIMITS:
            p[k] = min(max(p[k], LIMITS[k][0]), LIMITS[k][1])
    return p


def make(effect: str, form: str, params: dict):
    return FORMS[effect][form][0](**params)
