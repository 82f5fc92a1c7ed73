"""Pressure-compensated directional valve with load sensing (seed 000 §4.1, eqs. 10–11)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, Param, VariableSpec
from ..registry import register
from .valve import (EDGE_PARAMS, FLOW_PARAMS, SPOOL_PARAMS, SPOOL_STATES, VALVE_PORTS, VALVE_VARS,
                    edge_flow, spool_position, stamp_four_edges)
from .. import roles as RL
from ..roles import role


def smooth_clamp(x, lo_width, eps):
    """min(max(x, 0), lo_width) with both corners smoothed over ``eps``."""
    lo = E.smooth_pos(x, eps)
    return lo - E.smooth_pos(lo - lo_width, eps)


def compensated_drop(p_s, p_ls, p0, eps):
    """Pressure drop across the meter-in edge behind the compensator (seed 000 eq. 10):

    * p0              when p0 ≤ p_S − p_LS   (normal operation: the compensator holds p0),
    * p_S − p_LS      when 0 < p_S − p_LS < p0 (load too close to supply: compensator wide open),
    * 0               when p_S − p_LS ≤ 0     (built-in check function: no reverse flow).

    Eq. 10 gives the compensated pressure p_comp = p_LS + p0 / … / p_LS; the metering edge sees
    p_comp − p_LS, i.e. this clamp of p_S − p_LS to [0, p0].
    """
    return smooth_clamp(p_s - p_ls, p0, eps)


@register
class ValvePcLs(Component):
    """Pressure-compensated DCV with load sensing (Danfoss PVG32 type; seed 000 §4.1).

    Same spool chain and edges as ``valve_4_3`` (eq. 9, Fig. 8, eq. 6 with C_V from eq. 8).
    The load-sensing pressure is the pressure of the fed port (eq. 11; this library's u > 0
    opens P→A, so p_LS = p_A for u > 0 and p_B for u < 0, blended smoothly across centre
    where the overlapped meter-in edges are closed). The meter-in edge flow is
    Q = ξ·C_V·sqrt(Δp_c) with Δp_c = clamp(p_S − p_LS, 0, p0) (eq. 10, three cases);
    return edges are plain orifices. Seed 000 Table 4: ω_V = 30 rad/s (τ = 1/30 s),
    ζ_V = 0.8, overlap 10 %, underlap 5 %, C_V = 37.8 L/min/bar^0.5, p0 = 7 bar.
    """

    type = "valve_pc_ls"
    roles = (role(RL.METERING_VALVE, {"supply": "P", "tank": "T", "work_a": "A", "work_b": "B", "command": "cmd"},
                  flow_gain="Kv", direction_ratio="Kv_neg_ratio",
                  overlaps=("overlap_PA", "overlap_BT", "overlap_PB", "overlap_AT"), edge_leak="G_leak",
                  spool_dynamics=("tau", "s_max"), spool_lag="tau", spool_hysteresis=("hyst_h", "hyst_sigma"),
                  spool_play=("play_b", "play_eps")),)
    family = "hydraulic"
    description = "Pressure-compensated load-sensing DCV (compensator holds p0 across the meter-in edge)"
    source = "seed 000 §4.1 eqs. 6–11, Fig. 7–8, Table 4"
    ports = VALVE_PORTS
    parameters = FLOW_PARAMS + (
        Param("p0", "Pa", 7e5, "compensator spring setting: nominal meter-in pressure drop",
              source="seed 000 eq. 10, Table 4", positive=True, bounds=(1e5, 3e6)),
        Param("eps_p", "Pa", 1e3, "smoothing of the compensator limits", positive=True),
    ) + SPOOL_PARAMS + EDGE_PARAMS
    states = SPOOL_STATES
    variables = VALVE_VARS + (
        VariableSpec("p_LS", "Pa", "load-sensing pressure (eq. 11)"),
        VariableSpec("dp_comp", "Pa", "compensated meter-in pressure drop (eq. 10)"),
    )

    def equations(self, c):
        p = c.p
        xv = spool_position(c)
        pP, pT, pA, pB = (c.across(n) for n in "PTAB")
        w = 0.5 * (1.0 + E.tanh(xv / p.eps_x))
        p_ls = c.let("p_LS", w * pA + (1.0 - w) * pB)
        c.let("dp_comp", compensated_drop(pP, p_ls, p.p0, p.eps_p))
        kneg = p.Kv * p.Kv_neg_ratio
        # each meter-in edge is fed behind the compensator, which senses that edge's port
        dp_pa = compensated_drop(pP, pA, p.p0, p.eps_p)
        dp_pb = compensated_drop(pP, pB, p.p0, p.eps_p)
        stamp_four_edges(c,
                         edge_flow(c, dp_pa, xv, p.overlap_PA, p.Kv),
                         edge_flow(c, pB - pT, xv, p.overlap_BT, p.Kv),
                         edge_flow(c, dp_pb, -xv, p.overlap_PB, kneg),
                         edge_flow(c, pA - pT, -xv, p.overlap_AT, kneg))
