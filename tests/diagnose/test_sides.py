"""The fluid volumes on each side of an actuator (diagnose/sides.py), and a chamber that a fit
grew by what it took from a volume on the same side is not undrawn fluid (findings.py)."""
from __future__ import annotations

from pathlib import Path

import pytest

from hydrocli.components import roles as R
from hydrocli.diagnose import findings
from hydrocli.diagnose.candidates import Context
from hydrocli.diagnose.findings import Feeder
from hydrocli.diagnose.sides import feeders
from hydrocli.netlist.loader import load_netlist, load_netlist_text

ROOT = Path(__file__).resolve().parents[2]


def _free(net):
    return {f"{c}.{p}" for c, comp in net.components.items() for p, v in comp.params.items() if v.free}


def _sides(net):
    ctx = Context(net, _free(net))
    return feeders(ctx)[ctx.parts(R.ACTUATOR)[0].name]


def test_the_line_beyond_a_counterbalance_valve_feeds_the_piston_side_only():
    """The counterbalance valve joins the work line A to chamber A; its pilot port takes no
    flow, so the rod-side chamber that pilots it is NOT on the line's side."""
    a, b = _sides(load_netlist(ROOT / "machines/luffing_cylinder_cbv.yaml"))
    assert [f.volume for f in a] == ["line_A_oil.V"] and b == ()
    assert a[0].volume_file == pytest.approx(3.0e-4) and a[0].modulus_file == pytest.approx(1.5e9)
    # machines whose chambers the metering valve feeds directly have none
    for name in ("luffing_cylinder", "eha_testbench", "rotary_drive"):
        assert _sides(load_netlist(ROOT / f"machines/{name}.yaml")) == ((), ())


CHAIN = """
name: chain
fluid: {beta: "1.5 GPa"}
inputs: {u: {unit: "1"}}
components:
  supply: {type: pressure_source, ports: {P: ps}, p: "100 bar"}
  supply_oil: {type: volume, ports: {P: ps}, V: {value: 1.0e-3, free: true}}
  tank: {type: tank, ports: {T: pt}}
  valve: {type: valve_4_3, ports: {P: ps, T: pt, A: a1, B: b1, cmd: u}, Kv: 1.0e-7}
  hose_a: {type: orifice, ports: {A: a1, B: a2}, Kv: 1.0e-6}
  oil_a1: {type: volume, ports: {P: a1}, V: {value: 2.0e-4, free: true}}
  oil_a2: {type: volume, ports: {P: a2}, V: {value: 1.0e-4, free: true}}
  oil_fixed: {type: volume, ports: {P: a2}, V: 5.0e-5}
  cylinder: {type: cylinder, ports: {A: a2, B: b1, rod: rod, body: ground}, A_A: 1.0e-3, A_B: 5.0e-4,
             V_A0: 1.0e-4, V_B0: 1.0e-4}
  load: {type: mass, ports: {m: rod}, m: 10}
"""


def test_volumes_are_found_along_flow_paths_up_to_the_metering_valve():
    """Two free volumes behind an orifice on the A side are found; the supply's volume lies
    beyond the metering valve and a fixed volume is not the fit's to move."""
    a, b = _sides(load_netlist_text(CHAIN, "chain.yaml"))
    assert sorted(f.volume for f in a) == ["oil_a1.V", "oil_a2.V"] and b == ()


VOLS = ("cylinder.V_A0", "cylinder.V_B0")
LINE = Feeder("line_A_oil.V", "line_A_oil.beta", 3.0e-4, 1.5e9)


def _rows(v_a0, v_line, beta_line, beta=1.37e9):
    """The counterbalanced lift's null case (dev seed 30): V_A0 ×1.70, the line at its bound."""
    return [{"name": "cylinder.V_A0", "value": v_a0, "initial": 4.0e-4, "stderr": 6.0e-5},
            {"name": "cylinder.V_B0", "value": 1.88e-3, "initial": 2.12e-3, "stderr": 1.6e-4},
            {"name": "cylinder.beta", "value": beta, "initial": 1.5e9, "stderr": 1e7},
            {"name": "line_A_oil.V", "value": v_line, "initial": 3.0e-4, "stderr": 5e-6},
            {"name": "line_A_oil.beta", "value": beta_line, "initial": 1.5e9, "stderr": 1e5}]


def test_a_chamber_grown_by_what_the_line_lost_is_not_undrawn_fluid():
    with_line = [findings.Chambers("cylinder", VOLS, "cylinder.beta", ((LINE,), ()))]
    without = [findings.Chambers("cylinder", VOLS, "cylinder.beta")]
    moved = _rows(6.81e-4, 5.0e-5, 2.5e9)
    # read alone, V_A0 ×1.70 (4.7 σ) on one side is a hose the drawing leaves out
    assert [f["effect"] for f in findings.undrawn_volume(moved, without, lambda v: (1.0, 0.1))] == ["line_dynamics"]
    # the line's 0.3 L at 1.5 GPa went to 0.05 L at 2.5 GPa: 2.46e-4 m³ of oil at the chamber's
    # 1.37 GPa moved into V_A0; net ×1.09, as drawn
    net = findings.net_of_feeders(with_line[0], moved[:2], {r["name"]: r for r in moved})
    assert net[0]["value"] == pytest.approx(6.81e-4 - (3e-4 / 1.5e9 - 5e-5 / 2.5e9) * 1.37e9)
    assert net[1] == moved[1]
    assert findings.undrawn_volume(moved, with_line, lambda v: (1.0, 0.1)) == []
    # the line kept its volume: the growth is undrawn fluid again, on the same rule
    kept = _rows(6.81e-4, 3.0e-4, 1.5e9)
    assert [f["effect"] for f in findings.undrawn_volume(kept, with_line, lambda v: (1.0, 0.1))] == ["line_dynamics"]
    # the chamber's modulus not free: the file's stands in for the fitted one
    fixed = [r for r in moved if r["name"] != "cylinder.beta"]
    ch = findings.Chambers("cylinder", VOLS, "cylinder.beta", ((LINE,), ()), 1.37e9)
    assert findings.net_of_feeders(ch, fixed[:2], {r["name"]: r for r in fixed})[0] == net[0]
    # a line the fit GREW is not chamber volume taken back
    grown = _rows(6.81e-4, 6.0e-4, 1.5e9)
    assert findings.net_of_feeders(with_line[0], grown[:2], {r["name"]: r for r in grown})[0] == grown[0]


def test_every_chamber_grown_counts_the_feeders_too():
    """Air grows every chamber alike (fluid_compliance_excess); a side whose growth is the line's
    loss does not count as grown."""
    rows = _rows(1.2e-3, 3.0e-4, 1.5e9)
    rows[1] = dict(rows[1], value=4.5e-3)                       # V_B0 ×2.1
    ch = [findings.Chambers("cylinder", VOLS, "cylinder.beta", ((LINE,), ()))]
    assert [f["effect"] for f in findings.fluid_compliance_excess(rows, ch, lambda v: (1.0, 0.1))] == ["entrained_air"]
    rows[3] = dict(rows[3], value=5.0e-5)
    rows[0] = dict(rows[0], value=6.0e-4)                       # ×1.5, all of it from the line
    assert findings.fluid_compliance_excess(rows, ch, lambda v: (1.0, 0.1)) == []
