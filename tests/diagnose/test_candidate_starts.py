"""Acceptance and start details that decide whether an effect can be found at all."""
from __future__ import annotations

from hydrocli.components import registry
from hydrocli.diagnose import accept
from hydrocli.diagnose.candidates.base import NewParam
from hydrocli.diagnose.workers import _log_grid


def test_at_bound_is_judged_in_log_space_for_log_parameters():
    # 1e7 is far inside 1e5…1e10 on a log scale (a linear test would call it "at the bound")
    assert not accept._at_bound(1e7, (1e5, 1e10), True)
    assert accept._at_bound(1.001e5, (1e5, 1e10), True)
    assert accept._at_bound(1e7, (1e5, 1e10), False)


def test_starts_cover_the_plausible_range():
    k = NewParam("k", 1e9, (1e5, 1e10), (1e5, 5e8), 1e6, True)
    starts = [s["k"] for s in _log_grid([k])]
    assert len(starts) == 4 and min(starts) < 1e6 and max(starts) > 5e7
    overlap = NewParam("o", 0.0, (-0.05, 0.1), (5e-3, 0.1), 0.01)
    leak = NewParam("g", 1e-14, (1e-15, 1e-10), (1e-14, 1e-10), 1e-12, True, primary=False)
    grid = _log_grid([overlap, leak])
    assert all(5e-3 < s["o"] < 0.1 and s["g"] == 1e-14 for s in grid)
    gain = NewParam("g_BT", 1.0, (0.3, 3.0), (0.08, 2.0), 1.2, ref=1.0)
    assert _log_grid([gain]) == []
    # a range of many decades declares more starts; a joint grid takes the densest
    wide = NewParam("k", 1e9, (1e3, 1e10), (1e3, 5e8), 1e6, True, grid=7)
    assert len(_log_grid([wide])) == 7 and len(_log_grid([k, wide])) == 7


def test_edge_gain_valve_is_registered_with_four_gains():
    comp = registry.get("valve_4_3_edges")
    names = {p.name for p in comp.parameters}
    assert {"g_PA", "g_BT", "g_PB", "g_AT", "Kv", "Kv_neg_ratio", "overlap_PA"} <= names


def test_companion_shapes_cross_the_grid_of_amounts():
    """Each amount of the grid is tried with the companion at its start and at each of its
    typical shapes (the k-th shape of every companion together)."""
    l = NewParam("l", 0.05, (0.01, 20.0), (0.2, 20.0), 2.0, True)
    d = NewParam("d", 0.01, (0.004, 0.032), (0.004, 0.032), 0.01, True, primary=False, shapes=(0.006, 0.019))
    grid = _log_grid([l, d])
    assert len(grid) == 4 * 3
    assert {s["d"] for s in grid} == {0.01, 0.006, 0.019}
    assert len({s["l"] for s in grid}) == 4 and all(0.2 < s["l"] < 20.0 for s in grid)
    assert len(_log_grid([l])) == 4


def test_a_candidate_fit_also_starts_from_the_machine_as_drawn():
    """Starts are offered on the current fit's base parameters AND on the file's: a base fit
    that lacks a strong effect may have wandered far from the drawing (an inertia ×0.23) to
    imitate it; with the effect present the drawing is where the data are."""
    import numpy as np
    from types import SimpleNamespace
    from hydrocli.diagnose.workers import _fit_starts

    names = ["J", "air"]
    model = SimpleNamespace(param_index=names.index,
                            param_vector=lambda over, base: np.array([over.get(n, base[i]) for i, n in enumerate(names)]))
    truth = np.array([0.8, 0.2])
    obj = SimpleNamespace(cost=lambda q: float(np.sum((q - truth) ** 2) + (1.0 if q[0] < 0.5 else 0.0)))
    wandered, drawn = np.array([0.18, 0.0]), np.array([0.75, 0.0])
    starts = [{"air": 0.0}, {"air": 0.03}, {"air": 0.25}]
    out = _fit_starts(obj, wandered, model, starts, drawn)
    assert np.allclose(out[0], [0.75, 0.25])            # from the drawing, with the effect present
    # without the drawing only the wandered base is offered
    assert all(q[0] == 0.18 for q in _fit_starts(obj, wandered, model, starts))
    # effect off cheapest: the best start with the effect present is fitted too (as before)
    near = np.array([0.8, 0.0])
    obj_off = SimpleNamespace(cost=lambda q: float(q[1] ** 2 + (q[0] - 0.8) ** 2))
    out = _fit_starts(obj_off, near, model, starts, drawn)
    assert np.allclose(out[0], [0.8, 0.0]) and len(out) == 2 and out[1][1] > 0


def test_a_compliance_is_fitted_with_the_effect_present_from_each_base():
    """each_base: a compliance's mode is tuned by its stiffness AND the base's masses and
    volumes, so the best start with the effect present is fitted from the bent base fit and
    from the drawing alike — a single simulation's cost cannot say which basin holds the
    truth."""
    import numpy as np
    from types import SimpleNamespace
    from hydrocli.diagnose.workers import _fit_starts

    names = ["V", "l"]
    model = SimpleNamespace(param_index=names.index,
                            param_vector=lambda over, base: np.array([over.get(n, base[i]) for i, n in enumerate(names)]))
    bent, drawn = np.array([2.6, 0.05]), np.array([1.0, 0.05])
    # the bent base with the hose off is cheapest; with a hose, the bent base is cheaper than the drawing
    obj = SimpleNamespace(cost=lambda q: float((q[0] - 2.6) ** 2 + 0.1 * q[1] + (0.0 if q[0] > 2 else 0.5)))
    starts = [{"l": 0.05}, {"l": 2.0}, {"l": 6.0}]
    plain = _fit_starts(obj, bent, model, starts, drawn)
    assert len(plain) == 2 and all(q[0] == 2.6 for q in plain)      # off, and on — both from the bent base
    out = _fit_starts(obj, bent, model, starts, drawn, each_base=True)
    assert len(out) == 3 and all(np.allclose(a, b) for a, b in zip(out[:2], plain))
    assert np.allclose(out[2], [1.0, 2.0])                           # the drawing with the cheapest hose


def test_each_shape_of_a_basin_companion_is_fitted_from_its_best_start():
    """A companion whose shapes are basins of their own (a spring's mild or strong hardening,
    NewParam.basins): besides the cheapest start (here effect off) and the cheapest with the
    effect present, the cheapest start at EACH of its shapes is fitted: on held-out seed 49's
    EHA bushing both cheapest starts were near-rigid and went rigid, and the fit from the mild
    shape's cheapest start found the bushing."""
    import numpy as np
    from types import SimpleNamespace
    from hydrocli.diagnose.workers import _fit_starts

    names = ["k", "hc"]
    model = SimpleNamespace(param_index=names.index,
                            param_vector=lambda over, base: np.array([over.get(n, base[i]) for i, n in enumerate(names)]))
    # cost rises as the spring softens, the more so the harder it is at first: rigid is cheapest
    obj = SimpleNamespace(cost=lambda q: float(1.0 / q[0] + q[1]))
    base = np.array([1e9, 1e-6])
    starts = [{"k": 1e9, "hc": 1e-6}] + [{"k": k, "hc": hc} for hc in (1e-6, 1.0, 1e4) for k in (1e3, 1e5, 1e7)]
    plain = _fit_starts(obj, base, model, starts)
    assert len(plain) == 2 and plain[1][1] == 1e-6                  # rigid, and the cheapest soft linear one
    out = _fit_starts(obj, base, model, starts, basins={"hc": (1.0, 1e4)})
    assert len(out) == 4 and all(np.allclose(a, b) for a, b in zip(out[:2], plain))
    assert np.allclose(out[2], [1e7, 1.0]) and np.allclose(out[3], [1e7, 1e4])   # the best start of each shape
    # a shape already among the starts chosen is not fitted twice
    assert len(_fit_starts(obj, base, model, starts, basins={"hc": (1e-6,)})) == 2


def test_a_law_that_can_hold_the_bases_leak_starts_from_it():
    """NewParam.takes_over: a seal's resistance can hold what the base's shared leak
    conductance c_el holds (R = 1/c_el). The start is the base re-expressed in the seal law
    (each seal at 1/c_el, c_el back at 0); none when the base has no leak or the resistance
    would leave its bounds. It is fitted whatever it costs: a cheaper start that adds a little
    leak on top of the found c_el ends in the base's minimum (held-out seed 61's EHA)."""
    import numpy as np
    from types import SimpleNamespace
    from hydrocli.diagnose.workers import _fit_starts, _transfer_starts

    over = ("cyl.c_el", 0.0, -1.0)
    seals = [NewParam(f"seal_{i}.R", 1e16, (1e9, 1e17), (2e9, 2e14), 5e10, True, takes_over=over) for i in (1, 2)]
    names = ["cyl.c_el", "seal_1.R", "seal_2.R", "m"]
    model = SimpleNamespace(param_names=names, param_index=names.index,
                            param_vector=lambda o, base: np.array([o.get(n, base[i]) for i, n in enumerate(names)]))
    p = np.array([2e-13, 1e16, 1e16, 70.0])
    (start,) = _transfer_starts(seals, model, p)
    assert start == {"cyl.c_el": 0.0, "seal_1.R": 5e12, "seal_2.R": 5e12}
    assert _transfer_starts(seals, model, np.array([0.0, 1e16, 1e16, 70.0])) == []       # nothing found
    assert _transfer_starts(seals, model, np.array([1e-18, 1e16, 1e16, 70.0])) == []     # R 1e18 > bound
    plain = [NewParam("orifice.Kv", 0.0, (0.0, 1e-6), (1e-11, 1e-6), 1e-9, True)]
    assert _transfer_starts(plain, model, p) == []
    # fitted although dearer than the cheapest starts (off, and a little leak on top of c_el)
    obj = SimpleNamespace(cost=lambda q: float(q[0] * 1e13 + (1e16 - q[2]) * 1e-17))
    starts = [{"seal_1.R": 1e16, "seal_2.R": 1e16}, {"seal_1.R": 1e16, "seal_2.R": 3e15}]
    out = _fit_starts(obj, p, model, starts)
    assert len(out) == 2
    out = _fit_starts(obj, p, model, starts, transfers=[start])
    assert len(out) == 3 and np.allclose(out[2], [0.0, 5e12, 5e12, 70.0])


def test_a_soft_bumper_is_fitted_from_the_end_the_machine_presses():
    """A stop's soft-bumper stiffness is a basin of its own at EACH end: the cheapest soft
    start may press the end the machine only turns at (seed 64's vane), and from there the fit
    never meets the bumper (that fit ended at cost 0.354, the upper end's at 0.00069). Each
    end pressed alone at the soft shape is fitted."""
    import numpy as np
    from types import SimpleNamespace
    from hydrocli.diagnose.workers import _fit_starts, _one_end_probes

    lo = NewParam("lo", -1.2, (-1.5, -0.78), (-1.5, -0.78), -0.82, scale=1.0, seen=(-0.8, 0.5))
    hi = NewParam("hi", 0.7, (0.48, 1.0), (0.48, 1.0), 0.505, scale=1.0, seen=(-0.8, 0.5))
    k = NewParam("k", 1e8, (1.5e3, 1e11), (1.5e3, 1e11), 3e8, True, primary=False, shapes=(1.5e4,), basins=True)
    one_end = _one_end_probes([lo, hi, k])
    # each end alone, with the stiff probe and with the bumper
    assert one_end == [{"lo": -0.82, "hi": 0.7, "k": 3e8}, {"lo": -0.82, "hi": 0.7, "k": 1.5e4},
                       {"lo": -1.2, "hi": 0.505, "k": 3e8}, {"lo": -1.2, "hi": 0.505, "k": 1.5e4}]
    names = ["lo", "hi", "k"]
    model = SimpleNamespace(param_index=names.index,
                            param_vector=lambda over, base: np.array([over.get(n, base[i]) for i, n in enumerate(names)]))
    # off is cheapest; the stiff upper start next; the soft LOW start is cheaper than the soft upper one
    cost = {(-1.2, 0.7, 1e8): 0.17, (-0.82, 0.7, 3e8): 0.5, (-1.2, 0.505, 3e8): 0.3,
            (-0.82, 0.7, 1.5e4): 0.35, (-1.2, 0.505, 1.5e4): 1.2}
    obj = SimpleNamespace(cost=lambda q: cost[tuple(float(x) for x in q)])
    base = np.array([-1.2, 0.7, 1e8])
    starts = [{"lo": -1.2, "hi": 0.7, "k": 1e8}] + one_end
    stops = [{"name": "lo", "start": -1.2}, {"name": "hi", "start": 0.7}]
    basins = {"k": (1.5e4,)}
    without = _fit_starts(obj, base, model, starts, basins=basins)
    assert not any(np.allclose(q, [-1.2, 0.505, 1.5e4]) for q in without)      # the pressed end's bumper: never fitted
    out = _fit_starts(obj, base, model, starts, basins=basins, stops=stops)
    assert any(np.allclose(q, [-1.2, 0.505, 1.5e4]) for q in out)
    assert any(np.allclose(q, [-0.82, 0.7, 1.5e4]) for q in out)


def test_the_stop_candidate_damps_and_softens_in_the_actuators_own_units():
    """The stop's fixed contact damping is C_STOP_REF·(size/REF_SIZE)² (the same pressure per
    displaced flow), its soft-bumper start arrests the actuator's force at 100 bar over 1 %
    of the travel seen, and its contact may sit inside the recorded ends as far as the
    softest stop compresses: seed 004's cylinder keeps 1e4 N·s/m, a 20 cm³/rad vane gets
    0.9 N·m·s/rad, not 1e4 N·m·s/rad — 500 N·m at 0.05 rad/s, a wall."""
    from hydrocli.diagnose.candidates import catalogue
    from hydrocli.diagnose.candidates.base import Context
    from hydrocli.diagnose.candidates.leakage import REF_SIZE
    from hydrocli.netlist.loader import load_netlist
    from pathlib import Path
    import pytest
    root = Path(__file__).resolve().parents[2] / "machines"
    for file, node, size_name, span in (("rotary_drive.yaml", "arm_node", ("vane", "D_v"), 1.0),
                                        ("eha_testbench.yaml", None, ("cylinder", "A"), 0.1)):
        net = load_netlist(root / file)
        if node is None:
            node = net.components["cylinder"].ports["rod"]
        cands, _ = catalogue(Context(net, set(), {node: (-span / 2, span / 2)}, {}, {}))
        stop = next(c for c in cands if c.effect == "end_stop" and not c.variant)     # the stops, not a cushion
        size = net.components[size_name[0]].params[size_name[1]].value
        (c_name, c_value), = stop.fixed.items()
        assert c_name.endswith("c_stop") and c_value == pytest.approx(1e4 * (size / REF_SIZE) ** 2)
        k = next(p for p in stop.params if p.name.endswith("k_stop"))
        assert k.basins and k.shapes == pytest.approx((size * 1e7 / (0.01 * span),))
        assert k.bounds[0] < k.shapes[0] < k.start
        # a contact may sit inside the recorded end by the softest stop's compression (a tenth
        # of the travel): dev seed 64's EHA bumper, 2.4 % inside, was cut at the old 2 %
        hi = next(p for p in stop.params if p.name.endswith("_max"))
        assert hi.bounds[0] == pytest.approx(span / 2 - 0.1 * span) and hi.plausible == hi.bounds
        assert k.bounds[0] == pytest.approx(min(1e5, size * 1e7 / (0.1 * span)))
