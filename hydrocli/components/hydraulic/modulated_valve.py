"""Valve as a nonlinear resistance modulated by the command voltage (seed 002 eq. 2)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, S, VariableSpec
from ..registry import register


def polynomial(coeffs, x):
    """c0 + c1·x + c2·x² + … (Horner)."""
    out = E.as_expr(0.0)
    for c in reversed(coeffs):
        out = out * x + c
    return out


def piecewise_linear(xs, ys, x):
    """Linear interpolation in a table (numbers xs ascending), held at the ends."""
    out = E.as_expr(ys[0])
    for k in range(1, len(xs)):
        slope = (ys[k] - ys[k - 1]) / (xs[k] - xs[k - 1])
        out = out + slope * (E.clamp(x, xs[k - 1], xs[k]) - xs[k - 1])
    return out


@register
class ModulatedResistance(Component):
    """ΔP = C_R·Q|Q| (seed 002 eq. 2a), C_R = ρ/(2C_d²A²) (eq. 2b) modulated by the command V:
    Q = g(V)·sign(Δp)·sqrt(|Δp|) with g = C_R^(−1/2) given as a polynomial in (V_eff − V_db)
    (``coeffs``, g = 0 inside the deadband 0…V_db, 1.2 V in seed 002 Fig. 5) or, when
    ``table_V`` is given, as a table g(V) (``table_g``, linear interpolation, same deadband rule).
    ``polarity`` +1 opens for V > 0, −1 for V < 0 (V_eff = |V| then), 0 for both; four such
    resistances make the 4-way valve of seed 002 Fig. 3 (C_R, C_R')."""

    type = "modulated_resistance"
    family = "hydraulic"
    description = "Command-modulated turbulent resistance ΔP = C_R(V)·Q|Q| with deadband"
    source = "seed 002 eqs. 2a–2b, Fig. 5"
    ports = (Port("A", H, "inlet"), Port("B", H, "outlet"), Port("cmd", S, "command voltage [V]", direction="in"))
    parameters = (
        Param("coeffs", "m^3/s/Pa^0.5", [0.0, 1e-7], "polynomial of C_R^(−1/2) in (V − V_db): c0, c1 [per V], …",
              source="seed 002 Fig. 5", vector=True),
        Param("table_V", "V", [], "voltages of a C_R^(−1/2) table (empty: use the polynomial)", vector=True,
              structural=True),
        Param("table_g", "m^3/s/Pa^0.5", [], "C_R^(−1/2) at table_V", vector=True),
        Param("V_db", "V", 1.2, "deadband", source="seed 002 §3a", min=0.0, bounds=(0.0, 3.0)),
        Param("polarity", "1", 1, "+1: opens for V > 0; −1: for V < 0; 0: for |V|", structural=True, min=-1, max=1),
        Param("dp_lam", "Pa", 5e4, "laminar transition of sign(Δp)·sqrt(|Δp|)", positive=True),
        Param("eps_V", "V", 1e-3, "smoothing of the deadband corner", positive=True),
    )
    variables = (VariableSpec("g", "m^3/s/Pa^0.5", "C_R^(−1/2) at the present command"),
                 VariableSpec("q", "m^3/s", "flow A→B"))

    def check(self, values):
        tv, tg = values.get("table_V") or [], values.get("table_g") or []
        if len(tv) != len(tg):
            return [f"table_V has {len(tv)} entries but table_g has {len(tg)}"]
        if any(b <= a for a, b in zip(tv, tv[1:])):
            return ["table_V must be strictly increasing"]
        return []

    def equations(self, c):
        p = c.p
        v = c.signal("cmd")
        pol = int(c.value("polarity"))
        v_eff = E.fabs(v) if pol == 0 else pol * v
        table = [float(x) for x in c.value("table_V") or []]
        if table:
            g = piecewise_linear(table, p.table_g, E.fmax(v_eff, table[0]))
            g = E.where(v_eff > p.V_db, g, 0.0)
        else:
            g = E.where(v_eff > p.V_db, polynomial(p.coeffs, E.smooth_pos(v_eff - p.V_db, p.eps_V)), 0.0)
        g = c.let("g", E.fmax(g, 0.0))
        q = c.let("q", g * E.signed_sqrt(c.across("A") - c.across("B"), p.dp_lam))
        c.through("A", q)
        c.through("B", -q)
