"""The per-chamber air pocket candidate (candidates/leakage.py::_air_pockets): free air
trapped in one chamber more than the other, told apart from a hose by the pressure dependence
of its compliance."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist

MACHINE = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"
P0 = 1e5


@pytest.fixture(scope="module")
def pocket(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net = load_netlist(MACHINE)
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"piston": (0.04, 0.2)}, {})
    cands = [c for c in catalogue(ctx)[0] if c.effect == "entrained_air"]
    cand = next(c for c in cands if c.variant == "pocket")
    return net, model, cand, cands


def _dp_dt(model, p_vec, pressure, position=None):
    """Chamber pressure derivatives (dp1/dt, dp2/dt) at rest, with a valve command
    feeding chamber 1, both chambers at ``pressure`` (the piston at ``position``)."""
    x = np.array([s.initial for s in model.states], dtype=float)
    for i, s in enumerate(model.state_names):
        if s in ("chamber_1.p", "chamber_2.p"):
            x[i] = pressure
        if s == "piston.x" and position is not None:
            x[i] = position
    u = np.zeros(len(model.input_names))
    for i, n in enumerate(model.input_names):
        if n == "u":
            u[i] = 0.2
        elif n.startswith("p"):
            u[i] = 1.6e7
    dx, _, _, _ = model.numpy_evaluate()(0.0, list(x), p_vec, list(u))
    return float(dx[model.state_index("chamber_1.p")]), float(dx[model.state_index("chamber_2.p")])


def test_each_chamber_gets_its_own_pocket_started_at_no_effect(pocket):
    """One amount per chamber, both primary (either may stay off), the gas law's exponent a
    companion bounded by its limiting laws; at the start the chambers' pressure rates are the
    machine's own to 1e-4 down to 20 bar."""
    net, model, cand, cands = pocket
    assert [c.variant for c in cands] == ["", "pocket", "dissolving"]
    amounts = [p for p in cand.params if p.primary]
    assert len(amounts) == 2 and all(p.start <= 1e-4 for p in amounts)
    assert all(p.limits and p.bounds == (1.0, 1.4) for p in cand.params if not p.primary)
    aug = build_model(cand.build(net))
    assert {p.name for p in cand.params} <= set(aug.free_params)
    for pres in (2e6, 5e6, 1e7):
        base, start = _dp_dt(model, model.p0, pres), _dp_dt(aug, aug.p0, pres)
        assert start == pytest.approx(base, rel=1e-4)


@pytest.mark.parametrize("pressure", [2e6, 5e6, 1.2e7])
def test_a_pocket_in_one_chamber_adds_the_isothermal_gas_compliance_to_that_chamber_only(pocket, pressure):
    """Isothermal gas (Boyle, V_g·p = V_g0·p₀): the pocket adds C_g = V_g0·p₀/p² to chamber A's
    oil capacitance V_A/β, so dp_A/dt falls by C_oil/(C_oil + C_g); chamber B is untouched.
    V_g0 = r·V_A0, r = 5 % free air at 1 bar per volume of the chamber's dead volume."""
    net, model, cand, _ = pocket
    aug = build_model(cand.build(net))
    a_air, b_air = (p.name for p in cand.params if p.primary)
    a_n, b_n = (p.name for p in cand.params if not p.primary)
    r = 0.05
    V_A0 = model.param_vector()[model.param_index("cylinder.V_A0")]
    p_on = aug.param_vector({a_air: r * V_A0, a_n: 1.0, b_air: 1e-30, b_n: 1.0})
    p_off = aug.param_vector({a_air: 1e-30, b_air: 1e-30})
    (a1, b1), (a0, b0) = _dp_dt(aug, p_on, pressure), _dp_dt(aug, p_off, pressure)
    beta = model.param_vector()[model.param_index("cylinder.beta")]
    x = next(s.initial for s in model.states if s.name == "piston.x")
    A_A = model.param_vector()[model.param_index("cylinder.A")]
    C_oil = (V_A0 + A_A * x) / beta
    C_gas = r * V_A0 * P0 / pressure ** 2
    assert a1 / a0 == pytest.approx(C_oil / (C_oil + C_gas), rel=1e-6)
    assert a1 / a0 < 0.9 if pressure < 1e7 else a1 / a0 < 0.999
    assert b1 == pytest.approx(b0, rel=1e-9)


def test_the_pockets_stiffness_rises_with_pressure_a_hoses_does_not(pocket):
    """What separates a chamber's air pocket from a hose on its line: the pocket's added
    capacitance falls as 1/p² (isothermal), so the slowdown of dp_A/dt it causes shrinks
    sixfold from 20 to 120 bar (an oil volume's would not change)."""
    net, model, cand, _ = pocket
    aug = build_model(cand.build(net))
    a_air, b_air = (p.name for p in cand.params if p.primary)
    a_n, _ = (p.name for p in cand.params if not p.primary)
    V_A0 = model.param_vector()[model.param_index("cylinder.V_A0")]
    p_on = aug.param_vector({a_air: 0.05 * V_A0, a_n: 1.0})
    p_off = aug.param_vector({a_air: 1e-30, b_air: 1e-30})
    slow = [1 - _dp_dt(aug, p_on, pr)[0] / _dp_dt(aug, p_off, pr)[0] for pr in (2e6, 1.2e7)]
    assert slow[0] > 5 * slow[1]


def test_air_that_dissolves_during_the_record_starts_at_no_effect_and_adds_its_gas_and_the_volume_it_leaves(pocket):
    """The ``dissolving`` variant: a free-air state per chamber (G₀ primary, either may stay
    off; the absorption time constant a companion started at 30 s, 5 s and 150 s). At its
    start the chamber rates are the machine's to 10⁻⁴; with G₀ = 5 % of V_A0 in chamber A at
    the record's start (s = 1, dissolving: Ġ = −G₀/τ_a) the continuity of oil and gas gives
    (C_oil + G·p_atm/p²)·ṗ_A = C_oil·ṗ_A,off − p_atm·G/(τ_a·p) (Zhou et al. 2013), where the
    chamber's free air G = G₀·V_A(x)/V_A0 is a share of its oil, V_A(x) = V_A0 + A·x (the
    bubbles travel with the oil), and chamber B, shrinking, keeps none of chamber A's."""
    net, model, _, cands = pocket
    cand = next(c for c in cands if c.variant == "dissolving")
    amounts = [p for p in cand.params if p.primary]
    taus = [p for p in cand.params if not p.primary]
    assert len(amounts) == 2 and len(taus) == 2
    assert all(t.start == 30.0 and t.shapes == (5.0, 150.0) for t in taus)
    aug = build_model(cand.build(net))
    for pres in (2e6, 5e6, 1e7):
        assert _dp_dt(aug, aug.p0, pres) == pytest.approx(_dp_dt(model, model.p0, pres), rel=1e-4)
    a_g, b_g = (p.name for p in amounts)
    a_t, _ = (p.name for p in taus)
    V_A0 = model.param_vector()[model.param_index("cylinder.V_A0")]
    beta = model.param_vector()[model.param_index("cylinder.beta")]
    A_A = model.param_vector()[model.param_index("cylinder.A")]
    G0, tau, pres = 0.05 * V_A0, 10.0, 2e6
    p_on = aug.param_vector({a_g: G0, a_t: tau, b_g: 1e-30})
    p_off = aug.param_vector({a_g: 1e-30, b_g: 1e-30})
    for x in (0.0, 0.07, -0.05):
        C_oil = (V_A0 + A_A * x) / beta
        G = G0 * (V_A0 + A_A * x) / V_A0
        (a1, b1), (a0, b0) = _dp_dt(aug, p_on, pres, x), _dp_dt(aug, p_off, pres, x)
        assert a1 == pytest.approx((C_oil * a0 - P0 * G / (tau * pres)) / (C_oil + G * P0 / pres ** 2), rel=1e-6)
        assert b1 == pytest.approx(b0, rel=1e-9)


def test_dissolving_air_takes_the_chambers_oil_from_the_drawing_not_from_a_grown_fit(pocket):
    """A base fit without the air grows the chamber volumes to stand in for it (dev EHA seed
    137: ×2.8, ×2.1); the dissolving law's share of air follows the chamber's oil as DRAWN,
    or the fit can shrink the actuator's volume until the recorded stroke empties a chamber."""
    net, model, _, _ = pocket
    from hydrocli.diagnose import augment as A
    grown = A.set_values(net, {"cylinder.V_A0": 3 * 2.11e-4, "cylinder.V_B0": 2 * 6.75e-4})
    ctx = Context(grown, set(model.free_params), {"piston": (0.04, 0.2)}, {}, drawn=net)
    cand = next(c for c in catalogue(ctx)[0] if c.effect == "entrained_air" and c.variant == "dissolving")
    built = cand.build(grown)
    elements = [built.components[p.name.rpartition(".")[0]] for p in cand.params if p.primary]
    assert [e.params["V"].value for e in elements] == pytest.approx([2.11e-4, 6.75e-4])
    assert [e.params["A"].value for e in elements] == pytest.approx([2.0994e-3, -2.0994e-3])
    # without a drawing the current volumes stand in
    ctx = Context(grown, set(model.free_params), {"piston": (0.04, 0.2)}, {})
    cand = next(c for c in catalogue(ctx)[0] if c.effect == "entrained_air" and c.variant == "dissolving")
    built = cand.build(grown)
    assert built.components[cand.params[0].name.rpartition(".")[0]].params["V"].value == pytest.approx(3 * 2.11e-4)
