"""End-position cushioning of a cylinder chamber's outlet (as on Festo DSNU/DNC and most
industrial hydraulic cylinders): over the last millimetres of stroke a cushioning spear
enters the chamber's main outlet bore and closes it, so the oil leaving the chamber must pass
an adjustable needle orifice; a check valve lets the oil back in freely when the piston
reverses. References: Festo, *Cushioning* (DSNU/DNC data sheets: adjustable cushioning PPV);
H. Murrenhoff, *Grundlagen der Fluidtechnik I*, §8 (Endlagendämpfung)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, R, T, VariableSpec
from ..registry import register
from ..two_port import across_drop, branch
from .. import roles as RL
from ..roles import role


def cushion_opening(d, length, w, eps):
    """Open fraction of the main outlet at distance ``d`` from the end stop: the spear enters
    the outlet bore at d = L + w and closes it linearly until d = L, g = clamp((d − L)/w, 0, 1),
    smoothed over eps·w at both corners; over the last L only the needle is left."""
    r = (d - length) / w
    return E.smooth_pos(r, eps) - E.smooth_pos(r - 1.0, eps)


def cushion_ports(motion, chamber: str, rod: str, body: str) -> tuple[Port, ...]:
    """The cushion's ports: the chamber and its line (hydraulic), the moving part and its
    reference on ``motion``'s domain (translational or rotational), read only."""
    return (Port("chamber", H, f"{chamber} being cushioned"), Port("line", H, "line/valve side of the outlet"),
            Port("rod", motion, rod), Port("body", motion, body))


def cushion_params(unit: str, where: str, x: str, length: float, length_max: float, entry: float,
                   entry_bounds: tuple[float, float]) -> tuple[Param, ...]:
    """The cushion's parameters, its positions in its motion's unit (m for a rod, rad for a
    vane shaft)."""
    return (
        Param("Kv", "m^3/s/Pa^0.5", 1e-7, "main outlet (and line) flow coefficient, away from the end",
              min=0.0, bounds=(1e-10, 1e-4)),
        Param("Kv_needle", "m^3/s/Pa^0.5", 1e-9, "cushioning needle orifice coefficient (adjustable screw)",
              min=0.0, bounds=(1e-12, 1e-6)),
        Param("Kv_spear", "m^3/s/Pa^0.5", 0.0, "tapered spear: gap coefficient at the cushion's start, "
              "falling linearly to 0 at the stop (0 = cylindrical spear, needle only)", min=0.0, bounds=(0.0, 1e-6)),
        Param("Kv_check", "m^3/s/Pa^0.5", 0.0, "check valve bypass for flow into the chamber (0 = none)",
              min=0.0, bounds=(0.0, 1e-5)),
        Param("p_crack", "Pa", 5e4, "check valve cracking pressure (opens over ±10 % of it)", positive=True),
        Param("x_end", unit, 0.0, f"{where} of the cushioned end stop"),
        Param("direction", "1", 1.0, f"+1: cushion at the upper end ({x} near x_end from below); "
              f"−1: at the lower end ({x} near x_end from above)", structural=True, min=-1, max=1),
        Param("L", unit, length, "cushion length (needle-only travel before the stop)",
              min=0.0, bounds=(0.0, length_max)),
        Param("w", unit, entry, "spear entry length over which the main outlet closes", positive=True,
              bounds=entry_bounds),
        Param("eps", "1", 0.02, "corner smoothing of the opening, as a fraction of w", positive=True),
        Param("dp_lam", "Pa", 5e4, "laminar/turbulent transition pressure drop", positive=True),
    )


@register
class EndCushion(Component):
    """Cushioned outlet between a cylinder chamber and its line:
    q = K·sign(Δp)·sqrt(|Δp|) (turbulent, laminar below dp_lam), Δp = p_chamber − p_line,
    K = Kv·g(d) + Kv_spear·clamp(d/L, 0, 1) + Kv_needle + Kv_check·s_in with
    g = clamp((d − L)/w, 0, 1) the main outlet's
    open fraction at distance d = direction·(x_end − x) from the cushioned end and s_in ∈ [0, 1]
    the check valve's smooth opening for flow into the chamber (line above chamber by p_crack). Far from the end it is the
    line's orifice Kv; in the last millimetres the chamber empties through the needle (and a
    tapered spear's narrowing gap) only, so a piston pushed at speed v holds the cushion
    pressure Δp = (A v / K)²; with a taper the speed decays ~exponentially towards the stop."""

    type = "end_cushion"
    roles = (role(RL.END_CUSHION, {"chamber": "chamber", "line": "line", "motion": "rod", "reference": "body"},
                  open_flow="Kv", needle="Kv_needle", check="Kv_check", end="x_end", direction="direction",
                  length="L", entry="w"),)
    family = "hydraulic"
    description = "Cylinder end-position cushioning: outlet throttled to a needle orifice over the last L of stroke"
    source = "Festo DSNU/DNC cushioning (spear + needle + check valve); turbulent orifice as seed 004 eq. 3"
    ports = cushion_ports(T, "cylinder chamber", "piston rod (position read only, no force)",
                          "cylinder body (position read only, usually ground)")
    parameters = cushion_params("m", "piston position", "x", 0.01, 0.1, 1e-3, (1e-5, 0.05))
    variables = (
        VariableSpec("g", "1", "open fraction of the main outlet"),
        VariableSpec("K", "m^3/s/Pa^0.5", "effective flow coefficient"),
        VariableSpec("q", "m^3/s", "flow out of the chamber into the line"),
    )

    def equations(self, c):
        p = c.p
        x = c.position("rod") - c.position("body")
        d = (p.x_end - x) if c.value("direction") > 0 else (x - p.x_end)
        g = c.let("g", cushion_opening(d, p.L, p.w, p.eps))
        dp = across_drop(c, "chamber", "line")
        k = p.Kv * g + p.Kv_needle
        if c.active("Kv_spear"):        # tapered spear: the gap narrows towards the stop
            k = k + p.Kv_spear * cushion_opening(d, 0.0, p.L, p.eps)
        if c.active("Kv_check"):       # opens once the line exceeds the chamber by p_crack
            s_in = 0.5 * (1.0 + E.tanh((-dp - p.p_crack) / (0.1 * p.p_crack)))
            k = k + p.Kv_check * s_in
        k = c.let("K", k)
        branch(c, "q", k * E.signed_sqrt(dp, p.dp_lam), "chamber", "line")

    def check(self, values):
        return [] if values["direction"] in (1.0, -1.0) else ["direction must be +1 (extended end) or -1 (retracted end)"]


@register
class EndCushionRotary(EndCushion):
    """:class:`EndCushion` at an end of a vane's (or rotary piston's) swing: the vane closes
    the chamber's main outlet groove over its last part of the swing and the oil leaves through
    the needle (cushioned rotary actuators, e.g. Parker HTR, Micromatic); angles in rad."""

    type = "end_cushion_rotary"
    description = "Rotary actuator end-position cushioning: outlet throttled to a needle over the last L of swing"
    source = ("rotary actuator cushioning (the vane closes the outlet groove; needle + check valve); "
              "turbulent orifice as seed 004 eq. 3")
    ports = cushion_ports(R, "actuator chamber", "vane shaft (angle read only, no torque)",
                          "housing (angle read only, usually ground)")
    parameters = cushion_params("rad", "vane angle", "θ", 0.1, 1.0, 0.01, (1e-4, 0.5))
