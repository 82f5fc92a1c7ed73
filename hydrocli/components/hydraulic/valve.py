"""4/3 proportional directional valve with rate-limited command and spool dynamics.

The spool chain (rate limiter → 0/1/2-order dynamics) and the four-edge flow stamping are
shared with the pressure-compensated valve (:mod:`.valve_pc`).
"""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, S, StateSpec, VariableSpec
from ..dynamics import dahl_rate, play_rate, rate_limited, second_order, first_order
from ..registry import register
from .. import roles as RL
from ..roles import role


def edge_opening(x, overlap, eps):
    """Relative opening ξ of one metering edge for spool position ``x`` (fraction of full
    stroke): max(x − o, 0)/(1 − o), smoothed over ``eps``, so that ξ(1) = 1 (C_V is the
    fully-open coefficient, seed 000 eq. 8) whatever the overlap o. A negative overlap is an
    underlap: the edge is open by −o/(1 − o) at centre (seed 000 Fig. 8: overlap of the
    metering edges, underlap of the return edges)."""
    return E.smooth_pos(x - overlap, eps) / (1.0 - overlap)


SPOOL_PARAMS = (
    Param("tau", "s", 4e-3, "spool time constant τ_v = 1/ω_V", source="seed 004 eq. 2; seed 000 eq. 9",
          positive=True, bounds=(1e-4, 5e-2)),
    Param("zeta", "1", 1.0, "spool damping ratio ζ_V (1 = seed 004's double pole; 0.8 in seed 000 Table 4)",
          positive=True, bounds=(0.2, 2.0)),
    Param("order", "1", 2, "spool dynamics order: 0, 1 or 2", structural=True, min=0, max=2),
    Param("s_max", "1/s", 20.0, "maximum spool speed (2000 %/s = 20 1/s)", source="seed 004 eq. 1",
          positive=True, bounds=(1.0, 1000.0)),
    Param("s_min", "1/s", 0.0, "maximum falling spool speed (magnitude; seed 004 eq. 1 s_v,min = −s_min); "
          "0 = s_max (symmetric)", source="seed 004 eq. 1", min=0.0, bounds=(1.0, 1000.0)),
    Param("tau_rl", "s", 1e-4, "tracking lag of the rate limiter below s_max", positive=True),
    Param("hyst_h", "1", 0.0, "half-width of a Dahl hysteresis loop between the spool and its metering lands "
          "(0: none)", source="Dahl 1968 eq. 5", min=0.0, bounds=(0.0, 0.1)),
    Param("hyst_sigma", "1", 2.0, "shape of that loop: dz/dx_v = 2σ just after a reversal (σ ≫ 1 switches abruptly)",
          positive=True, bounds=(0.05, 100.0)),
    Param("hyst_eps", "1/s", 5e-3, "spool speed below which the loop's direction is smoothed", positive=True),
    Param("play_b", "1", 0.0, "half-width of a play (backlash) between the spool and its metering lands (0: none)",
          min=0.0, bounds=(0.0, 0.1)),
    Param("play_eps", "1", 1e-4, "smoothing of the play's band edges", positive=True, bounds=(1e-6, 0.05)),
    Param("play_tau", "s", 2e-4, "tracking lag of the lands outside the play's band", positive=True),
)
EDGE_PARAMS = (
    Param("overlap_PA", "1", 0.0, "overlap of edge P→A (negative: underlap)", min=-0.5, max=0.5,
          bounds=(-0.1, 0.1), source="seed 000 Fig. 8, Table 4"),
    Param("overlap_BT", "1", 0.0, "overlap of edge B→T", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
    Param("overlap_PB", "1", 0.0, "overlap of edge P→B", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
    Param("overlap_AT", "1", 0.0, "overlap of edge A→T", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
    Param("eps_x", "1", 1e-4, "smoothing of the edge openings near closure", positive=True),
    Param("G_leak", "m^3/s/Pa", 0.0, "laminar leakage conductance of each edge", min=0.0,
          bounds=(0.0, 1e-10)),
)
FLOW_PARAMS = (
    Param("Kv", "m^3/s/Pa^0.5", 4.68e-7, "flow coefficient per edge at full opening, C_V = Q_nom/sqrt(Δp_nom) "
          "(\"37.8 L/min/bar^0.5\" accepted)", source="seed 004 eq. 3; seed 000 eqs. 6–8",
          positive=True, bounds=(1e-8, 1e-4)),
    Param("Kv_neg_ratio", "1", 1.0, "gain ratio of the P→B / A→T edges to Kv (asymmetric spool)",
          positive=True, bounds=(0.5, 2.0)),
    Param("dp_lam", "Pa", 5e4, "laminar transition pressure drop of the edges", positive=True),
)
SPOOL_STATES = (
    StateSpec("xr", "1", "rate-limited spool reference", nominal=0.01),
    StateSpec("xv", "1", "spool position (fraction)", nominal=0.01),
    StateSpec("xv_dot", "1/s", "spool velocity", nominal=1.0),
    StateSpec("zh", "1", "offset of the metering lands from the spool (hysteresis loop; only with hyst_h)",
              nominal=1e-3),
    StateSpec("xe", "1", "position of the metering lands behind a play (only with play_b)", nominal=1e-2),
)
VALVE_PORTS = (
    Port("P", H, "supply"), Port("T", H, "tank/return"), Port("A", H, "work port A"),
    Port("B", H, "work port B"), Port("cmd", S, "spool command, fraction of full opening (−1…1)", direction="in"),
)
VALVE_VARS = (
    VariableSpec("spool", "1", "metering position of the spool (its position less the hysteresis offset)"),
    VariableSpec("qA", "m^3/s", "flow out of port A"),
    VariableSpec("qB", "m^3/s", "flow out of port B"),
)


def spool_position(c):
    """Command → smooth rate limiter (seed 004 eq. 1) → spool dynamics of order 0/1/2
    (seed 004 eq. 2; seed 000 eq. 9 with ω_V = 1/τ, ζ_V = zeta) → metering position
    of the lands: with ``play_b`` > 0 they follow the spool through a play of half-width b
    (the play operator, Tao & Kokotović ch. 2); with ``hyst_h`` > 0 they trail it by a Dahl
    loop driven by the spool's own speed, z' = σ·ẋ_v·(1 − (z/h)·tanh(ẋ_v/ε)) (Dahl 1968 eq. 5).
    Either is the spool's hysteresis as the metering sees it, after the spool's dynamics."""
    p = c.p
    xr = c.state("xr")
    dxr = rate_limited(c.signal("cmd"), xr, p.s_max, p.tau_rl, p.s_min if c.active("s_min") else None)
    c.der("xr", dxr)
    order = int(c.value("order"))
    if order == 2:
        xv, xd = c.state("xv"), c.state("xv_dot")
        c.der("xv", xd)
        c.der("xv_dot", second_order(xv, xd, xr, p.tau, p.zeta))
        rate = xd
    elif order == 1:
        xv = c.state("xv")
        rate = first_order(xv, xr, p.tau)
        c.der("xv", rate)
    else:
        xv, rate = xr, dxr
    if c.active("play_b"):
        xe = c.state("xe")
        c.der("xe", play_rate(xv, xe, p.play_b, p.play_eps, p.play_tau))
        xv = xe
    if c.active("hyst_h"):
        z = c.state("zh")
        c.der("zh", dahl_rate(z, rate, p.hyst_h, p.hyst_sigma, p.hyst_eps))
        xv = xv - z
    return c.let("spool", xv)


def edge_flow(c, dp, x, overlap, gain):
    """q = gain·ξ(x)·dp/(dp² + dp_lam²)^¼ + G_leak·dp (seed 000 eq. 6, seed 004 eq. 3)."""
    p = c.p
    leak = p.G_leak * dp if c.active("G_leak") else 0.0
    return gain * edge_opening(x, overlap, p.eps_x) * E.signed_sqrt(dp, p.dp_lam) + leak


def stamp_four_edges(c, q_pa, q_bt, q_pb, q_at):
    """Port flows of a four-edge valve; exposes qA, qB (flows out of A and B)."""
    qa = c.let("qA", q_pa - q_at)
    qb = c.let("qB", q_pb - q_bt)
    c.through("A", -qa)
    c.through("B", -qb)
    c.through("P", q_pa + q_pb)
    c.through("T", -(q_bt + q_at))


VALVE_ROLE = role(RL.METERING_VALVE, {"supply": "P", "tank": "T", "work_a": "A", "work_b": "B", "command": "cmd"},
                   flow_gain="Kv", direction_ratio="Kv_neg_ratio",
                   overlaps=("overlap_PA", "overlap_BT", "overlap_PB", "overlap_AT"), edge_leak="G_leak",
                   spool_dynamics=("tau", "s_max"), spool_lag="tau", spool_hysteresis=("hyst_h", "hyst_sigma"),
                   spool_play=("play_b", "play_eps"))


@register
class Valve43(Component):
    """4/3 proportional valve, seed 004 §III.A and seed 000 §4.1.

    Command u (fraction, −1…1; u > 0 opens P→A and B→T) → smooth rate limiter
    (eq. 1, s_max) → spool dynamics 1/(τ²s² + 2ζτs + 1) (seed 004 eq. 2; seed 000 eq. 9 with
    ω_V = 1/τ; ``order`` 1 gives 1/(1+τs), 0 none) → four metering edges, each
    q = Kv·ξ(x_v)·dp/(dp² + dp_lam²)^¼ (seed 000 eq. 6, seed 004 eq. 3), ξ the piecewise-linear
    opening with overlap/underlap (seed 000 Fig. 8), plus a laminar leakage G_leak·dp per edge.
    Edges used for negative commands (P→B, A→T) have gain Kv·Kv_neg_ratio (valve asymmetry).
    Optionally the lands follow the spool through a play (``play_b``) or a Dahl loop
    (``hyst_h``): the spool's hysteresis as the metering sees it (``spool_position``).
    """

    type = "valve_4_3"
    roles = (VALVE_ROLE,)
    family = "hydraulic"
    description = "4/3 proportional valve: rate limit, spool lag, four edges with overlap, leakage"
    source = "seed 004 eqs. 1–3 and Table I; seed 000 §4.1 eqs. 6–9, Fig. 8"
    ports = VALVE_PORTS
    parameters = FLOW_PARAMS + SPOOL_PARAMS + EDGE_PARAMS
    states = SPOOL_STATES
    variables = VALVE_VARS

    def equations(self, c):
        p = c.p
        xv = spool_position(c)
        pP, pT, pA, pB = (c.across(n) for n in "PTAB")
        g_pa, g_bt, g_pb, g_at = self.edge_gains(c)
        stamp_four_edges(c,
                         edge_flow(c, pP - pA, xv, p.overlap_PA, g_pa),
                         edge_flow(c, pB - pT, xv, p.overlap_BT, g_bt),
                         edge_flow(c, pP - pB, -xv, p.overlap_PB, g_pb),
                         edge_flow(c, pA - pT, -xv, p.overlap_AT, g_at))

    def edge_gains(self, c):
        """Flow gains of the edges P→A, B→T (x_v > 0) and P→B, A→T (x_v < 0)."""
        kneg = c.p.Kv * c.p.Kv_neg_ratio
        return c.p.Kv, c.p.Kv, kneg, kneg
