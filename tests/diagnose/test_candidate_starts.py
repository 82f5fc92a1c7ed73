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
