"""Every applicable candidate of the EHA test bench yields a machine that builds and
simulates, with its new parameters free; skipped effects carry a reason; every effect of
the vocabulary is covered by some family."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose.candidates import FAMILIES, VOCABULARY, Context, catalogue
from hydrocli.diagnose.measurement import with_pressure_sensors
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist, load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

MACHINE = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"


@pytest.fixture(scope="module")
def eha(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net, _ = with_pressure_sensors(load_netlist(MACHINE))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"piston": (0.04, 0.2)},
                  {"P1": "pressure", "P2": "pressure", "x": "position", "v": "velocity"})
    return net, ctx


def test_vocabulary_is_covered():
    covered = {e for f in FAMILIES for e in f.effects}
    assert covered == set(VOCABULARY)


def test_every_candidate_builds_and_simulates(eha):
    net, ctx = eha
    cands, skipped = catalogue(ctx)
    assert {s.effect for s in skipped} >= {"coulomb_friction", "viscous_friction"}   # already free in the base
    assert all(s.reason for s in skipped)
    effects = {c.effect for c in cands}
    assert {"valve_overlap", "pressure_dependent_friction", "input_delay", "sensor_lag", "load_compliance",
            "line_dynamics", "supply_pressure_drop", "entrained_air", "end_stop", "internal_leakage",
            "external_leakage", "valve_hysteresis", "valve_asymmetry", "structural_flexibility", "payload_swing"} <= effects
    leak = next(c for c in cands if c.effect == "internal_leakage")
    assert leak.params[0].name.endswith(".Kv")        # c_il is free already: a worn-seal orifice instead
    t = np.linspace(0, 0.3, 301)
    U = np.column_stack([0.1 * np.sin(2 * np.pi * 3 * t) * 100 / 100, np.full(t.size, 1e7), np.zeros(t.size)])
    for c in cands:
        aug = c.build(net)
        again = load_netlist_text(aug.text or "", str(MACHINE)) if aug.text else aug
        model = build_model(again)
        for p in c.params:
            assert p.name in model.free_params, (c.key, p.name)
        tr = simulate(model, InputTable(t, U), t, opts=SolverOptions(rtol=1e-5))
        assert np.all(np.isfinite(tr.Y)), c.key
