"""4/3 proportional directional valve with rate-limited command and spool dynamics."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, S, StateSpec, VariableSpec
from ..dynamics import rate_limited, second_order, first_order
from ..registry import register


def edge_opening(x, overlap, eps):
    """Opening of one metering edge for spool position ``x`` (fraction of full stroke):
    max(x − overlap, 0), smoothed over ``eps``; a negative overlap is an underlap
    (seed 000 Fig. 8: piecewise-linear opening with overlap of metering edges)."""
    return E.smooth_pos(x - overlap, eps)


@register
class Valve43(Component):
    """4/3 proportional valve, seed 004 §III.A.

    Command u (fraction, −1…1; u > 0 opens P→A and B→T) → smooth rate limiter
    (eq. 1, s_max) → spool dynamics 1/(τ²s² + 2ζτs + 1) (eq. 2 with ζ = 1; ``order`` 1
    gives 1/(1+τs), 0 none) → four metering edges, each
    q = Kv·a(x_v)·dp/(dp² + dp_lam²)^¼ (eq. 3 / Table I), a(x_v) the edge opening with
    overlap, plus a laminar leakage G_leak·dp per edge. Edges used for negative commands
    (P→B, A→T) have gain Kv·Kv_neg_ratio (valve asymmetry).
    """

    type = "valve_4_3"
    family = "hydraulic"
    description = "4/3 proportional valve: rate limit, spool lag, four edges with overlap, leakage"
    source = "seed 004 eqs. 1–3 and Table I; seed 000 §4.1 eqs. 6–9, Fig. 8"
    ports = (
        Port("P", H, "supply"), Port("T", H, "tank/return"), Port("A", H, "work port A"),
        Port("B", H, "work port B"), Port("cmd", S, "spool command, fraction of full opening (−1…1)", direction="in"),
    )
    parameters = (
        Param("Kv", "m^3/s/Pa^0.5", 4.68e-7, "flow gain per edge at full opening, q_n/sqrt(ΔP_n)",
              source="seed 004 eq. 3", positive=True, bounds=(1e-8, 1e-4)),
        Param("Kv_neg_ratio", "1", 1.0, "gain ratio of the P→B / A→T edges to Kv (asymmetric spool)",
              positive=True, bounds=(0.5, 2.0)),
        Param("dp_lam", "Pa", 5e4, "laminar transition pressure drop of the edges", positive=True),
        Param("tau", "s", 4e-3, "spool time constant τ_v", source="seed 004 eq. 2", positive=True,
              bounds=(1e-4, 5e-2)),
        Param("zeta", "1", 1.0, "spool damping ratio (1 = seed 004's double pole)", positive=True,
              bounds=(0.2, 2.0)),
        Param("order", "1", 2, "spool dynamics order: 0, 1 or 2", structural=True, min=0, max=2),
        Param("s_max", "1/s", 20.0, "maximum spool speed (2000 %/s = 20 1/s)", source="seed 004 eq. 1",
              positive=True, bounds=(1.0, 1000.0)),
        Param("tau_rl", "s", 1e-4, "tracking lag of the rate limiter below s_max", positive=True),
        Param("overlap_PA", "1", 0.0, "overlap of edge P→A (negative: underlap)", min=-0.5, max=0.5,
              bounds=(-0.1, 0.1)),
        Param("overlap_BT", "1", 0.0, "overlap of edge B→T", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
        Param("overlap_PB", "1", 0.0, "overlap of edge P→B", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
        Param("overlap_AT", "1", 0.0, "overlap of edge A→T", min=-0.5, max=0.5, bounds=(-0.1, 0.1)),
        Param("eps_x", "1", 1e-4, "smoothing of the edge openings near closure", positive=True),
        Param("G_leak", "m^3/s/Pa", 0.0, "laminar leakage conductance of each edge", min=0.0,
              bounds=(0.0, 1e-10)),
    )
    states = (
        StateSpec("xr", "1", "rate-limited spool reference", nominal=0.01),
        StateSpec("xv", "1", "spool position (fraction)", nominal=0.01),
        StateSpec("xv_dot", "1/s", "spool velocity", nominal=1.0),
    )
    variables = (
        VariableSpec("spool", "1", "spool position"),
        VariableSpec("qA", "m^3/s", "flow out of port A"),
        VariableSpec("qB", "m^3/s", "flow out of port B"),
    )

    def equations(self, c):
        p = c.p
        xr = c.state("xr")
        c.der("xr", rate_limited(c.signal("cmd"), xr, p.s_max, p.tau_rl))
        order = int(c.value("order"))
        if order == 2:
            xv, xd = c.state("xv"), c.state("xv_dot")
            c.der("xv", xd)
            c.der("xv_dot", second_order(xv, xd, xr, p.tau, p.zeta))
        elif order == 1:
            xv = c.state("xv")
            c.der("xv", first_order(xv, xr, p.tau))
        else:
            xv = xr
        xv = c.let("spool", xv)
        pP, pT, pA, pB = (c.across(n) for n in "PTAB")

        def edge(p_from, p_to, x, overlap, gain):
            dp = p_from - p_to
            leak = p.G_leak * dp if c.active("G_leak") else 0.0
            return gain * edge_opening(x, overlap, p.eps_x) * E.signed_sqrt(dp, p.dp_lam) + leak

        kneg = p.Kv * p.Kv_neg_ratio
        q_pa = edge(pP, pA, xv, p.overlap_PA, p.Kv)
        q_bt = edge(pB, pT, xv, p.overlap_BT, p.Kv)
        q_pb = edge(pP, pB, -xv, p.overlap_PB, kneg)
        q_at = edge(pA, pT, -xv, p.overlap_AT, kneg)
        qa = c.let("qA", q_pa - q_at)
        qb = c.let("qB", q_pb - q_bt)
        c.through("A", -qa)
        c.through("B", -qb)
        c.through("P", q_pa + q_pb)
        c.through("T", -(q_bt + q_at))
