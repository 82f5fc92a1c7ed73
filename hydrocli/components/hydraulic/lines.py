"""Hydraulic lines: lumped hose (T/π/L lumps, N segments) and an inertance line.

Per lump (linear-graph elements of seed 002 §2b): series inertance I = ρ·l/A and resistance
(laminar 128·μ·l/(π d⁴), seed 001 eqs. 7/11, and/or turbulent C_R·Q|Q|, seed 002 eq. 2a),
shunt capacitance C = A·l/β (or the measured I, C of seed 002 §3c). Branch law:
I·dQ/dt = Δp − R·Q − C_R·Q|Q|.
"""
from __future__ import annotations

import math
import re

from ...model import expr as E
from ..base import Component, H, Param, Port, StateSpec, VariableSpec
from ..registry import register

PI, L_LUMP, T_LUMP = 0, 1, 2


def laminar_resistance(rho, nu, length, d):
    """Hagen–Poiseuille R = 128·μ·l/(π d⁴), μ = ρ·ν (seed 001 eqs. 7, 11)."""
    return 128.0 * rho * nu * length / (math.pi * d ** 4)


def single_lump_frequency(beta, rho, length):
    """Highest frequency one lump represents, f = C0/(2π l), C0 = sqrt(β/ρ) (seed 002 eq. 3)."""
    return math.sqrt(beta / rho) / (2.0 * math.pi * length)


def branch_rate(q, dp, inertance, r_lam, c_r):
    """dQ/dt = (Δp − R·Q − C_R·Q|Q|)/I."""
    return (dp - r_lam * q - c_r * q * E.fabs(q)) / inertance


def ladder(arrangement: int, n: int, split=0.5):
    """(capacitance fraction per node [A, internal…, B], inertance fraction per branch);
    ``split``: the π's share of the end capacitance 1/N that sits at A (a number or an
    expression)."""
    if arrangement == PI:
        return [split / n] + [1.0 / n] * (n - 1) + [(1.0 - split) / n], [1.0 / n] * n
    if arrangement == L_LUMP:
        return [0.0] + [1.0 / n] * n, [1.0 / n] * n
    return [0.0] + [1.0 / n] * n + [0.0], [0.5 / n] + [1.0 / n] * (n - 1) + [0.5 / n]


_GEOMETRY = (
    Param("l", "m", 4.0, "hose length", source="seed 002 §3b (4 m SAE 100R12)", positive=True, bounds=(0.01, 100.0)),
    Param("d", "m", 0.01905, "internal diameter", source="seed 002 §3b (3/4 in)", positive=True, bounds=(1e-3, 0.2)),
    Param("rho", "kg/m^3", 870.0, "oil density", fluid="rho", positive=True, bounds=(700.0, 1100.0)),
    Param("nu", "m^2/s", 4.6e-5, "kinematic viscosity", fluid="nu", positive=True, bounds=(1e-6, 1e-3)),
    Param("laminar", "1", 1, "1: include the laminar loss 128μl/(πd⁴); 0: not", structural=True, min=0, max=1),
    Param("C_R", "Pa*s^2/m^6", 0.0, "turbulent resistance coefficient, Δp = C_R·Q|Q| (seed 002: 3.125e11 "
          "for the 4 m hose)", source="seed 002 eq. 2a, §3b", min=0.0, bounds=(0.0, 1e14)),
    Param("I", "kg/m^4", 0.0, "total inertance (0: ρl/A)", source="seed 002 §3c (3.06e7)", min=0.0,
          bounds=(1e5, 1e10)),
    Param("C_R_ref", "Pa*s^2/m^6", 0.0, "measured C_R of a reference hose, scaled to this hose by seed 002 eq. 7, "
          "C_R ∝ μ^0.25 ρ^0.75 L/D^4.75 (same oil): C_R_ref·(l/l_ref)·(d_ref/d)^4.75; 0 = use C_R",
          source="seed 002 eq. 7, §3b", min=0.0, bounds=(0.0, 1e14)),
    Param("l_ref", "m", 4.0, "length of the reference hose of C_R_ref", source="seed 002 §3b", positive=True),
    Param("d_ref", "m", 0.01905, "diameter of the reference hose of C_R_ref", source="seed 002 §3b", positive=True),
)


def turbulent_coefficient(c):
    """C_R of the hose: the parameter, or seed 002 eq. 7's scaling of a measured reference hose
    C_R(L, D) = a·μ^0.25·ρ^0.75·L/D^4.75 → C_R_ref·(l/l_ref)·(d_ref/d)^4.75 for the same oil."""
    p = c.p
    if not c.active("C_R_ref"):
        return p.C_R
    return p.C_R_ref * (p.l / p.l_ref) * (p.d_ref / p.d) ** 4.75


@register
class Hose(Component):
    """Lumped hose between A and B in ``lumps`` segments (seed 002 §2b, eq. 3).

    ``arrangement`` 0 = π (C/2N at each end, so both ends are well posed on their own: use it
    when a valve or orifice connects directly; ``split`` s moves the end capacitance C/N to
    s·C/N at A and (1 − s)·C/N at B: where a single lump's volume sits is not known when a
    manifold or a pipe run holds most of the line's oil at one end), 1 = L (I, R then C: all capacitance towards B,
    the form of seed 002 eq. 6; A must be fed by a source or a node with its own volume),
    2 = T (I/2–C–I/2 per lump, as in seed 002's text; both end nodes need a volume or source).
    States: the branch flows q0…q(N−1) (q(N) for T) and internal pressures p1…. A build
    warning is issued when a lump is longer than seed 002 eq. 3 allows for ``f_max``:
    f_max ≥ C0/(2π·l/N), C0 = sqrt(β/ρ).
    """

    type = "hose"
    family = "hydraulic"
    description = "Hose/pipe: N lumps of series inertance and resistance with shunt capacitance (π, L or T)"
    source = "seed 002 §2b eqs. 2a, 3, §3b–c; seed 001 eqs. 7, 11"
    ports = (Port("A", H, "end A"), Port("B", H, "end B"))
    parameters = _GEOMETRY + (
        Param("beta", "Pa", 1.5e9, "effective bulk modulus of oil and hose wall", fluid="beta", positive=True,
              bounds=(1e8, 2.5e9)),
        Param("C", "m^5/N", 0.0, "total capacitance (0: A·l/β)", source="seed 002 §3c (1.59e-12)", min=0.0,
              bounds=(1e-15, 1e-8)),
        Param("lumps", "1", 1, "number of segments N", structural=True, min=1, max=50),
        Param("arrangement", "1", 0, "0 = π, 1 = L (I then C), 2 = T (I/2, C, I/2)", structural=True, min=0, max=2),
        Param("split", "1", 0.5, "π only: share of the end capacitance C/N that sits at end A (0.5: the symmetric π; "
              "towards 1 the line's oil volume sits at A, e.g. a valve manifold or a pipe run there)",
              min=0.01, max=0.99, bounds=(0.02, 0.98)),
        Param("f_max", "Hz", 50.0, "highest frequency of interest, for the lumping check (seed 002 eq. 3)",
              structural=True, positive=True),
    )
    states = (StateSpec("q0", "m^3/s", "flow of branch k (q0, q1, …) from A towards B", nominal=1e-4),
              StateSpec("p1", "Pa", "pressure of internal node k (p1, p2, …)", nominal=1e5))
    variables = (VariableSpec("qA", "m^3/s", "flow entering at A"), VariableSpec("qB", "m^3/s", "flow leaving at B"),
                 VariableSpec("I_total", "kg/m^4", "total inertance"), VariableSpec("C_total", "m^5/N", "total capacitance"))

    @classmethod
    def state_spec(cls, name):
        m = re.fullmatch(r"([qp])(\d+)", name)
        if not m:
            return None
        return StateSpec(name, *(("m^3/s", f"flow of branch {m[2]}", 0.0, 1e-4) if m[1] == "q"
                                 else ("Pa", f"pressure of internal node {m[2]}", 0.0, 1e5)))

    def equations(self, c):
        p = c.p
        n, arr = int(c.value("lumps")), int(c.value("arrangement"))
        area = math.pi / 4.0 * p.d * p.d
        i_tot = c.let("I_total", p.I if c.active("I") else p.rho * p.l / area)
        c_tot = c.let("C_total", p.C if c.active("C") else area * p.l / p.beta)
        r_lam = laminar_resistance(p.rho, p.nu, p.l, p.d) if int(c.value("laminar")) else 0.0
        c_r = turbulent_coefficient(c)
        self._lumping_check(c, n)
        # the split acts on a π only (read on an L or T it would become a model parameter there)
        caps, inert = ladder(arr, n, p.split if arr == PI else 0.5)
        if arr != PI and float(c.value("split")) != 0.5:
            c.warn("split places a π line's end capacitance; it has no effect on an L or T arrangement")
        nodes = [c.across("A")] + [c.state(f"p{k}") for k in range(1, len(caps) - 1)] + [c.across("B")]
        flows = [c.state(f"q{k}") for k in range(len(inert))]
        for k, (q, frac) in enumerate(zip(flows, inert)):
            c.der(f"q{k}", branch_rate(q, nodes[k] - nodes[k + 1], frac * i_tot, frac * r_lam, frac * c_r))
        for k in range(1, len(caps) - 1):
            c.der(f"p{k}", (flows[k - 1] - flows[k]) / (caps[k] * c_tot))
        if arr == PI:              # end capacitance: π at both ends, L at B only, T at neither
            c.capacitance("A", caps[0] * c_tot)
        if arr != T_LUMP:
            c.capacitance("B", caps[-1] * c_tot)
        c.through("A", c.let("qA", flows[0]))
        c.through("B", -c.let("qB", flows[-1]))

    @staticmethod
    def _lumping_check(c, n):
        beta, rho, length = (float(c.value(k)) for k in ("beta", "rho", "l"))
        f_lump = single_lump_frequency(beta, rho, length / n)
        f_max = float(c.value("f_max"))
        if f_max >= f_lump:
            need = math.ceil(n * f_max / f_lump + 1e-9)
            c.warn(f"a lump of {length / n:.3g} m represents frequencies up to C0/(2πl) = {f_lump:.3g} Hz only "
                   f"(seed 002 eq. 3), below f_max = {f_max:g} Hz: use lumps ≥ {need}")


@register
class FluidLine(Component):
    """Inertance line without capacitance (seed 001 eqs. 7 and 11):
    dQ/dt = (A/(ρl))·(p_A − 128μl/(πd⁴)·Q − C_R·Q|Q| − p_B). Both end nodes need a volume
    (e.g. the accumulator of eq. 8) or a source."""

    type = "fluid_line"
    family = "hydraulic"
    description = "Supply/return line: fluid inertance with laminar (and optional turbulent) loss"
    source = "seed 001 eqs. 7, 11"
    ports = (Port("A", H, "upstream end"), Port("B", H, "downstream end"))
    parameters = _GEOMETRY
    states = (StateSpec("q", "m^3/s", "line flow A→B", nominal=1e-4),)
    variables = (VariableSpec("R_lam", "Pa*s/m^3", "laminar resistance"),)

    def equations(self, c):
        p = c.p
        area = math.pi / 4.0 * p.d * p.d
        inertance = p.I if c.active("I") else p.rho * p.l / area
        r_lam = c.let("R_lam", laminar_resistance(p.rho, p.nu, p.l, p.d) if int(c.value("laminar")) else 0.0)
        q = c.state("q")
        c.der("q", branch_rate(q, c.across("A") - c.across("B"), inertance, r_lam, turbulent_coefficient(c)))
        c.through("A", q)
        c.through("B", -q)
