"""Pressure-opened valves: check valve, relief valve, counterbalance valve (seed 000 §4.2)."""
from __future__ import annotations

from ...model import expr as E
from .. import roles as RL
from ..base import Component, H, Param, Port, VariableSpec
from ..registry import register
from .valve_pc import smooth_clamp


def pressure_opening(dp, p_cr, k_s, eps):
    """Relative opening ξ = clamp((dp − p_cr)/k_s, 0, 1) (seed 000 eq. 12), corners smoothed
    over ``eps`` (a fraction of the opening)."""
    return smooth_clamp((dp - p_cr) / k_s, 1.0, eps)


def regularised_power(s, n, eps):
    """s^n for s > 0, exactly 0 for s ≤ 0, linear (slope eps^(n−1)) for s ≪ eps so the flow
    has a finite derivative at the cracking line: max(s,0)·(max(s,0) + eps)^(n−1)."""
    sp = E.fmax(s, 0.0)
    return sp * E.power(sp + eps, n - 1.0)


_CHECK_PARAMS = (
    Param("Cv", "m^3/s/Pa^0.5", 63.2 / 60000 / 316.2278,
          "flow coefficient when fully open (e.g. \"63.2 L/min/bar^0.5\")",
          source="seed 000 eqs. 6–8, Table 5", positive=True, bounds=(1e-8, 1e-3)),
    Param("p_cr", "Pa", 1e5, "cracking pressure", source="seed 000 eq. 12, Table 5", min=0.0,
          bounds=(0.0, 5e7)),
    Param("k_s", "Pa", 1e5, "pressure rise from cracking to full opening (normalised spring stiffness)",
          source="seed 000 eq. 12, Table 5 (k_s,CV = 1 bar)", positive=True, bounds=(1e3, 1e7)),
    Param("dp_lam", "Pa", 1e4, "laminar transition pressure drop", positive=True),
    Param("eps", "1", 1e-3, "smoothing of the opening limits (fraction of full opening)", positive=True),
)


def _opened_orifice(c, dp):
    p = c.p
    xi = c.let("xi", pressure_opening(dp, p.p_cr, p.k_s, p.eps))
    return xi * p.Cv * E.signed_sqrt(dp, p.dp_lam)


@register
class CheckValve(Component):
    """Check valve from A (p1, the DCV side) to B (p2): Q = ξ·C_V·sqrt(p1 − p2) with
    ξ = clamp((p1 − p2 − p_cr,CV)/k_s,CV, 0, 1) (seed 000 eqs. 6 and 12). Closed for
    reverse pressure."""

    type = "check_valve"
    family = "hydraulic"
    description = "Spring-loaded check valve (flow A→B only), opening proportional to excess pressure"
    source = "seed 000 eqs. 6, 12, Table 5"
    ports = (Port("A", H, "inlet (p1)"), Port("B", H, "outlet (p2)"))
    parameters = _CHECK_PARAMS
    variables = (VariableSpec("q", "m^3/s", "flow A→B"), VariableSpec("xi", "1", "relative opening"))

    def equations(self, c):
        q = c.let("q", _opened_orifice(c, c.across("A") - c.across("B")))
        c.through("A", q)
        c.through("B", -q)


@register
class ReliefValve(Component):
    """Direct-acting relief valve from P to T: opens at p_cr (setting) and is fully open
    k_s above it (pressure override), Q = ξ·C_V·sqrt(p_P − p_T) (seed 000 eqs. 6, 12 form)."""

    type = "relief_valve"
    family = "hydraulic"
    description = "Pressure relief valve P→T with cracking pressure and pressure override"
    source = "seed 000 eqs. 6, 12 (pressure-equilibrium opening)"
    ports = (Port("P", H, "protected line"), Port("T", H, "tank/return"))
    roles = (RL.role(RL.RELIEF, {"inlet": "P", "outlet": "T"}, flow="Cv", cracking="p_cr", override="k_s",
                     smoothing="eps"),)
    parameters = tuple(
        Param("p_cr", "Pa", 2.5e7, "cracking (setting) pressure", min=0.0, bounds=(1e5, 5e7)) if p.name == "p_cr"
        else Param("k_s", "Pa", 1e6, "pressure override from cracking to full opening", positive=True,
                   bounds=(1e4, 1e7)) if p.name == "k_s" else p
        for p in _CHECK_PARAMS)
    variables = (VariableSpec("q", "m^3/s", "relief flow P→T"), VariableSpec("xi", "1", "relative opening"))

    def equations(self, c):
        q = c.let("q", _opened_orifice(c, c.across("P") - c.across("T")))
        c.through("P", q)
        c.through("T", -q)


@register
class CounterbalanceValve(Component):
    """Counterbalance valve, black-box model of seed 000 §4.2 (eqs. 15–22, 29), with its
    built-in check valve (eq. 12).

    Port L (load, cylinder side, p2 = p_L), port V (valve/DCV side, p1), pilot X (p_x);
    pressures are gauge (relative to p_ref, the tank pressure by default).
    μ_x = p_x/p_L (15); μ_L = p_L/p_cr (16, ``vented`` = 1, externally vented) or
    μ_L = (p_L − p_1)/p_cr (17, ``vented`` = 0, non-vented). Cracking line
    μ_L,cr = 1/(1 + C1·μ_x + C2·μ_x²) (eq. 29; C1 = ψ, C2 = 0 is eq. 18). s = μ_L − μ_L,cr (19);
    no flow for s ≤ 0, else Q = A_CBV·s^n (20) with A_CBV = A0 + A1·μ_x (21),
    n = n0 + n1·μ_x (22), from L to V. Reverse flow V → L passes the check valve
    (Cv_check, p_cr_check, k_s_check; Cv_check = 0 removes it). Table 8 (outer jib): C1 = 1.6267,
    C2 = 0.2452, A0 = 27.84, A1 = 146.2 (L/min), n0 = 0.4707, n1 = 0.0359; Table 5: p_cr = 250 bar,
    ψ = 6 geometric (1.95 effective), check valve 63.2 L/min/bar^0.5, 1 bar, 1 bar."""

    type = "counterbalance_valve"
    family = "hydraulic"
    description = "Counterbalance (load-holding) valve: black-box cracking line and flow map + check valve"
    source = "seed 000 §4.2 eqs. 12–22, 29; Tables 5 and 8"
    ports = (Port("L", H, "load port (cylinder side, p2)"), Port("V", H, "valve port (DCV side, p1)"),
             Port("X", H, "pilot port (p_x)"))
    parameters = (
        Param("vented", "1", 1, "1: externally vented (μ_L = p_L/p_cr, eq. 16); 0: non-vented "
              "(μ_L = Δp/p_cr, eq. 17)", structural=True, min=0, max=1),
        Param("p_cr", "Pa", 2.5e7, "cracking pressure p_cr,CBV", source="seed 000 Table 5", positive=True,
              bounds=(1e6, 5e7)),
        Param("C1", "1", 1.6267, "linear coefficient of the cracking line (= ψ for eq. 18)",
              source="seed 000 eq. 29, Table 8", min=0.0, bounds=(0.0, 20.0)),
        Param("C2", "1", 0.2452, "quadratic coefficient of the cracking line (0 for eq. 18)",
              source="seed 000 eq. 29, Table 8", bounds=(-5.0, 5.0)),
        Param("A0", "m^3/s", 27.84 / 60000, "flow-map gain at μ_x = 0 (\"27.84 L/min\")",
              source="seed 000 eq. 21, Table 8", min=0.0, bounds=(0.0, 1e-2)),
        Param("A1", "m^3/s", 146.2 / 60000, "flow-map gain slope in μ_x (\"146.2 L/min\")",
              source="seed 000 eq. 21, Table 8", bounds=(-1e-2, 1e-2)),
        Param("n0", "1", 0.4707, "flow-map exponent at μ_x = 0", source="seed 000 eq. 22, Table 8",
              positive=True, bounds=(0.1, 2.0)),
        Param("n1", "1", 0.0359, "flow-map exponent slope in μ_x", source="seed 000 eq. 22, Table 8",
              bounds=(-1.0, 1.0)),
        Param("p_ref", "Pa", 1e5, "reference (tank) pressure for the gauge pressures", fluid="p_tank", min=0.0),
        Param("p_L_min", "Pa", 1e5, "floor of p_L in μ_x = p_x/p_L (keeps the ratio finite)", positive=True),
        Param("eps_s", "1", 1e-3, "regularisation of s^n at the cracking line", positive=True),
        Param("Cv_check", "m^3/s/Pa^0.5", 63.2 / 60000 / 316.2278, "built-in check valve flow coefficient "
              "(0: none)", source="seed 000 Table 5", min=0.0, bounds=(0.0, 1e-3)),
        Param("p_cr_check", "Pa", 1e5, "check valve cracking pressure", source="seed 000 Table 5", min=0.0),
        Param("k_s_check", "Pa", 1e5, "check valve normalised spring stiffness", source="seed 000 Table 5",
              positive=True),
        Param("dp_lam", "Pa", 1e4, "laminar transition of the check valve", positive=True),
    )
    variables = (
        VariableSpec("mu_x", "1", "pilot ratio p_x/p_L (eq. 15)"),
        VariableSpec("mu_L", "1", "load ratio (eq. 16 or 17)"),
        VariableSpec("mu_L_cr", "1", "cracking line (eq. 29)"),
        VariableSpec("s", "1", "distance above the cracking line (eq. 19)"),
        VariableSpec("q_cbv", "m^3/s", "flow L→V through the pilot-assisted relief part (eq. 20)"),
        VariableSpec("q_check", "m^3/s", "flow V→L through the check valve (eq. 12)"),
        VariableSpec("q", "m^3/s", "net flow L→V"),
    )

    def equations(self, c):
        p = c.p
        p_l = c.across("L") - p.p_ref
        p_1 = c.across("V") - p.p_ref
        p_x = c.across("X") - p.p_ref
        mu_x = c.let("mu_x", E.fmax(p_x, 0.0) / E.fmax(p_l, p.p_L_min))
        mu_l = c.let("mu_L", (p_l if int(c.value("vented")) else p_l - p_1) / p.p_cr)
        mu_cr = c.let("mu_L_cr", 1.0 / (1.0 + p.C1 * mu_x + p.C2 * mu_x * mu_x))
        s = c.let("s", mu_l - mu_cr)
        q_map = (p.A0 + p.A1 * mu_x) * regularised_power(s, p.n0 + p.n1 * mu_x, p.eps_s)
        if int(c.value("vented")):
            # the vented map (eq. 16) does not see the outlet pressure: let the flow vanish
            # smoothly when p_1 reaches p_L, so a trapped line cannot push oil backwards
            drop = E.smooth_pos(p_l - p_1, p.dp_lam)
            q_map = q_map * drop / (drop + p.dp_lam)
        q_cbv = c.let("q_cbv", q_map)
        if c.active("Cv_check"):
            dp = p_1 - p_l
            xi = pressure_opening(dp, p.p_cr_check, p.k_s_check, 1e-3)
            q_chk = c.let("q_check", xi * p.Cv_check * E.signed_sqrt(dp, p.dp_lam))
        else:
            q_chk = c.let("q_check", 0.0)
        q = c.let("q", q_cbv - q_chk)
        c.through("L", q)
        c.through("V", -q)
        c.through("X", 0.0)
