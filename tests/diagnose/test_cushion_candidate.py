"""The end-cushion candidate (candidates/cushion.py): an ``end_stop`` form that throttles the
emptied chamber's outflow near an end, inserted between the chamber and what feeds it."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.measurement import with_pressure_sensors
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

MACHINE = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"
TRAVEL = (0.04, 0.2)


@pytest.fixture(scope="module")
def eha(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net, _ = with_pressure_sensors(load_netlist(MACHINE))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"piston": TRAVEL}, {})
    cands = {c.variant: c for c in catalogue(ctx)[0] if c.effect == "end_stop"}
    return net, model, cands


def _run(model, p=None, t_end=4.0):
    """The EHA driven out to its upper end and back: a slow 0.25 Hz command."""
    t = np.linspace(0.0, t_end, 2001)
    cols = {"u": 0.1 * np.sin(2 * np.pi * 0.25 * t)}
    U = np.column_stack([cols.get(n, np.full(t.size, 1.6e7 if n.lower().startswith("p") else 0.0)) for n in model.input_names])
    return simulate(model, InputTable(t, U), t, p=model.p0 if p is None else p, opts=SolverOptions(rtol=1e-7))


def test_a_cushion_is_offered_at_each_end_on_the_chamber_that_end_empties(eha):
    """Upper end: chamber B (emptied while extending), lower end: chamber A. The valve's
    port moves to a new line node; the chamber keeps the actuator and its pressure sensor."""
    net, _, cands = eha
    assert {"cushion_max", "cushion_min"} <= set(cands)
    for variant, chamber in (("cushion_max", "chamber_2"), ("cushion_min", "chamber_1")):
        c = cands[variant]
        assert c.params[0].primary and c.params[0].scale > 0            # a position, judged as a stop's
        assert not any(p.primary for p in c.params[1:3])
        # the file has no stops: the metal stop behind the cushion comes with it (its end's
        # position and the contact stiffness), the other end's stop out of reach
        mine, other = ("x_max", "x_min") if variant == "cushion_max" else ("x_min", "x_max")
        assert {p.name for p in c.params[3:]} == {f"cylinder.{mine}", "cylinder.k_stop"}
        stop = next(p for p in c.params if p.name == f"cylinder.{mine}")
        assert stop.primary and stop.reach == c.params[0].reach             # a stop without a cushion is a stop
        far = c.fixed[f"cylinder.{other}"]
        assert far > TRAVEL[1] + 0.2 if other == "x_max" else far < TRAVEL[0] - 0.2
        aug = c.build(net)
        on_chamber = {comp for comp, _ in aug.nodes()[chamber]}
        assert "cylinder" in on_chamber and f"{chamber}_sensor" in on_chamber and "valve" not in on_chamber
        cushion = next(n for n, k in aug.components.items() if k.type == "end_cushion")
        assert aug.components[cushion].ports["chamber"] == chamber
        line = aug.components[cushion].ports["line"]
        assert "valve" in {comp for comp, _ in aug.nodes()[line]}


def test_started_beyond_the_travel_the_cushion_changes_nothing(eha):
    """Off (its end a fifth of the travel beyond the travel seen) the cushioned machine
    follows the machine's own trajectory: pressures within 0.05 bar, position within 5 µm."""
    net, model, cands = eha
    base = _run(model)
    for c in (cands["cushion_max"], cands["cushion_min"]):
        aug = build_model(c.build(net))
        tr = _run(aug)
        for o in ("P1", "P2"):
            i, j = model.output_names.index(o), aug.output_names.index(o)
            assert np.max(np.abs(tr.Y[:, j] - base.Y[:, i])) < 5e3, (c.key, o)
        i, j = model.output_names.index("x"), aug.output_names.index("x")
        assert np.max(np.abs(tr.Y[:, j] - base.Y[:, i])) < 5e-6


def test_engaged_the_cushion_raises_the_emptied_chambers_pressure_and_brakes_the_piston(eha):
    """With its end inside the travel, over the cushion's length the oil leaving chamber B
    must pass the needle: chamber B's pressure rises above the uncushioned machine's while the
    piston approaches the end more slowly; away from the end nothing changes."""
    net, model, cands = eha
    c = cands["cushion_max"]
    aug = build_model(c.build(net))
    x_end, length, needle = (p.name for p in c.params[:3])
    base = _run(model)
    x0 = base.Y[:, model.output_names.index("x")]
    top = float(np.max(x0))
    p = aug.param_vector({x_end: top + 0.002, length: 0.01, needle: 2e-9})
    tr = _run(aug, p)
    x1 = tr.Y[:, aug.output_names.index("x")]
    p2_0, p2_1 = base.Y[:, model.output_names.index("P2")], tr.Y[:, aug.output_names.index("P2")]
    near = x0 > top - 0.01
    far = (x0 < top - 0.03) & (np.arange(x0.size) < 600)          # before it first nears the end
    assert np.max(p2_1[near] - p2_0[near]) > 5e5                      # the needle holds back chamber B
    assert np.max(x1) < top - 1e-3                                     # braked before the uncushioned top
    assert far.sum() > 100 and np.max(np.abs(p2_1[far] - p2_0[far])) < 5e3


@pytest.fixture(scope="module")
def vane(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net, _ = with_pressure_sensors(load_netlist(MACHINE.parent / "rotary_drive.yaml"))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"arm_node": (-0.025, 0.52)}, {})
    cands = {c.variant: c for c in catalogue(ctx)[0] if c.effect == "end_stop"}
    return net, model, cands


def _swing(model, p=None):
    """The vane drive swung up to about 0.52 rad and back: a slow 0.25 Hz command."""
    t = np.linspace(0.0, 4.0, 2001)
    U = np.column_stack([0.1 * np.sin(2 * np.pi * 0.25 * t) if n == "u" else np.full(t.size, 1.6e7)
                         for n in model.input_names])
    return simulate(model, InputTable(t, U), t, p=model.p0 if p is None else p, opts=SolverOptions(rtol=1e-7))


def test_a_vane_is_offered_a_rotary_cushion_that_brakes_the_swing_near_its_end(vane):
    """A vane actuator's swing ends like a piston's stroke: the cushion (its end, length and
    needle in rad, library ``end_cushion_rotary``) sits on the chamber that end empties. Off
    it changes nothing; engaged near the top of the swing the oil leaving chamber 2 must pass
    the needle, chamber 2's pressure rises and the arm stops short of the uncushioned top."""
    net, model, cands = vane
    assert {"cushion_max", "cushion_min"} <= set(cands)
    c = cands["cushion_max"]
    aug_net = c.build(net)
    cushion = next(n for n, k in aug_net.components.items() if k.type == "end_cushion_rotary")
    assert aug_net.components[cushion].ports["chamber"] == "chamber_2"
    aug = build_model(aug_net)
    base = _swing(model)
    th0 = base.Y[:, model.output_names.index("theta")]
    i2, j2 = model.output_names.index("P2"), aug.output_names.index("P2")
    off = _swing(aug)
    assert np.max(np.abs(off.Y[:, j2] - base.Y[:, i2])) < 5e3
    assert np.max(np.abs(off.Y[:, aug.output_names.index("theta")] - th0)) < 5e-5      # 0.003°
    x_end, length, needle = (p.name for p in c.params[:3])
    top = float(np.max(th0))
    on = _swing(aug, aug.param_vector({x_end: top + 0.02, length: 0.1, needle: 5e-10}))
    near = th0 > top - 0.05
    assert np.max(on.Y[near, j2] - base.Y[near, i2]) > 5e5
    assert np.max(on.Y[:, aug.output_names.index("theta")]) < top - 0.01
