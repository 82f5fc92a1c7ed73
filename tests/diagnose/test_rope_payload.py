"""An arm that swings in a vertical plane (its joint carries a weight) is offered its payload in
two forms: a mass on a flexible tip (the tangential spring–mass, in the arm's frame) and a bob on
a rope (``hanging_payload``, the exact pendulum, in gravity's frame); both are fitted once
either is shortlisted. A drum, which carries no weight, keeps the spring–mass alone."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from hydrocli.diagnose import augment as A
from hydrocli.diagnose.candidates import LAWS, Context
from hydrocli.diagnose.candidates import payload
from hydrocli.diagnose.shortlist import shortlist
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _payloads(machine: str, peaks=(), hanging: float | None = None):
    net = load_netlist(ROOT / "machines" / machine)
    if hanging is not None:
        net = A.set_values(net, {"gravity.theta0": hanging})
    ctx = Context(net, set(), {}, {}, {}, residual_peaks_hz=tuple(peaks))
    return net, [c for c in payload.PayloadFamily().candidates(ctx) if c.effect == "payload_swing"]


def test_an_arm_with_a_weight_is_offered_a_rope_beside_the_flexible_tip():
    net, cands = _payloads("rotary_drive.yaml", peaks=(0.7,), hanging=0.4)
    assert [c.key for c in cands] == ["payload_swing@vane", "payload_swing@vane#rope"]
    rope = cands[1]
    aug = rope.build(net)
    model = build_model(aug)
    el = next(n for n, d in aug.components.items() if d.type == "hanging_payload")
    assert {p.name for p in rope.params} == {f"{el}.{k}" for k in ("J_p", "L", "r", "c")} <= set(model.free_params)
    # it hangs where the arm's weight hangs, and starts as no payload (the spring–mass's start inertia)
    assert float(aug.components[el].params["theta0"].value) == pytest.approx(0.4)
    assert rope.params[0].start == cands[0].params[0].start
    # the rope's lengths are the swings tried: 1 m, 10 cm, 1.5 cm and the residual's 0.7 Hz, each a basin
    length = rope.params[1]
    swings = [math.sqrt(9.81 / x) / (2 * math.pi) for x in (length.start, *length.shapes)]
    assert swings == pytest.approx([0.498, 1.576, 4.070, 0.7], rel=1e-3) and length.basins
    # the arm's radius starts at twice the weight's lever g·J/W (J 0.8 kg·m², W 60 N·m)
    assert rope.params[2].start == pytest.approx(2 * 9.81 * 0.8 / 60.0)


def test_a_drum_keeps_the_spring_mass_alone():
    _, cands = _payloads("hoist_winch.yaml")
    assert [c.variant for c in cands] == [""]


def test_both_forms_of_a_payload_are_fitted_once_one_is_shortlisted():
    assert "payload_swing" in LAWS
    rows = (("lag", "measurement", "sensor_lag", 0.2), ("tip", "force", "payload_swing", 0.1),
            ("delay", "signal", "input_delay", 0.09), ("rope", "force", "payload_swing", 0.01))
    order = [SimpleNamespace(key=k, equation=eq, effect=eff) for k, eq, eff, _ in rows]
    scores = {k: {"dr2": v, "p_value": 1e-9} for k, _, _, v in rows}
    assert [c.key for c in shortlist(order, scores, 3)] == ["lag", "tip", "delay", "rope"]
