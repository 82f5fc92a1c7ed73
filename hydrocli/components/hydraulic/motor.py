"""Rotary hydraulic actuators: fixed-displacement motor (seed 002) and vane actuator (seed 001)."""
from __future__ import annotations

from ..base import Component, H, Param, Port, R, VariableSpec
from ..registry import register
from .cylinder import end_stop_force
from .fluid import AIR_PARAMS, cavitation_floor, oil_bulk_modulus
from .. import roles as RL
from ..roles import role


@register
class HydraulicMotor(Component):
    """Fixed-displacement motor as a gyrator with leakages (seed 002 Fig. 3, eqs. 5, 8, 9):
    torque D_m·(p_A − p_B) on the shaft, flow D_m·ω plus internal leakage
    Q_in = (p_A − p_B)/R_m (eq. 8) and external leakage Q_ex = (p − p_drain)/R_ex from each
    chamber (eq. 9). The port nodes need volumes (hoses); optional chamber volumes V_A, V_B
    add V/β_e there, β_e with entrained air when ``air`` is set (``fluid.effective_bulk_modulus``,
    the same free-air fraction in both chambers: the oil carries it), the vane's law. Seed 002:
    R_m = 8e11, R_ex = 2.2e12 N·s/m⁵. The gearbox (N, B_sw) is a separate ``gearbox`` component."""

    type = "hydraulic_motor"
    roles = (role(RL.ACTUATOR, {"chamber_a": "A", "chamber_b": "B", "motion": "shaft", "reference": "body"}, size="D_m", displacements=("D_m",), dead_volumes=("V_A", "V_B"), bulk_modulus="beta", air="air", air_exponent="air_n", air_dissolve="p_dissolve"),)
    family = "hydraulic"
    description = "Fixed-displacement hydraulic motor with internal and external leakage"
    source = "seed 002 Fig. 3, eqs. 5, 8, 9"
    ports = (Port("A", H, "inlet (forward chamber)"), Port("B", H, "outlet (return chamber)"),
             Port("shaft", R, "motor shaft"), Port("body", R, "housing (usually ground)"),
             Port("drain", H, "case drain (if not connected: p_drain)", optional=True))
    parameters = (
        Param("D_m", "m^3/rad", 1e-5, "volumetric displacement per radian", positive=True, bounds=(1e-8, 1e-2)),
        Param("R_m", "Pa*s/m^3", 8e11, "internal (cross-port) leakage resistance", source="seed 002 eq. 8",
              positive=True, bounds=(1e9, 1e15)),
        Param("R_ex", "Pa*s/m^3", 2.2e12, "external leakage resistance of each chamber", source="seed 002 eq. 9",
              positive=True, bounds=(1e9, 1e15)),
        Param("p_drain", "Pa", 0.0, "case drain pressure when 'drain' is not connected (seed 002: 0)", min=0.0),
        Param("V_A", "m^3", 0.0, "chamber volume A (0: none; the lines carry the capacitance)", min=0.0),
        Param("V_B", "m^3", 0.0, "chamber volume B", min=0.0),
        Param("beta", "Pa", 1.5e9, "oil bulk modulus", fluid="beta", positive=True),
        *AIR_PARAMS,
    )
    variables = (VariableSpec("w", "rad/s", "shaft speed relative to the housing"),
                 VariableSpec("tau", "N*m", "hydraulic torque D_m·Δp"),
                 VariableSpec("q_in", "m^3/s", "internal leakage A→B (eq. 8)"),
                 VariableSpec("q_exA", "m^3/s", "external leakage of chamber A (eq. 9)"),
                 VariableSpec("q_exB", "m^3/s", "external leakage of chamber B (eq. 9)"))

    def equations(self, c):
        p = c.p
        pa, pb = c.across("A"), c.across("B")
        pd = c.across("drain") if c.connected("drain") else p.p_drain
        w = c.let("w", c.across("shaft") - c.across("body"))
        q_in = c.let("q_in", (pa - pb) / p.R_m)
        q_ea = c.let("q_exA", (pa - pd) / p.R_ex)
        q_eb = c.let("q_exB", (pb - pd) / p.R_ex)
        c.through("A", p.D_m * w + q_in + q_ea)
        c.through("B", -p.D_m * w - q_in + q_eb)
        if c.connected("drain"):
            c.through("drain", -(q_ea + q_eb))
        tau = c.let("tau", p.D_m * (pa - pb))
        c.through("shaft", -tau)
        c.through("body", tau)
        for port, vol in (("A", "V_A"), ("B", "V_B")):
            if c.active(vol):
                cap = c.param(vol) / oil_bulk_modulus(c, c.across(port))
                c.capacitance(port, cap)
                cavitation_floor(c, port, cap)


@register
class VaneActuator(Component):
    """Rotary vane actuator (seed 001 eqs. 9–10, 12–13): torque D_v·(p_1 − p_2) (eq. 12), flow
    D_v·ω (eq. 13), cross-vane leakage R_v·(p_1 − p_2) (eq. 20; R_v is a conductance), chamber
    capacitances (V_c + V_p ± D_v·θ)/β (eqs. 9–10), β with entrained air when ``air`` is set
    (``fluid.effective_bulk_modulus``); penalty stops at the ends of the vane's travel
    [θ_min, θ_max] (the cylinder's ``end_stop_force`` in rotary units), off while k_stop = 0."""

    type = "vane_actuator"
    roles = (role(RL.ACTUATOR, {"chamber_a": "A", "chamber_b": "B", "motion": "shaft", "reference": "body"}, size="D_v", displacements=("D_v",), swept=("D_v",), dead_volumes=("V_1", "V_2"), bulk_modulus="beta", internal_leakage="R_v", air="air", air_exponent="air_n", air_dissolve="p_dissolve", stop_min="theta_min", stop_max="theta_max", stop_stiffness="k_stop", stop_damping="c_stop"),)
    family = "hydraulic"
    description = "Rotary vane actuator with cross-port leakage and chamber compressibility"
    source = "seed 001 eqs. 9–10, 12–13, 20"
    ports = (Port("A", H, "chamber 1"), Port("B", H, "chamber 2"),
             Port("shaft", R, "vane"), Port("body", R, "housing (usually ground)"))
    parameters = (
        Param("D_v", "m^3/rad", 5e-6, "volumetric displacement", source="seed 001 eq. 12", positive=True,
              bounds=(1e-8, 1e-2)),
        Param("R_v", "m^3/s/Pa", 1e-12, "cross-vane leakage coefficient", source="seed 001 eqs. 9–10, 20",
              min=0.0, bounds=(0.0, 1e-9)),
        Param("V_1", "m^3", 2e-5, "chamber 1 + port line volume at θ = 0 (V_c1 + V_p1)", positive=True,
              bounds=(1e-7, 1e-2)),
        Param("V_2", "m^3", 2e-5, "chamber 2 + port line volume at θ = 0", positive=True, bounds=(1e-7, 1e-2)),
        Param("beta", "Pa", 1.5e9, "oil bulk modulus", fluid="beta", positive=True, bounds=(1e8, 2.5e9)),
        *AIR_PARAMS,
        Param("theta_min", "rad", -1e3, "stop at the low end of the vane's travel"),
        Param("theta_max", "rad", 1e3, "stop at the high end of the vane's travel"),
        Param("k_stop", "N*m/rad", 0.0, "stop contact stiffness (0 and not free = no stops)", min=0.0,
              bounds=(1e4, 1e10)),
        Param("c_stop", "N*m*s/rad", 0.0, "stop contact damping", min=0.0, bounds=(0.0, 1e7)),
        Param("eps_stop", "rad", 1e-5, "smoothing of the stop contact", positive=True),
    )
    variables = (VariableSpec("theta", "rad", "vane angle"), VariableSpec("w", "rad/s", "vane speed"),
                 VariableSpec("tau", "N*m", "hydraulic torque"), VariableSpec("q_leak", "m^3/s", "leakage 1→2"),
                 VariableSpec("tau_stop", "N*m", "stop torque"))

    def equations(self, c):
        p = c.p
        pa, pb = c.across("A"), c.across("B")
        th = c.let("theta", c.position("shaft") - c.position("body"))
        w = c.let("w", c.across("shaft") - c.across("body"))
        v1, v2 = p.V_1 + p.D_v * th, p.V_2 - p.D_v * th
        c.guard(v1 <= 0.0, "chamber 1 volume reached zero: check V_1 and the vane travel")
        c.guard(v2 <= 0.0, "chamber 2 volume reached zero: check V_2 and the vane travel")
        for port, vol, pr in (("A", v1, pa), ("B", v2, pb)):
            cap = vol / oil_bulk_modulus(c, pr)      # with entrained air when 'air' is set (fluid.py)
            c.capacitance(port, cap)
            cavitation_floor(c, port, cap)
        q_l = c.let("q_leak", (p.R_v if c.active("R_v") else 0.0) * (pa - pb))
        c.through("A", p.D_v * w + q_l)
        c.through("B", -p.D_v * w - q_l)
        tau = c.let("tau", p.D_v * (pa - pb))
        t_stop = c.let("tau_stop", end_stop_force(th, w, p.theta_min, p.theta_max, p.k_stop, p.c_stop, p.eps_stop)
                       if c.active("k_stop") else 0.0)
        c.through("shaft", -(tau + t_stop))
        c.through("body", tau + t_stop)

    def check(self, values):
        return ["theta_min must be below theta_max"] if values["theta_min"] >= values["theta_max"] else []
