"""The weeping-relief candidate (candidates/leakage.py::_weeping_reliefs): external leakage
that flows only above a cracking pressure, q = K·max(p − p_T − p_cr, 0)·√(p − p_T) with
K = C_V/k_s (seed 000 eqs. 6, 12 with the override k_s beyond any chamber pressure), one
relief per chamber, told from a seal's leak by where in the pressure range the oil goes."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.candidates.leakage import WEEP_CRACK_STARTS, WEEP_OVERRIDE
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist

MACHINE = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"
P_S = 1.6e7          # the supply set-point the recording starts with (an input of this bench)
P_T = 1e5


@pytest.fixture(scope="module")
def relief(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net = load_netlist(MACHINE)
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"piston": (0.04, 0.2)}, {}, {"Ps": P_S})
    cand = next(c for c in catalogue(ctx)[0] if c.key == "external_leakage@cylinder#relief")
    return net, model, cand


def _dp_dt(model, p_vec, p1, p2):
    """Chamber pressure rates at rest with the valve closed, chambers at p1 and p2."""
    x = np.array([s.initial for s in model.states], dtype=float)
    x[model.state_index("chamber_1.p")], x[model.state_index("chamber_2.p")] = p1, p2
    u = np.zeros(len(model.input_names))
    u[model.input_names.index("Ps")] = P_S
    dx, _, _, _ = model.numpy_evaluate()(0.0, list(x), p_vec, list(u))
    return float(dx[model.state_index("chamber_1.p")]), float(dx[model.state_index("chamber_2.p")])


def test_one_relief_per_chamber_started_off_cracking_at_shares_of_the_supply(relief):
    """Two conductances, both primary (one chamber's relief may weep alone), two cracking
    pressures as companions started at half the supply read from its input, crossed with a
    quarter and three quarters of it; at the start the machine is the base to 1e-6 up to the
    supply pressure (it drains at most 3·10⁻¹⁰ m³/s there)."""
    net, model, cand = relief
    cv = [p for p in cand.params if p.primary]
    crack = [p for p in cand.params if not p.primary]
    assert len(cv) == 2 and len(crack) == 2
    assert all(p.start == WEEP_CRACK_STARTS[0] * P_S and p.shapes == tuple(f * P_S for f in WEEP_CRACK_STARTS[1:])
               and p.bounds[0] == 0.0 for p in crack)
    aug = build_model(cand.build(net))
    assert {p.name for p in cand.params} <= set(aug.free_params)
    for pres in (3e6, 1e7, P_S):
        assert _dp_dt(aug, aug.p0, pres, 2e6) == pytest.approx(_dp_dt(model, model.p0, pres, 2e6), rel=1e-5)


def _relief_flows(model, p_vec, pressures):
    """Each relief's flow (its named variable q) with chamber 1 at each of ``pressures``."""
    n = len(pressures)
    X = np.tile([s.initial for s in model.states], (n, 1)).astype(float)
    X[:, model.state_index("chamber_1.p")] = pressures
    X[:, model.state_index("chamber_2.p")] = 2e6
    U = np.zeros((n, len(model.input_names)))
    U[:, model.input_names.index("Ps")] = P_S
    return model.evaluate_along(np.zeros(n), X, U, p_vec)


def test_the_relief_drains_its_chamber_only_above_cracking_by_the_poppet_law(relief):
    """With chamber 1's relief at K = 3·10⁻¹⁵ m³/s/Pa^1.5 cracking 80 bar over the tank, its flow is
    K·(p − p_T − p_cr)·√(p − p_T) above that and nothing below (to the 0.1 bar smoothing:
    under 10⁻⁹ m³/s 5 bar below it), and
    it is all taken from chamber 1: dp₁/dt falls by the flow over the chamber's capacitance
    as the same flow through a laminar seal takes it; chamber 2 is untouched."""
    net, model, cand = relief
    aug = build_model(cand.build(net))
    cv1, cv2 = (p.name for p in cand.params if p.primary)
    cr1, cr2 = (p.name for p in cand.params if not p.primary)
    K, p_cr = 3e-15, 8e6
    p_on = aug.param_vector({cv1: K * WEEP_OVERRIDE, cr1: p_cr, cr2: p_cr})
    p_off = aug.param_vector({cr1: p_cr, cr2: p_cr})
    pressures = np.array([4e6, 7.5e6, 1e7, 1.4e7])
    flows = _relief_flows(aug, p_on, pressures)
    relief_1 = cv1.rsplit(".", 1)[0]
    ref = K * np.maximum(pressures - P_T - p_cr, 0.0) * np.sqrt(pressures - P_T)
    assert flows[f"{relief_1}.q"] == pytest.approx(ref, rel=1e-3, abs=1e-9)
    assert flows[f"{relief_1}.q"][-1] > 1e-5       # 60 bar over cracking: about a litre a minute
    # the flow leaves chamber 1 and nothing else: the same drop as a laminar seal passing it
    c_el = model.param_vector()[model.param_index("cylinder.c_el")]
    for pres, q in zip(pressures, flows[f"{relief_1}.q"]):
        (a1, b1), (a0, b0) = _dp_dt(aug, p_on, pres, 2e6), _dp_dt(aug, p_off, pres, 2e6)
        seal = model.param_vector({"cylinder.c_el": c_el + q / pres})
        (s1, _), (s0, _) = _dp_dt(model, seal, pres, 2e6), _dp_dt(model, model.p0, pres, 2e6)
        assert a0 - a1 == pytest.approx(s0 - s1, rel=1e-3, abs=10.0), pres
        assert b1 == pytest.approx(b0, rel=1e-12)


def test_the_relief_is_offered_on_every_machine_with_a_tank_and_a_supply():
    """Found by roles on the lift, the vane drive and the winch (supply a parameter or an input), one valve per chamber."""
    root = Path(__file__).parents[2] / "machines"
    for name in ("luffing_cylinder.yaml", "rotary_drive.yaml", "hoist_winch.yaml"):
        path = root / name
        net = load_netlist(path)
        model = build_model(net)
        cands, _ = catalogue(Context(net, set(model.free_params), {}, {}, {}))
        found = [c for c in cands if c.effect == "external_leakage" and c.variant == "relief"]
        assert len(found) == 1 and sum(p.primary for p in found[0].params) == 2, name
