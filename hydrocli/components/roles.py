"""Roles: what part a component type can play in a machine, as data.

Tools that reason about a machine as a whole (the diagnosis: "leakage across every
actuator", "friction on every moving load", "a line between each valve work port and the
actuator chamber it feeds") find components by the ROLE they offer, never by type name.
A component type lists its roles in its spec (``roles = (Role(...), ...)``); each role maps
the role's SLOTS to the type's own port and parameter names, so a cylinder, a vane actuator
and a hydraulic motor all offer ``ACTUATOR`` with ``chamber_a``/``chamber_b``/``motion``
ports, and the diagnosis needs no list of cylinder types.

Slots of each role (a type fills the ones it has; a missing slot means "not offered"):

=================  ==========================================================================
role               slots
=================  ==========================================================================
actuator           ports chamber_a, chamber_b, motion, reference; params size (area or
                   displacement: force or torque per Pa), displacements (every area or
                   displacement, within manufacturing tolerance), dead_volumes (each chamber's
                   volume at the reference position: dead volume and lines), swept (the area or
                   displacement by which each chamber's volume grows with travel, chamber_a's
                   first; none for a motor, whose chambers keep their volume), bulk_modulus (of the oil in
                   the chambers), internal_leakage / external_leakage
                   (laminar conductances, 0 = none), air (free-air fraction), stop_min,
                   stop_max, stop_stiffness, stop_damping
metering_valve     ports supply, tank, work_a, work_b, command; params flow_gain, direction_ratio
                   (1 = symmetric), overlaps (four edges), edge_leak, edge_gains (four edges),
                   spool_dynamics (time constant, rate limit: nuisance parameters),
                   spool_lag (the spool's time constant alone)
load               ports node; params inertia (mass or moment of inertia)
spring             ports a, b; params stiffness
damper             ports a, b; params damping
clearance          ports a, b; params stiffness and damping (in contact), gap (the total free play)
friction           ports a, b, pressure_a, pressure_b; params viscous, coulomb, stribeck (one or
                   two names: both directions of motion), stribeck_speed (the speed over which
                   the breakaway excess decays, one or two names), pressure (seal friction per
                   Pa·size), pressure_size, band (the speed over which Coulomb friction reverses)
pressure_source    ports out, reference; params pressure
tank               ports node
volume             ports node; params volume, air, bulk_modulus
gas_volume         ports node; params gas_volume (at the precharge), precharge (absolute), exponent
                   (polytropic), oil_volume (of its port): a gas spring on a node
restriction        ports a, b; params conductance (turbulent: q = K·√Δp)
laminar_restriction ports a, b; params resistance (Δp = R·q)
end_cushion        ports chamber, line, motion, reference; params open_flow (the outlet's flow coefficient
                   away from the end), needle (the cushioning orifice's), check (the inflow bypass),
                   end (the cushioned end's position), direction (+1 extended end, −1 retracted),
                   length (the needle-only travel), entry (over which the outlet closes)
relief             ports inlet, outlet; params flow (the flow coefficient fully open, q = ξ·C_V·√Δp),
                   cracking (the pressure where it starts to open), override (the pressure rise from
                   cracking to full opening), smoothing (of the opening's corners, a share of it)
dissolving_air     ports node (and motion, reference in a chamber whose volume follows them); params
                   free_air (its volume at 1 bar when the record starts), absorption and release
                   (time constants), oil_volume, solubility, saturation (Henry's law), swept (the
                   chamber's growth per unit of travel)
band_restriction   ports a, b, motion, reference; params conductance (laminar, inside the band),
                   band_start, band_end (positions), edge (width of the band's edges)
film_restriction   ports a, b, motion, reference; params conductance (laminar, at the reference
                   speed), exponent (of the speed), speed (the reference speed): a sliding seal's leak
weight             ports node; params weight (a gravity load's force or moment), hanging (a
                   pendulum load's angle from hanging straight down at θ = 0)
pendulum           ports node; params inertia (m_p·r²), length (the rope's), radius (the arm's
                   to the rope), damping, hanging (a payload on a rope from an arm's tip)
=================  ==========================================================================
"""
from __future__ import annotations

from dataclasses import dataclass

ACTUATOR = "actuator"
METERING_VALVE = "metering_valve"
LOAD = "load"
SPRING = "spring"
DAMPER = "damper"
CLEARANCE = "clearance"
FRICTION = "friction"
PRESSURE_SOURCE = "pressure_source"
TANK = "tank"
VOLUME = "volume"
GAS_VOLUME = "gas_volume"
RESTRICTION = "restriction"
LAMINAR_RESTRICTION = "laminar_restriction"
BAND_RESTRICTION = "band_restriction"
FILM_RESTRICTION = "film_restriction"
PUMP_COMPENSATOR = "pump_compensator"
RELIEF = "relief"
DISSOLVING_AIR = "dissolving_air"
END_CUSHION = "end_cushion"
WEIGHT = "weight"
PENDULUM = "pendulum"


@dataclass(frozen=True)
class Role:
    """One role a component type offers: slot → port name, slot → parameter name(s)."""

    name: str
    ports: tuple[tuple[str, str], ...] = ()
    params: tuple[tuple[str, tuple[str, ...]], ...] = ()

    def port(self, slot: str) -> str | None:
        return dict(self.ports).get(slot)

    def params_of(self, slot: str) -> tuple[str, ...]:
        """The type's parameter names filling ``slot`` (empty when not offered)."""
        return dict(self.params).get(slot, ())

    def param(self, slot: str) -> str | None:
        names = self.params_of(slot)
        return names[0] if names else None


def role(name: str, ports: dict[str, str] | None = None, **params: str | tuple[str, ...]) -> Role:
    """``role(ACTUATOR, {"chamber_a": "A", ...}, size="A", internal_leakage="c_il")``."""
    return Role(name, tuple((ports or {}).items()),
                tuple((k, (v,) if isinstance(v, str) else tuple(v)) for k, v in params.items()))
