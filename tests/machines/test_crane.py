"""Seed 000 knuckle-boom crane: mobility (eq. 1), Table 2 connection stiffnesses (eq. 2), and a
steady holding run whose p2/p3 balance the gravity load through the cylinder Jacobian with
both counterbalance valves below their cracking lines (eqs. 29–33); the inner jib has the Fig. 2
circuit (servo valve, Table 4; one externally vented CBV, Table 5) and holds its load with that
CBV below its cracking line p2 + ψ·p3 = p_cr (eqs. 13, 16, 18)."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.graph.mobility import mechanism_mobility
from hydrocli.experiments.experiment_file import load_experiment_file
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]
MACHINES = ("knuckle_boom_crane.yaml", "knuckle_boom_crane_identified.yaml")


@pytest.mark.parametrize("machine", MACHINES)
def test_mechanism_has_four_degrees_of_freedom(machine):
    count = mechanism_mobility(load_netlist(ROOT / "machines" / machine))
    # seed 000 eq. 1: three jibs and the yoke; the cylinders' barrels/pistons add no DOF
    assert (count.prismatic, count.universal, count.spherical, count.revolute) == (3, 3, 3, 4)
    assert count.dof == 4


def test_table2_connection_stiffnesses():
    model = build_model(load_netlist(ROOT / "machines" / "knuckle_boom_crane.yaml"))
    vs = model.evaluate_along(np.zeros(1), model.x0[None, :], np.zeros((1, 3)))
    ser = lambda a, b: 1.0 / (1.0 / a + 1.0 / b)        # eq. 2
    expected = {  # Table 2 (printed k_C where legible; the rest from eq. 2 on Table 2's k_S)
        "pedestal_flex.k_C1": 2.88e9,
        "inner_flex.k_C1": 1.96e9, "inner_flex.k_C2": ser(1.96e9, 8.73e8),
        "inner_flex.k_C3": ser(8.73e8, 4.05e8), "inner_flex.k_C4": 4.05e8,
        "outer_flex.k_C1": 2.08e8, "outer_flex.k_C2": 8.33e7, "outer_flex.k_C3": 1.39e8,
    }
    for name, k in expected.items():
        assert vs[name][0] == pytest.approx(k, rel=3e-3), name
    ident = build_model(load_netlist(ROOT / "machines" / "knuckle_boom_crane_identified.yaml"))
    vi = ident.evaluate_along(np.zeros(1), ident.x0[None, :], np.zeros((1, 3)))
    assert vi["outer_flex.k_C2"][0] == pytest.approx(0.55 * 8.33e7, rel=3e-3)   # §5.3: 55 %


def test_steady_hold_pressures_balance_gravity():
    model = build_model(load_netlist(ROOT / "machines" / "knuckle_boom_crane.yaml"))
    exp = load_experiment_file(ROOT / "experiments" / "crane" / "hold.yaml", model)
    tr = simulate(model, exp.inputs, exp.t_out, x0=model.x0, opts=SolverOptions(rtol=1e-6))
    y = {n: tr.Y[:, i] for i, n in enumerate(model.output_names)}
    late = exp.t_out > exp.t_out[-1] - 1.0
    assert np.ptp(y["l_outer"]) < 5e-3                     # held: no creep beyond deflection
    u = np.zeros((exp.t_out.size, 3))
    vs = model.evaluate_along(exp.t_out, tr.X, u)
    p = {k: np.mean(y[f"{k}_outer"][late]) - 1e5 for k in ("p1", "p2", "p3", "p4")}   # gauge
    a_a, a_b = 4.909e-2, 3.682e-2                          # Table 6
    # static balance: (p2·A_A − p3·A_B − F_S-band)·∂L/∂q = gravity torque at joint D
    f_hyd = p["p2"] * a_a - p["p3"] * a_b
    f_needed = np.mean(vs["crane.bias10"][late] / vs["crane.dL3_dq10"][late])
    assert f_hyd == pytest.approx(f_needed, abs=6400 + 0.03 * f_needed)
    # eqs. 29–33: neither CBV is past its cracking line while holding
    c1, c2, p_cr = 1.6267, 0.2452, 250e5
    line = lambda mu_x: 1.0 / (1.0 + c1 * mu_x + c2 * mu_x ** 2)
    mu_l2, mu_x2 = (p["p3"] - p["p4"]) / p_cr, p["p1"] / p["p3"]     # eqs. 30–31 (CBV2)
    mu_l1, mu_x1 = (p["p2"] - p["p1"]) / p_cr, p["p4"] / p["p2"]     # eqs. 32–33 (CBV1)
    assert mu_l1 < line(mu_x1) and mu_l2 < line(mu_x2)
    assert p["p2"] > 30e5 and p["p3"] > 0.0


def test_inner_jib_servo_valve_and_vented_cbv_hold_the_load():
    net = load_netlist(ROOT / "machines" / "knuckle_boom_crane.yaml")
    inner = {k.split(".", 1)[1]: c for k, c in net.components.items() if k.startswith("inner.")}
    assert inner["dcv"].type == "valve_4_3"                               # servo valve, not PC-LS
    cbvs = [c for c in inner.values() if c.type == "counterbalance_valve"]
    assert len(cbvs) == 1 and int(cbvs[0].params["vented"].value) == 1   # ONE vented CBV (Fig. 2)
    model = build_model(net)
    p = model.param_vector()
    lpm = 1e-3 / 60 / np.sqrt(1e5)                                        # L/min/bar^0.5 → SI
    table = {"inner.dcv.Kv": 111.8 * lpm, "inner.dcv.tau": 1 / 250, "inner.dcv.zeta": 0.8,     # Table 4
             "inner.dcv.overlap_PA": 0.05, "inner.dcv.overlap_AT": 0.0,
             "inner.cbv.Cv_check": 89.4 * lpm, "inner.cbv.p_cr": 250e5, "inner.cbv.C1": 3.0,   # Table 5
             "inner.cbv.C2": 0.0, "inner.cbv.p_cr_check": 1e5, "inner.cbv.k_s_check": 1e5}
    for name, v in table.items():
        assert p[model.param_index(name)] == pytest.approx(v, rel=1e-3, abs=1e-12), name
    exp = load_experiment_file(ROOT / "experiments" / "crane" / "hold.yaml", model)
    tr = simulate(model, exp.inputs, exp.t_out, x0=model.x0, opts=SolverOptions(rtol=1e-6))
    y = {n: tr.Y[:, i] for i, n in enumerate(model.output_names)}
    vs = model.evaluate_along(exp.t_out, tr.X, np.zeros((exp.t_out.size, 3)))
    assert np.ptp(y["l_inner"]) < 1e-3                                    # held (no creep)
    p2, p3 = y["p2_inner"] - 1e5, y["p3_inner"] - 1e5                    # gauge (vented to tank)
    psi, p_cr = 3.0, 250e5                                                # Table 5, inner jib
    assert np.all(p2 + psi * p3 < 0.95 * p_cr)                            # eq. 13: below cracking
    assert np.all(p2 / p_cr < 1.0 / (1.0 + psi * p3 / p2))                # eqs. 15, 16, 18
    assert np.all(vs["inner.cbv.s"] < 0)
    assert np.max(np.abs(vs["inner.cbv.q"])) < 1e-7                       # no lowering flow
    # the trapped piston chamber carries the jib: p2·A_A − p3·A_B = gravity torque / (∂L/∂q) at B
    a_a, a_b = 7.069e-2, 4.524e-2                                         # Table 6, inner jib
    f_hyd = np.mean(p2 * a_a - p3 * a_b)
    f_needed = np.mean(vs["crane.bias4"] / vs["crane.dL1_dq4"])
    assert f_needed > 5e5
    assert f_hyd == pytest.approx(f_needed, abs=6400 + 0.03 * f_needed)
