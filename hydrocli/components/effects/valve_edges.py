"""A 4/3 proportional valve with an individual flow gain per metering edge (valve asymmetry:
unmatched edges from machining tolerances or wear, so meter-in and meter-out edges and the two
directions differ). Same equations as ``valve_4_3`` (seed 004 eqs. 1–3; seed 000 eqs. 6–9) with
the edge flows scaled by g_PA, g_BT (x_v > 0) and g_PB, g_AT (x_v < 0); all gains 1 is the
symmetric valve."""
from __future__ import annotations

from ..base import Param
from ..hydraulic.valve import VALVE_ROLE, Valve43
from ..registry import register
from .. import roles as RL
from ..roles import role


@register
class Valve43Edges(Valve43):
    type = "valve_4_3_edges"
    roles = (role(RL.METERING_VALVE, dict(VALVE_ROLE.ports), **{k: v for k, v in VALVE_ROLE.params}, edge_gains=("g_PA", "g_BT", "g_PB", "g_AT")),)
    family = "effects"
    description = "4/3 proportional valve with one flow gain per metering edge (valve asymmetry)"
    parameters = Valve43.parameters + (
        Param("g_PA", "1", 1.0, "gain of edge P→A relative to Kv", positive=True, bounds=(0.3, 3.0)),
        Param("g_BT", "1", 1.0, "gain of edge B→T relative to Kv", positive=True, bounds=(0.3, 3.0)),
        Param("g_PB", "1", 1.0, "gain of edge P→B relative to Kv·Kv_neg_ratio", positive=True, bounds=(0.3, 3.0)),
        Param("g_AT", "1", 1.0, "gain of edge A→T relative to Kv·Kv_neg_ratio", positive=True, bounds=(0.3, 3.0)),
    )

    def edge_gains(self, c):
        p = c.p
        kv, _, kneg, _ = super().edge_gains(c)
        return kv * p.g_PA, kv * p.g_BT, kneg * p.g_PB, kneg * p.g_AT
