"""The film-leak candidate (candidates/leakage.py::_film_leaks): external leakage through a
rod (shaft) seal's film, q = c·φ(v)·(p − p_T), φ → (|v|/v_ref)ⁿ in motion and 0 at rest — a
seal that holds a load at standstill and lets oil out while the rod moves. Checked against the
laminar seal law (seed 004 eqs. 4–5), which the film law must equal at the reference speed and
must NOT be at rest."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose import locate
from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.candidates.leakage import FILM_EXPONENTS
from hydrocli.diagnose.engine import diagnosed_machine
from hydrocli.model.builder import build_model

MACHINES = Path(__file__).parents[2] / "machines"
C = 3e-12            # m³/s/Pa at the reference speed: 30 bar over the tank drains 9·10⁻⁶ m³/s (0.5 L/min)


def _setup(machine: str):
    net, _, _ = diagnosed_machine(str(MACHINES / f"{machine}.yaml"))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {}, locate.output_quantities(model), {})
    cands = {c.key: c for c in catalogue(ctx)[0]}
    return net, model, cands


@pytest.fixture(scope="module")
def lift():
    return _setup("luffing_cylinder")


@pytest.fixture(scope="module")
def winch():
    return _setup("hoist_winch")


def _rates(model, p_vec, speed_state: str, v: float, pressures: dict[str, float]) -> dict[str, float]:
    """d p/dt of each chamber with the actuator moving at ``v``, chambers at ``pressures``."""
    x = np.array([s.initial for s in model.states], dtype=float)
    for name, p in pressures.items():
        x[model.state_index(name)] = p
    x[model.state_index(speed_state)] = v
    u = np.zeros(len(model.input_names))
    u[model.input_names.index("Ps")] = 1.6e7
    dx, _, _, _ = model.numpy_evaluate()(0.0, list(x), p_vec, list(u))
    return {name: float(dx[model.state_index(name)]) for name in pressures}


def test_a_single_rod_cylinder_gets_one_film_on_its_rod_side_a_motor_one_per_shaft_seal(lift, winch):
    """The lift's piston side has no seal to the outside: one film leak, from chamber B (the
    annulus), conductance primary and started off, the exponent a companion started at ½ and 3/2.
    The winch's motor has two shaft seals: two rotary film leaks, one per chamber."""
    net, _, cands = lift
    film = cands["external_leakage@cylinder#film"]
    c = [p for p in film.params if p.primary]
    n = [p for p in film.params if not p.primary]
    assert len(c) == 1 and len(n) == 1
    assert n[0].start == FILM_EXPONENTS[0] and n[0].shapes == FILM_EXPONENTS[1:]
    aug = film.build(net)
    comp = aug.components[c[0].name.rpartition(".")[0]]
    assert comp.type == "film_leak" and comp.ports["A"] == net.components["cylinder"].ports["B"]
    wnet, _, wcands = winch
    wfilm = wcands["external_leakage@motor#film"]
    waug = wfilm.build(wnet)
    types = [waug.components[p.name.rpartition(".")[0]].type for p in wfilm.params if p.primary]
    assert types == ["film_leak_rotary", "film_leak_rotary"]


@pytest.mark.parametrize("which", ["lift", "winch"])
def test_the_film_drains_like_a_laminar_seal_at_the_reference_speed_and_not_at_rest(which, lift, winch):
    """At the reference speed the film leak at conductance c takes from the sealed chamber what
    a laminar seal R = 1/c takes (to (v_ε/v_ref)² = 10⁻⁴ of it); at three times the speed √3
    times that (n = ½); at standstill nothing (the base's rates to 10⁻⁹ of the laminar seal's
    drain): the seal holds the load."""
    net, model, cands = lift if which == "lift" else winch
    key, speed, v_ref = (("external_leakage@cylinder", "rod.v", 0.1) if which == "lift"
                         else ("external_leakage@motor", "drum_node.w", 1.0))
    chambers = (["chamber_A.p", "chamber_B.p"] if which == "lift" else ["chamber_1.p", "chamber_2.p"])
    pres = dict(zip(chambers, (8e6, 3e6)))
    film = cands[f"{key}#film"]
    seal = cands[f"{key}#rod_seal" if which == "lift" else f"{key}#laminar"]
    f_model = build_model(film.build(net))
    s_model = build_model(seal.build(net))
    f_on = f_model.param_vector({p.name: C for p in film.params if p.primary})
    s_on = s_model.param_vector({p.name: 1.0 / C for p in seal.params})
    for v, share in ((v_ref, 1.0), (-3 * v_ref, 3 ** 0.5)):
        base = _rates(model, model.p0, speed, v, pres)
        laminar = _rates(s_model, s_on, speed, v, pres)
        filmed = _rates(f_model, f_on, speed, v, pres)
        for ch in chambers:
            if laminar[ch] == pytest.approx(base[ch], rel=1e-12, abs=1e-9):
                continue                  # a chamber without a seal (the lift's piston side)
            assert filmed[ch] - base[ch] == pytest.approx(share * (laminar[ch] - base[ch]), rel=2e-4)
    base = _rates(model, model.p0, speed, 0.0, pres)
    laminar = _rates(s_model, s_on, speed, 0.0, pres)
    filmed = _rates(f_model, f_on, speed, 0.0, pres)
    drained = max(abs(laminar[ch] - base[ch]) for ch in chambers)
    assert drained > 0
    assert all(abs(filmed[ch] - base[ch]) <= 1e-9 * drained + 1e-9 for ch in chambers)


def test_started_off_the_candidate_is_the_base_machine(lift):
    """At its start values (c = 10⁻¹⁴·size ratio, a drift far below the noise) the augmented lift's
    chamber rates in motion are the base's to 10⁻³ of the drain at the plausible floor."""
    net, model, cands = lift
    film = cands["external_leakage@cylinder#film"]
    aug = build_model(film.build(net))
    pres = {"chamber_A.p": 8e6, "chamber_B.p": 3e6}
    a = _rates(aug, aug.p0, "rod.v", 0.1, pres)
    b = _rates(model, model.p0, "rod.v", 0.1, pres)
    assert a["chamber_A.p"] == pytest.approx(b["chamber_A.p"], rel=1e-9, abs=1e-6)
    assert abs(a["chamber_B.p"] - b["chamber_B.p"]) < 1e-3 * abs(b["chamber_B.p"]) + 10.0
