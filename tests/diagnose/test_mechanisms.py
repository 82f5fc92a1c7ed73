"""Fast unit tests of the diagnosis mechanisms: roles (matching by role, not type name),
nuisance spool dynamics, base-fit findings, the unexplained-mismatch verdict, strict JSON."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hydrocli.components import registry
from hydrocli.components import roles as R
from hydrocli.diagnose import findings, nuisance
from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.measurement import with_pressure_sensors
from hydrocli.diagnose.summary import write_json
from hydrocli.diagnose.workers import _log_grid
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist, load_netlist_text

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "identify"))
from synth import LAG  # noqa: E402  (two first-order lags in series, k and tau free)

ROOT = Path(__file__).resolve().parents[2]


def test_every_role_slot_names_a_real_port_and_parameter():
    """A role is data about the spec: each slot must point at the type's own ports/params."""
    n = 0
    for t, cls in registry.all_types().items():
        for role in cls.roles:
            for slot, port in role.ports:
                assert cls.port(port) is not None, f"{t}: role {role.name} slot {slot} → unknown port {port}"
            for slot, names in role.params:
                for p in names:
                    assert cls.param(p) is not None, f"{t}: role {role.name} slot {slot} → unknown parameter {p}"
            n += 1
    assert n >= 15


def test_actuators_of_both_domains_offer_the_actuator_role():
    acts = registry.offering(R.ACTUATOR)
    domains = {cls.port(cls.role(R.ACTUATOR).port("motion")).domain.value for cls in acts.values()}
    assert {"cylinder", "vane_actuator", "hydraulic_motor"} <= set(acts)
    assert domains == {"translational", "rotational"}


ROTARY = """
name: vane_pendulum
fluid: {beta: "1.5 GPa", p_tank: "1 bar"}
inputs: {u: {unit: "1"}}
components:
  supply: {type: pressure_source, ports: {P: sup}, p: "100 bar"}
  tank: {type: tank, ports: {T: ret}}
  valve: {type: valve_4_3, ports: {P: sup, T: ret, A: c1, B: c2, cmd: u}, Kv: 2.0e-8}
  vane: {type: vane_actuator, ports: {A: c1, B: c2, shaft: arm, body: ground}, D_v: 5.0e-6}
  arm_inertia: {type: inertia, ports: {r: arm}, J: 0.05}
  weight: {type: gravity_load, ports: {r: arm}, W: 5.0}
outputs: {p1: c1.p, p2: c2.p, angle: arm.theta}
initial: {c1.p: "50 bar", c2.p: "50 bar"}
"""


def test_rotary_drive_gets_candidates_by_role(tmp_path):
    """A vane actuator on an inertia (no cylinder, no type-name match) gets leakage, air,
    friction, compliance and mount candidates built from rotational elements."""
    net = load_netlist_text(ROTARY, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {"arm.theta": (-0.5, 0.5)}, {"p1": "pressure", "angle": "angle"}, {"u": 0.0})
    cands, skipped = catalogue(ctx)
    effects = {c.effect for c in cands}
    assert {"internal_leakage", "external_leakage", "entrained_air", "coulomb_friction", "viscous_friction",
            "load_compliance", "structural_flexibility", "valve_overlap", "input_delay"} <= effects
    comp = next(c for c in cands if c.effect == "load_compliance")
    aug = comp.build(net)
    types = {d.type for d in aug.components.values()}
    assert {"shaft", "rotary_damper"} <= types and "spring" not in types
    fr = next(c for c in cands if c.effect == "coulomb_friction")
    assert "rotary_friction" in {d.type for d in fr.build(net).components.values()}
    # the augmented machines are valid netlists that build
    from hydrocli.model.builder import build_model
    for c in cands:
        if c.effect in ("load_compliance", "internal_leakage", "entrained_air"):
            m = build_model(c.build(net))
            assert set(p.name for p in c.params) <= set(m.free_params)


def test_nuisance_frees_fixed_spool_dynamics_within_30_percent():
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    found = {n.name: n for n in nuisance.valve_dynamics(net, set())}
    assert set(found) == {"valve.tau", "valve.s_max"}
    tau = found["valve.tau"]
    assert tau.file_value == pytest.approx(4e-3)
    assert tau.bounds[0] == pytest.approx(4e-3 / 1.43) and tau.bounds[1] == pytest.approx(4e-3 * 1.43)
    assert "valve.tau" not in {n.name for n in nuisance.valve_dynamics(net, {"valve.tau"})}
    net2, _ = nuisance.with_nuisance(net, set())
    assert net2.components["valve"].params["tau"].free


def _row(name, value, initial, stderr):
    return {"name": name, "value": value, "initial": initial, "stderr": stderr}


def test_base_fit_finding_needs_plausible_determined_and_needed():
    offs = {"cyl.c_el": findings.OffValue("external_leakage", "cyl", 0.0, (1e-13, 5e-10), True)}
    big = lambda names: (5.0, 1.0)      # switching it off costs 5 % ESR, band 1 %
    small = lambda names: (0.5, 1.0)
    good = [_row("cyl.c_el", 2.9e-12, 0.0, 1e-13)]
    f = findings.base_fit_findings(good, offs, big)
    assert [x["effect"] for x in f] == ["external_leakage"] and f[0]["source"] == "base_fit"
    assert findings.base_fit_findings(good, offs, small) == []                       # not needed by the data
    assert findings.base_fit_findings([_row("cyl.c_el", 2.9e-12, 0.0, 2e-12)], offs, big) == []  # ± too large
    assert findings.base_fit_findings([_row("cyl.c_el", 1e-15, 0.0, 1e-17)], offs, big) == []    # negligible
    assert findings.base_fit_findings([_row("cyl.c_el", 2.9e-12, 1e-12, 1e-13)], offs, big) == []  # not from "off"


def test_a_declared_parameter_needs_no_look_elsewhere_margin():
    """A candidate picked as the best of the catalogue must gain more than the noise floor on
    held-out data; a parameter the file itself frees from "off" was not picked, so it must only
    account for MIN_REL of the error above the floor (an external leak the base fit resolved
    at 200 σ, worth 0.5 % held-out ESR beside a 0.64 % floor, was answered a bare `none`)."""
    from hydrocli.diagnose import accept
    val_off, floor = 1.7, 0.64
    assert accept.need(val_off, floor) == pytest.approx(accept.LOOK_ELSEWHERE * floor)
    declared = accept.need(val_off, floor, selected=False)
    assert declared == pytest.approx(accept.MIN_REL * (val_off - floor))
    assert declared < accept.need(val_off, floor)
    assert accept.need(0.5, floor, selected=False) == 0.0    # nothing above the floor: any real gain
    assert accept.need(0.5, floor) == pytest.approx(accept.LOOK_ELSEWHERE * floor)  # a selection: margin


def test_unexplained_mismatch_when_error_stays_above_noise():
    loc = {"regimes": [{"regime": "direction reversal", "concentration": 2.0}], "windows": [{"t0": 1, "t1": 2}]}
    assert findings.unexplained({"P1": 0.3, "v": 0.1}, {"P1": 0.15, "v": 0.05}, loc) is None
    u = findings.unexplained({"P1": 0.3, "v": 2.4}, {"P1": 0.15, "v": 0.05}, loc)
    assert list(u["outputs"]) == ["v"] and u["regimes"][0]["regime"] == "direction reversal"
    # an output whose noise floor is itself large needs an excess beyond that floor
    assert findings.unexplained({"P1": 3.0}, {"P1": 2.5}, loc) is None


def test_diagnosis_json_is_strict(tmp_path):
    diag = SimpleNamespace(data={"a": float("nan"), "b": [1.0, float("inf")], "c": {"d": -math.inf}})
    write_json(diag, tmp_path / "d.json")
    text = (tmp_path / "d.json").read_text()
    assert json.loads(text) == {"a": None, "b": [1.0, None], "c": {"d": None}}
    assert "NaN" not in text and "Infinity" not in text


def test_discriminating_design_separates_two_models_and_loads(tmp_path):
    """Two EHA models that differ only in the oil stiffness: the chosen design predicts a
    difference many σ large in a pressure or motion output, and its YAML loads as a designed
    experiment. Identical models predict no difference on any design (discrimination 0)."""
    from hydrocli.diagnose import design
    from hydrocli.experiments.experiment_file import load_experiment_file, load_all
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    model = build_model(net)
    train = load_all(ROOT / "experiments" / "quickstart" / "train.yaml", model)
    assert design.command_inputs(net) == {"u"}
    ds = design.designs(model, net, train)
    assert any(d.name.startswith("ramp_") for d in ds) and any(d.name.startswith("sine_") for d in ds)
    p = model.p0
    q = p.copy()
    q[model.param_index("fluid.beta" if "fluid.beta" in model.param_names else "cylinder.beta")] *= 0.3
    sigma = {"P1": 1.5e4, "P2": 1.5e4, "v": 1e-3}
    same = design.propose(("a", model, p), ("b", model, p), net, train, sigma, tmp_path / "w1", "eha")
    assert same["discrimination"] == pytest.approx(0.0, abs=1e-9)
    best = design.propose(("a", model, p), ("b", model, q), net, train, sigma, tmp_path / "w2", "eha")
    assert best["discrimination"] > 0 and max(best["z"].values()) > 3.0
    path = tmp_path / "proposed.yaml"
    path.write_text(best["text"])
    e = load_experiment_file(path, model)
    assert e.t_out[-1] == pytest.approx(design.DURATION, rel=1e-3)


def test_shortlist_adds_the_best_competing_candidate_of_each_other_balance():
    from hydrocli.diagnose.shortlist import shortlist
    C = lambda key, eq: SimpleNamespace(key=key, equation=eq, effect=key)
    order = [C("mount", "force"), C("hyst", "valve"), C("lag", "measurement"), C("delay", "signal"),
             C("air", "continuity"), C("leak", "continuity"), C("stop", "force")]
    dr2 = {"mount": 0.41, "hyst": 0.32, "lag": 0.30, "delay": 0.09, "air": 0.20, "leak": 0.19, "stop": 0.3}
    scores = {k: {"dr2": v, "p_value": 1e-9} for k, v in dr2.items()}
    keys = [c.key for c in shortlist(order, scores, 3)]
    assert keys == ["mount", "hyst", "lag", "air"]   # air competes (≥ 1/3 of the top), delay does not
    # two forms of one effect do not crowd out another effect
    forms = [C("edges", "valve"), C("ratio", "valve"), C("ext", "continuity"), C("int", "continuity")]
    for c, e in zip(forms, ("asym", "asym", "ext", "int")):
        c.effect = e
    sc = {k: {"dr2": v, "p_value": 1e-9} for k, v in {"edges": 0.84, "ratio": 0.83, "ext": 0.77, "int": 0.45}.items()}
    assert [c.key for c in shortlist(forms, sc, 3)] == ["edges", "ext", "int"]
    scores["air"]["p_value"] = 0.2                    # not significant: not fitted
    assert [c.key for c in shortlist(order, scores, 3)] == ["mount", "hyst", "lag", "leak"]


def test_a_failed_law_leaves_the_effects_other_laws_for_the_next_wave():
    """engine waves: a fitted effect is done, unless it is offered in several laws (an end stop:
    a plain stop or a cushion at either end) — then only the law fitted is."""
    from hydrocli.diagnose.candidates import LAWS
    from hydrocli.diagnose.shortlist import after_wave
    assert "end_stop" in LAWS and "valve_overlap" not in LAWS
    order, _ = _screened(("cushion_min", "force", "end_stop", 0.5), ("lap", "valve", "valve_overlap", 0.3),
                         ("lap2", "valve", "valve_overlap", 0.25), ("cushion_max", "force", "end_stop", 0.2),
                         ("stop", "force", "end_stop", 0.12), ("air", "continuity", "entrained_air", 0.1))
    assert [c.key for c in after_wave(order, {"cushion_min", "lap"})] == ["cushion_max", "stop", "air"]
    assert [c.key for c in after_wave(order, set())] == [c.key for c in order]


def test_a_findings_readings_are_fitted_whatever_they_screen():
    """Grown chamber volumes on trial leave the residual at the noise: air and a hose screen
    0.0 %, not significant. Both readings are fitted all the same (readings=...), once each, and
    do not take the places of the best-screening effects (dev rotary: air and a distributed hose
    alike were left to the finding's default name)."""
    from hydrocli.diagnose.shortlist import shortlist
    order, scores = _screened(
        ("lag", "measurement", "sensor_lag", 0.001), ("delay", "signal", "input_delay", 0.001),
        ("hyst", "valve", "valve_hysteresis", 0.0005), ("line", "continuity", "line_dynamics", 0.0),
        ("air", "continuity", "entrained_air", 0.0))
    for k in ("line", "air"):
        scores[k]["p_value"] = 0.9
    assert [c.key for c in shortlist(order, scores, 3)] == ["lag", "delay", "hyst"]
    keys = [c.key for c in shortlist(order, scores, 3, frozenset({"entrained_air", "line_dynamics"}))]
    assert sorted(keys) == ["air", "delay", "hyst", "lag", "line"] and len(keys) == len(set(keys))
    assert [c.key for c in shortlist(order[:3], scores, 3, frozenset({"entrained_air"}))] == ["lag", "delay", "hyst"]


def _screened(*rows):
    """Candidates in screening order and their scores, from (key, balance, effect, explained)
    rows, every score test significant."""
    order = [SimpleNamespace(key=k, equation=eq, effect=eff) for k, eq, eff, _ in rows]
    return order, {k: {"dr2": dr2, "p_value": 1e-9} for k, _, _, dr2 in rows}


def test_once_a_compliance_is_shortlisted_every_significant_other_compliance_is_fitted():
    from hydrocli.diagnose.shortlist import shortlist
    order, scores = _screened(
        ("lag", "measurement", "sensor_lag", 0.13), ("delay", "signal", "input_delay", 0.12),
        ("mount", "force", "structural_flexibility", 0.061), ("link", "force", "load_compliance", 0.029),
        ("air", "continuity", "entrained_air", 0.019), ("hose", "continuity", "line_dynamics", 0.016))
    assert [c.key for c in shortlist(order, scores, 3)] == ["lag", "delay", "mount", "link", "air", "hose"]
    scores["hose"]["p_value"] = 0.2                   # not significant: not fitted
    assert "hose" not in [c.key for c in shortlist(order, scores, 3)]
    # no compliance among the best: none is added
    assert [c.key for c in shortlist(order[:2] + order[3:], scores, 2)] == ["lag", "delay"]


def test_once_air_is_shortlisted_every_significant_air_law_is_fitted():
    """Air's three laws (a fixed fraction, a pocket per chamber, free air dissolving during the
    record) are laws of one continuity term: the score test, a secant at one value, ranked the
    dissolving law below the fixed fraction that stands in for it (dev EHA, seed 142: 20.6 %
    against 17.4 %; unfitted, the fraction was named imprecise beside a leak found by the base
    fit). Once one air law is in, every significant other law is fitted; a law that is not
    significant is not, and a failed law leaves the others for the next wave."""
    from hydrocli.diagnose.candidates import LAWS
    from hydrocli.diagnose.shortlist import after_wave, shortlist
    assert "entrained_air" in LAWS
    order, scores = _screened(
        ("air", "continuity", "entrained_air", 0.206), ("overlap", "valve", "valve_overlap", 0.045),
        ("relief", "continuity", "external_leakage", 0.038), ("dissolving", "continuity", "entrained_air", 0.174),
        ("pocket", "continuity", "entrained_air", 0.048), ("hose", "valve", "line_dynamics", 0.004))
    scores["hose"]["p_value"] = 0.2
    keys = [c.key for c in shortlist(order, scores, 3)]
    assert keys[:3] == ["air", "overlap", "relief"] and {"dissolving", "pocket"} <= set(keys)
    scores["pocket"]["p_value"] = 0.2                 # not significant: not fitted
    assert "pocket" not in [c.key for c in shortlist(order, scores, 3)]
    assert [c.key for c in after_wave(order, {"air", "overlap"})] == ["relief", "dissolving", "pocket", "hose"]


def test_once_a_lag_is_shortlisted_every_significant_other_lag_is_fitted():
    """A delay, a valve play and a slow transducer all retard the response; a score at one
    probe value ranks them poorly (dev EHA Dahl hysteresis: the delay screened 21 %, the play
    was not fitted). Once one is in, the others that are significant are fitted too."""
    from hydrocli.diagnose.shortlist import shortlist
    order, scores = _screened(
        ("delay", "signal", "input_delay", 0.21), ("mount", "force", "structural_flexibility", 0.042),
        ("leak", "continuity", "internal_leakage", 0.03), ("overlap", "valve", "valve_overlap", 0.02),
        ("play", "valve", "valve_hysteresis", 0.011), ("lag", "measurement", "sensor_lag", 0.01))
    # the play and the slow reading join the delay (the mount's compliance group is alone), and
    # the play brings its fellow dead band, the overlap
    assert [c.key for c in shortlist(order, scores, 3)] == ["delay", "mount", "leak", "play", "lag", "overlap"]
    scores["play"]["p_value"] = 0.2                   # not significant: not fitted
    assert [c.key for c in shortlist(order, scores, 3)] == ["delay", "mount", "leak", "lag"]
    # no lag among the best: none is added (the overlap joins as the valve balance's rival, and
    # the play, significant again, as the overlap's fellow dead band)
    scores["play"]["p_value"] = 1e-9
    assert [c.key for c in shortlist(order[1:], scores, 2)] == ["mount", "leak", "overlap", "play"]
    assert [c.key for c in shortlist(order[1:3] + order[5:], scores, 2)] == ["mount", "leak"]


def test_effect_traits_are_declared_by_the_family_that_models_the_effect():
    """Issue 11: the engine reads which effects switch and which are compliances from the
    families (a new candidate module declares its own), never from a list of names of its own."""
    import hydrocli.diagnose.engine as engine
    import hydrocli.diagnose.shortlist as shortlist
    from hydrocli.diagnose.candidates import BANDS, COMPLIANCES, FAMILIES, LAGS, SWITCHING, VOCABULARY
    for f in FAMILIES:
        assert f.switching | f.compliances | f.lags | f.bands <= set(f.effects), type(f).__name__
        assert set(f.effects) <= set(VOCABULARY), type(f).__name__
    assert engine.SWITCHING is SWITCHING and engine.COMPLIANCES is COMPLIANCES
    # the four ways a machine gets softer than its file: air, a hose, a rod-load link, a mount;
    # and a payload on a rope, whose mode moves with its stiffness as theirs do
    assert {"entrained_air", "line_dynamics", "load_compliance", "structural_flexibility", "payload_swing"} == COMPLIANCES
    assert not COMPLIANCES & SWITCHING
    # the three ways a response is retarded without a new compliance: a delay, a play, a slow reading
    assert shortlist.LAGS is LAGS and {"input_delay", "valve_hysteresis", "sensor_lag"} == LAGS
    assert not LAGS & COMPLIANCES
    # a spool's two dead bands: around centre (overlap) and around the last reversal (play)
    assert shortlist.BANDS is BANDS and {"valve_overlap", "valve_hysteresis"} == BANDS


def test_a_rod_load_link_starts_at_rest_under_its_load_and_carries_joint_friction():
    """The load_compliance candidate on the lift (a 1.5 t load hanging on the rod): the rod
    starts where the measured load starts, the link's spring carries the weight at t = 0
    (balance rule), and the joint's dry friction is a companion starting at 0."""
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.experiments.initial import initial_state
    from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
    net = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    model0 = build_model(net)
    ctx = Context(net, set(model0.free_params))
    cands, _ = catalogue(ctx)
    c = next(c for c in cands if c.effect == "load_compliance")
    friction = [p for p in c.params if "joint_friction" in p.name]
    assert friction and all(p.start == 0 and not p.primary for p in friction)
    aug = c.build(net)
    model = build_model(aug)
    kinds = {(r.state, r.kind) for r in model.initial_rules}
    assert ("rod.x", "same_as") in kinds and ("cylinder_coupling.dF", "balance") in kinds
    p = model.param_vector({"cylinder_coupling.k": 2.0e6})          # a soft link: 7 Hz under 1.5 t
    t = np.arange(0.0, 0.3, 1e-3)
    u = np.zeros((1, len(model.input_names)))
    u[0, model.input_names.index("Ps")] = 1.6e7
    e = Experiment("rest", "rest.csv", InputTable(np.array([0.0]), u), t, measured={"x": np.full(t.size, 0.2)})
    x0 = initial_state(model, e, p)
    assert x0[model.state_index("rod.x")] == pytest.approx(0.2)
    tr = simulate(model, e.inputs, t, p=p, x0=x0, opts=SolverOptions(rtol=1e-7))
    x = tr.Y[:, model.output_names.index("x")]
    weight = -float(model.p0[model.param_index("load.F_const")])
    # a relaxed link would drop the load by up to 2·W/k = 14 mm; balanced, it moves only as
    # the closed valve's chambers settle (well under a millimetre)
    assert 2 * weight / 2.0e6 > 0.01
    assert np.abs(x - 0.2).max() < 1e-3


def test_a_joint_with_play_starts_in_contact_under_its_load():
    """The clearance law of the rod–load link on the lift (1.5 t hanging on the rod, a 3 mm
    play): the balance rule puts the joint in contact on the side the weight pulls, carrying
    it at t = 0 (from the middle of the play the load would fall 1.5 mm, then ring); the play
    is the primary, the contact's stiffness a companion started rigid."""
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.experiments.initial import initial_state
    from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
    net = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    model0 = build_model(net)
    cands, _ = catalogue(Context(net, set(model0.free_params)))
    c = next(c for c in cands if c.key == "load_compliance@cylinder#clearance")
    # a law of the rod–load link beside the spring–damper: a failed spring leaves it to be fitted
    from hydrocli.diagnose.candidates import LAWS
    assert "load_compliance" in LAWS and "load_compliance@cylinder" in {c.key for c in cands}
    assert c.params[0].name == "cylinder_clearance.b" and c.params[0].primary
    assert not c.params[1].primary and c.params[1].start >= 1e9
    model = build_model(c.build(net))
    assert ("cylinder_clearance.d", "balance") in {(r.state, r.kind) for r in model.initial_rules}
    gap, k = 3e-3, 2.0e6
    p = model.param_vector({"cylinder_clearance.b": gap, "cylinder_clearance.k": k})
    t = np.arange(0.0, 0.3, 1e-3)
    u = np.zeros((1, len(model.input_names)))
    u[0, model.input_names.index("Ps")] = 1.6e7
    e = Experiment("rest", "rest.csv", InputTable(np.array([0.0]), u), t, measured={"x": np.full(t.size, 0.2)})
    x0 = initial_state(model, e, p)
    weight = -float(model.p0[model.param_index("load.F_const")])
    d0 = x0[model.state_index("cylinder_clearance.d")]
    # in contact: half the play plus the contact's deflection under the weight
    assert abs(d0) == pytest.approx(0.5 * gap + weight / k, rel=0.02)
    tr = simulate(model, e.inputs, t, p=p, x0=x0, opts=SolverOptions(rtol=1e-7))
    x = tr.Y[:, model.output_names.index("x")]
    assert np.abs(x - 0.2).max() < 1e-3


def test_rotary_payload_candidate_is_a_new_module_found_by_the_catalogue(tmp_path):
    """Issue 11: a new candidate is one module (candidates/payload.py) the catalogue discovers.
    On a vane drive it adds a swinging inertia J_p on a torsion 'rope' k = J_p·g/L to the arm:
    the swing's natural frequency at the start values is √(g/L) for L = 1 m."""
    from hydrocli.diagnose.candidates import FAMILIES
    from hydrocli.diagnose.candidates import payload
    from hydrocli.model.builder import build_model
    assert any(isinstance(f, payload.PayloadFamily) for f in FAMILIES)
    net = load_netlist_text(ROTARY, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {}, {"p1": "pressure"}, {"u": 0.0})
    cands, _ = catalogue(ctx)
    c = next(c for c in cands if c.effect == "payload_swing")
    aug = c.build(net)
    m = build_model(aug)
    assert {p.name for p in c.params} <= set(m.free_params)
    jp, k = (aug.components[n.split(".")[0]].params[n.split(".")[1]].value for n in (c.params[0].name, c.params[1].name))
    assert math.sqrt(k / jp) == pytest.approx(math.sqrt(9.81 / payload.L_START))
    types = {d.type for d in aug.components.values()}
    assert {"inertia", "shaft", "rotary_damper"} <= types
    # the swing loses energy (a damper at 5 % of critical) and is tried at three frequencies,
    # 0.5, 1.6 and 4 Hz (rope lengths 1 m, 10 cm, 1.5 cm), each a basin of its own
    jprobe, kp, cp = c.params[0].probe, c.params[1], c.params[2]
    assert cp.primary is False and cp.probe == pytest.approx(2 * 0.05 * math.sqrt(kp.probe * jprobe))
    freqs = [math.sqrt(k / jprobe) / (2 * math.pi) for k in (kp.probe, *kp.shapes)]
    assert freqs == pytest.approx([0.498, 1.576, 4.070], rel=1e-3) and kp.basins
    for k, c_ in zip(kp.shapes, cp.shapes):
        assert c_ == pytest.approx(2 * 0.05 * math.sqrt(k * jprobe))


def test_a_cylinders_payload_rings_on_its_rope_at_its_own_frequency():
    """Session 40: a load hanging on a rope under a lifting cylinder is the same identified
    spring–mass–damper as the vane's swing (until then a cylinder's rope was fixed at 0.5 Hz,
    undamped and unidentified). Closed form: with the valve shut the held load is ~50× stiffer
    than the rope, so a payload m_p on a rope k, released 2 mm off its rest, rings at
    √(k/m_p)/2π and decays at ζ = c/(2√(k·m_p)); the load barely moves."""
    from hydrocli.diagnose import augment as A
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.experiments.initial import initial_state
    from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
    net = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    ctx = Context(net, set(build_model(net).free_params), residual_peaks_hz=(1.22, 45.0))
    c = next(c for c in catalogue(ctx)[0] if c.effect == "payload_swing")
    names = [q.name for q in c.params]
    # the mass, the rope, its damping, and the sheaves' dry friction (both directions), unused at
    # the start; no winding on a cylinder
    assert [q.name.split(".")[1] for q in c.params] == ["m", "k", "c", "kc_p", "kc_m"] and c.component == "cylinder"
    assert all(q.start == 0 and not q.primary for q in c.params[3:])
    names = names[:3]
    jprobe, kp = c.params[0].probe, c.params[1]
    freqs = [math.sqrt(k / jprobe) / (2 * math.pi) for k in kp.shapes]
    assert freqs == pytest.approx([1.576, 4.070, 1.22], rel=1e-3)      # 45 Hz is no rope's bounce
    # a hook load a third of the load bouncing at 25 Hz on a short stiff rope is within reach
    assert kp.bounds[1] > 0.3 * 1500.0 * (2 * math.pi * 25.0) ** 2
    # what hangs may weigh what the file lets the load weigh (load.m free up to 4 t), though a
    # base fit without it lowers the rigid load (a 1.3 t hook load left 500 kg on the rod)
    assert c.params[0].bounds[1] == pytest.approx(2 * 4000.0)
    fixed = Context(net, set(build_model(net).free_params) - {"load.m"})
    assert next(c for c in catalogue(fixed)[0] if c.effect == "payload_swing").params[0].bounds[1] == pytest.approx(3000.0)
    mp, k, cd = 500.0, 5.0e4, 2 * 0.02 * math.sqrt(5.0e4 * 500.0)          # 1.59 Hz, ζ = 2 %
    aug = c.build(net)
    rope = names[1].split(".")[0]
    aug = A.set_initial(aug, {f"{rope}.dF": 2e-3 * k})
    model = build_model(aug)
    p = model.param_vector(dict(zip(names, (mp, k, cd))))
    t = np.arange(0.0, 4.0, 1e-3)
    u = np.zeros((1, len(model.input_names)))
    u[0, model.input_names.index("Ps")] = 1.6e7
    e = Experiment("rest", "rest.csv", InputTable(np.array([0.0]), u), t, measured={"x": np.full(t.size, 0.2)})
    tr = simulate(model, e.inputs, t, p=p, x0=initial_state(model, e, p), opts=SolverOptions(rtol=1e-8))
    F = tr.X[:, model.state_index(f"{rope}.dF")]
    up = np.flatnonzero((F[:-1] < 0) & (F[1:] >= 0))
    tz = t[up] - F[up] / (F[up + 1] - F[up]) * 1e-3
    f_w = math.sqrt(k / mp) / (2 * math.pi)
    assert 1.0 / np.mean(np.diff(tz)) == pytest.approx(f_w * math.sqrt(1 - 0.02 ** 2), rel=0.005)
    peaks = [np.abs(F[a:b]).max() for a, b in zip(up[:-1], up[1:])]
    zeta = math.log(peaks[0] / peaks[-1]) / (2 * math.pi * (len(peaks) - 1))
    assert zeta == pytest.approx(0.02, rel=0.05)
    x = tr.Y[:, model.output_names.index("x")]
    assert np.abs(x - x[0]).max() < 0.05 * 2e-3


def test_a_hook_load_on_a_winch_hangs_on_the_rope_its_drum_pays_out():
    """Session 43: on a motor (no ends of travel: it turns a drum) the payload's rope winds on
    the drum, its stiffness EA/L with L = L₀·(1 − wind·θ) (``shaft.wind``, a signed companion
    started at 0); the rope's sheaves carry dry friction. A vane (stops at its ends) keeps a
    rope of fixed length. Closed form on the augmented winch: the rope's stiffness at the
    drum angle θ is k/(1 − wind·θ), read from the model's equations."""
    net = load_netlist(ROOT / "machines" / "hoist_winch.yaml")
    ctx = Context(net, set(build_model(net).free_params))
    c = next(c for c in catalogue(ctx)[0] if c.effect == "payload_swing")
    by = {q.name.split(".")[1]: q for q in c.params}
    wind = by["wind"]
    assert wind.start == 0 and wind.bounds == (-0.5, 0.5) and not wind.primary and not wind.log
    assert by["tau_c"].start == 0 and not by["tau_c"].primary          # the sheaves' dry friction
    model = build_model(c.build(net))
    assert {q.name for q in c.params} <= set(model.free_params)
    rope = wind.name.split(".")[0]
    k, w, th, w_drum = 6.0e4, 0.025, 8.0, 0.3      # the drum 8 rad in, hoisting at 0.3 rad/s
    p = model.param_vector({f"{rope}.k": k, wind.name: w})
    x = np.zeros(len(model.state_names))
    x[model.state_index("drum_node.theta")] = th
    x[model.state_index("drum_node.w")] = w_drum
    x[model.state_index("chamber_1.p")] = x[model.state_index("chamber_2.p")] = 5e6
    u = [0.0 if n == "u" else 1.6e7 for n in model.input_names]
    dx, *_ = model.numpy_evaluate()(0.0, list(x), p, u)
    # the payload at rest: the rope's torque grows at k/(1 − wind·θ) × the drum's speed
    assert dx[model.state_index(f"{rope}.tau_k")] == pytest.approx(k / (1 - w * th) * w_drum, rel=1e-9)
    vane = Context(load_netlist(ROOT / "machines" / "rotary_drive.yaml"), set())
    cv = next(c for c in catalogue(vane)[0] if c.effect == "payload_swing")
    assert not any(q.name.endswith(".wind") for q in cv.params)


def test_a_swing_the_residual_shows_is_a_start_of_the_payload_candidate(tmp_path):
    """A lightly damped mode the model lacks leaves its frequency as the residual spectrum's
    peak (held-out seed 76's vane pendulum: a rope payload at 0.70 Hz, P1's residual peaks at
    0.73 Hz; started at 0.5 Hz the fit found a 15 Hz spring). The residual's peaks, merged
    within 10 %, are starts of the swing's frequency; peaks outside the swings of a 50 m rope
    and the bounces of a stiff one (0.07–30 Hz) are not."""
    from hydrocli.diagnose import locate
    located = {"spectrum": {"P1": {"peak_hz": 0.73}, "P2": {"peak_hz": 0.75}, "w": {"peak_hz": 45.0},
                            "theta": {"peak_hz": 0.0}}}
    assert locate.residual_peaks(located) == pytest.approx((0.73, 45.0))
    assert locate.residual_peaks({}) == ()
    net = load_netlist_text(ROTARY, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {}, {"p1": "pressure"}, {"u": 0.0}, residual_peaks_hz=locate.residual_peaks(located))
    c = next(c for c in catalogue(ctx)[0] if c.effect == "payload_swing")
    jprobe, kp, cp = c.params[0].probe, c.params[1], c.params[2]
    freqs = [math.sqrt(k / jprobe) / (2 * math.pi) for k in kp.shapes]
    assert freqs == pytest.approx([1.576, 4.070, 0.73], rel=1e-3)          # 45 Hz is no rope's swing
    assert len(cp.shapes) == len(kp.shapes) and cp.shapes[-1] == pytest.approx(2 * 0.05 * math.sqrt(kp.shapes[-1] * jprobe))


def test_actuator_areas_are_nuisance_within_their_tolerance():
    """Every actuator's fixed areas (displacements, by role) are freed within ±3 %."""
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    found = {n.name: n for n in nuisance.actuator_areas(net, set())}
    assert set(found) == {"cylinder.A"}
    a = found["cylinder.A"]
    assert a.bounds == pytest.approx((a.file_value / 1.03, a.file_value * 1.03))
    net2, all_found = nuisance.with_nuisance(net, {"valve.s_max"})
    assert {n.name for n in all_found} == {"valve.tau", "cylinder.A"}


def test_near_ties_on_training_bic_are_decided_by_held_out_data():
    from hydrocli.diagnose.ranking import rank_passing as _rank_passing
    seal = (-9955.0, SimpleNamespace(effect="pressure_dependent_friction"), {"esr_validation": {"P1": 0.50, "v": 0.26}})
    coul = (-9803.0, SimpleNamespace(effect="coulomb_friction"), {"esr_validation": {"P1": 0.32, "v": 0.33}})
    far = (-3000.0, SimpleNamespace(effect="valve_overlap"), {"esr_validation": {"P1": 0.10, "v": 0.10}})
    ranked = _rank_passing([seal, far, coul])
    assert [r[1].effect for r in ranked] == ["coulomb_friction", "pressure_dependent_friction", "valve_overlap"]


def test_a_training_advantage_the_held_out_data_refute_does_not_name_the_law():
    """Session 40, dev lift_cbv hook load (0.12 % in training, 0.86 % held out): a compliant mount
    fitted the training twice as well as the payload (ΔBIC −8719 against −4415) and predicted
    the held-out record 4× worse (summed ESR 0.683 against 0.157 %, band 0.175 %). Beyond the
    band the held-out data decide; within it, BIC's order stands."""
    from hydrocli.diagnose.ranking import rank_passing as _rank_passing
    mount = (-8719.0, SimpleNamespace(effect="structural_flexibility"), {"esr_validation": {"P1": 0.25, "P2": 0.11, "v": 0.323}})
    hook = (-4415.0, SimpleNamespace(effect="payload_swing"), {"esr_validation": {"P1": 0.03, "P2": 0.015, "v": 0.112}})
    leak = (-900.0, SimpleNamespace(effect="internal_leakage"), {"esr_validation": {"P1": 0.6, "P2": 0.3, "v": 0.12}})
    assert [r[1].effect for r in _rank_passing([mount, leak, hook])] == [
        "structural_flexibility", "payload_swing", "internal_leakage"]             # no band: BIC
    assert [r[1].effect for r in _rank_passing([mount, leak, hook], band=0.175)] == [
        "payload_swing", "structural_flexibility", "internal_leakage"]
    assert _rank_passing([mount, leak, hook], band=0.6)[0] is mount                 # within the band


def test_a_richer_law_the_data_do_not_separate_from_its_special_case_gives_way_to_it():
    """Seal friction fitted a hair better than Coulomb friction (the concealed Coulomb case's
    figures): not separated by the noise band, the simpler law is named; separated on one
    training experiment, or a pair neither of which reduces to the other, the order stands."""
    from hydrocli.diagnose.ranking import simplest as _simplest
    seal = (-1106.0, SimpleNamespace(effect="pressure_dependent_friction"),
            {"esr_validation": {"P1": 0.700, "v": 0.708}, "esr_train_each": [0.90]})
    coul = (-1102.0, SimpleNamespace(effect="coulomb_friction"),
            {"esr_validation": {"P1": 0.705, "v": 0.711}, "esr_train_each": [0.91]})
    far = (-300.0, SimpleNamespace(effect="valve_overlap"), {"esr_validation": {"P1": 0.6, "v": 0.6}})
    assert [r[1].effect for r in _simplest([seal, coul, far], band=0.17)] == \
        ["coulomb_friction", "pressure_dependent_friction", "valve_overlap"]
    apart = (coul[0], coul[1], dict(coul[2], esr_train_each=[1.5]))
    assert _simplest([seal, apart, far], band=0.17)[0] is seal
    weak = (-500.0, coul[1], coul[2])          # ΔBIC well short of the winner's: the data prefer the seal law
    assert _simplest([seal, weak], band=0.17)[0] is seal
    play = (-1102.0, SimpleNamespace(effect="valve_hysteresis"), coul[2])
    assert _simplest([seal, play], band=0.17)[0] is seal
    assert _simplest([coul, seal], band=0.17)[0] is coul


def test_primaries_are_judged_given_the_companions_that_shape_the_effect():
    """Two estimates that trade off (ρ = 0.995): the amount is determined once the shape is
    given, σ_a|b = σ_a·√(1 − ρ²) — the conditional covariance of a Gaussian, checked against
    inverting the information matrix's sub-block."""
    import numpy as np
    from hydrocli.diagnose.accept import conditional_stderr
    se, rho = np.array([0.4, 3.0, 0.02]), np.array([[1, 0.995, 0.3], [0.995, 1, 0.2], [0.3, 0.2, 1]])
    cond = conditional_stderr(["air", "n", "m"], se, rho, {"n"})
    info = np.linalg.inv(rho * np.outer(se, se))
    ref = np.sqrt(np.diag(np.linalg.inv(info[np.ix_([0, 2], [0, 2])])))
    assert cond["air"] == pytest.approx(ref[0]) and cond["m"] == pytest.approx(ref[1])
    assert cond["air"] < 0.2 * se[0] and cond["n"] == se[1]
    assert conditional_stderr(["air", "n"], se[:2], None, {"n"}) == {"air": 0.4, "n": 3.0}   # no correlation: marginal


def test_a_transducer_lag_at_the_ceiling_restrains_every_pressure_sensor():
    """A pressure-sensor lag the base fit presses against the measurement model's ceiling
    stands for a lag the file lacks (a hose, or a slow sensor): every sensor is restrained to
    a typical transducer's; lags a transducer has (up to 2.5 ms here) are left alone."""
    from hydrocli.diagnose import restrain
    from hydrocli.diagnose.measurement import PRESSURE_TAU_BOUNDS, PRESSURE_TAU_TYPICAL
    net, sensors = with_pressure_sensors(load_netlist(ROOT / "machines" / "eha_testbench.yaml"))
    ctx = Context(net, set(), {}, {}, {})
    taus = sorted(f"{s}.tau" for s in sensors)
    assert len(taus) == 2
    bounds = {n: PRESSURE_TAU_BOUNDS for n in taus}
    assert restrain.limits(ctx, {taus[0]: 1.2e-3, taus[1]: 2.5e-3}, bounds) == {}
    lim = restrain.limits(ctx, {taus[0]: 3.0e-3, taus[1]: 0.8e-3}, bounds)
    assert lim == {n: (PRESSURE_TAU_BOUNDS[0], PRESSURE_TAU_TYPICAL) for n in taus}


def test_a_spool_time_constant_at_its_tolerance_ceiling_is_offered_for_restraint():
    """The valve's spool time constant (its role's ``spool_lag``, a nuisance parameter free
    within the datasheet's ±30 %) pressed against that ceiling may stand for a lag the file
    lacks (a delayed command, a sticking spool): :func:`restrain.slow_spools` offers it,
    restrained to the datasheet's tolerance (tried only when the round from the free base
    accepted nothing). Inside the window, or at its FLOOR (a faster valve stands for no missing
    lag), it is not offered, and neither is the rate limit at its bound (nulls often leave it
    there); :func:`restrain.limits` never restrains it on its own."""
    from hydrocli.diagnose import restrain
    net, found = nuisance.with_nuisance(load_netlist(ROOT / "machines" / "eha_testbench.yaml"), set())
    ctx = Context(net, set(), {}, {}, {})
    for t in ("valve_4_3", "valve_pc_ls"):
        assert registry.get(t).role(R.METERING_VALVE).param("spool_lag") == "tau"
    bounds = {n.name: n.bounds for n in found}
    initial = {n.name: n.file_value for n in found}
    tau0, (lo, hi) = initial["valve.tau"], bounds["valve.tau"]
    smax_lo = bounds["valve.s_max"][0]
    pressed = {"valve.tau": hi, "valve.s_max": smax_lo}
    assert restrain.slow_spools(ctx, {"valve.tau": 1.3 * tau0, "valve.s_max": smax_lo}, bounds, initial) == {}
    assert restrain.slow_spools(ctx, {"valve.tau": lo}, bounds, initial) == {}
    assert restrain.limits(ctx, pressed, bounds, initial, set(pressed)) == {}
    lim = restrain.slow_spools(ctx, pressed, bounds, initial)
    assert lim == {"valve.tau": (lo, pytest.approx(restrain.SPOOL_TOLERANCE * tau0))}
    assert restrain.start(hi, lim["valve.tau"]) == pytest.approx(1.15 * tau0)


def test_a_round_from_a_base_with_the_spool_restrained_must_beat_the_free_base(monkeypatch):
    """``engine._spool_round``: the base is re-identified with the slow spool restrained AS
    WELL AS every other restraint, and the round runs from there with the free base as the
    floor every candidate must beat; when the restrained base cannot be simulated, nothing is
    tried, and when its round accepts nothing, no round is returned: either way the baseline is
    unchanged."""
    from hydrocli.diagnose import engine, restrained
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    model = build_model(net)
    free = SimpleNamespace(model=model, p=np.array(model.param_vector({"valve.tau": 5.72e-3})))
    b = engine.Baseline(free, None, [], {}, {}, [], 100.0, None, {"friction.vs_p": (1e-3, 1e-2)},
                        {"valve.tau": (2.8e-3, 4.6e-3)})
    held, seen = SimpleNamespace(name="restrained"), {}

    def refit(su, base, lim, st, progress):
        seen["lim"], seen["from"] = lim, base
        return held

    def round_from(su, b2, free_, accepted, st, pool, progress):
        seen["round"] = (b2.restrained, free_)
        return SimpleNamespace(accepted={"effect": "input_delay"}), accepted + ["x"]
    monkeypatch.setattr(restrained, "restrained_base", refit)
    monkeypatch.setattr(engine, "_restrained_round", round_from)
    said = []
    rnd, b2, acc = engine._spool_round(None, b, free, [], engine.Settings(), None, said.append, "why")
    assert seen["lim"] == {"friction.vs_p": (1e-3, 1e-2), "valve.tau": (2.8e-3, 4.6e-3)} and seen["from"] is free
    assert seen["round"] == (held, free) and b2.restrained is held and b2.restraints == seen["lim"]
    assert rnd.accepted["effect"] == "input_delay" and acc == ["x"]
    assert any("valve.tau = 0.00572" in m for m in said)
    monkeypatch.setattr(engine, "_restrained_round",
                        lambda su, b2, free_, accepted, *a: (SimpleNamespace(accepted=None), accepted + ["x"]))
    assert engine._spool_round(None, b, free, [], engine.Settings(), None, said.append, "why") == (None, b, [])
    monkeypatch.setattr(restrained, "restrained_base", lambda *a: None)
    assert engine._spool_round(None, b, free, [], engine.Settings(), None, said.append, "why") == (None, b, [])


def test_a_slow_transducer_does_not_explain_a_slow_spool():
    """``restrain.lag_left_to_the_spool``: a round from the restrained base that names an effect
    of the measurement (a slow transducer) leaves a spool pressed against its ceiling
    unexplained, since a transducer cannot delay the motion — unless that spool was already
    restrained in the round. An effect of the machine (a delayed command, a hose) may explain
    it, and a spool inside its tolerance asks nothing."""
    from hydrocli.diagnose import restrain
    from hydrocli.diagnose.measurement import EFFECTS
    slow = {"valve.tau": (2.8e-3, 4.6e-3)}
    sensors = {"p1_sensor.tau": (1e-4, 1.5e-3)}
    assert EFFECTS == {"sensor_lag"}
    assert restrain.lag_left_to_the_spool("sensor_lag", slow, sensors)
    assert not restrain.lag_left_to_the_spool("sensor_lag", slow, {**sensors, **slow})
    assert not restrain.lag_left_to_the_spool("sensor_lag", {}, sensors)
    for effect in ("input_delay", "line_dynamics", "entrained_air"):
        assert not restrain.lag_left_to_the_spool(effect, slow, sensors)
    # the model with the transducer still presses the spool beyond its tolerance: left to it
    assert restrain.lag_left_to_the_spool("sensor_lag", slow, sensors, {"valve.tau": 5.5e-3})
    # the transducer brought the spool back inside its tolerance: its lag was the transducer's
    assert not restrain.lag_left_to_the_spool("sensor_lag", slow, sensors, {"valve.tau": 4.0e-3})
    assert not restrain.lag_left_to_the_spool("sensor_lag", slow, sensors, {"valve.tau": 4.6e-3})


def test_a_slow_transducer_named_with_a_spool_at_its_ceiling_is_tried_again_with_the_spool_restrained(monkeypatch):
    """``engine._restrained_first``: when the round from the restrained base names a slow
    transducer and the spool's pressed lag was left free, the round runs again with the spool
    restrained (from the accepted list as it was before either round), and its answer stands
    when it accepts anything; when it accepts nothing, or the first round named an effect of
    the machine, the first round's answer stands."""
    from hydrocli.diagnose import engine
    from hydrocli.diagnose.clock import StepClock
    b = engine.Baseline(None, None, [], {}, {}, [], 100.0, "held", {"s.tau": (1e-4, 1.5e-3)},
                        {"valve.tau": (2.8e-3, 4.6e-3)})
    first, calls = {}, []

    def restrained_round(su, b_, free, accepted, st, pool, progress):
        return SimpleNamespace(accepted=first["accepted"], rows=["r1"], stage=first.get("stage")), accepted + ["first"]

    def spool_round(su, b_, free, accepted, st, pool, progress, why):
        calls.append((list(accepted), why))
        if first["spool"] is None:          # _spool_round's contract: no round when it accepted nothing
            return None, b_, accepted
        return SimpleNamespace(accepted=first["spool"], rows=["r2"]), "b_spool", accepted + ["spool"]
    monkeypatch.setattr(engine, "_restrained_round", restrained_round)
    monkeypatch.setattr(engine, "_spool_round", spool_round)

    def run():
        calls.clear()
        return engine._restrained_first(None, b, "free", ["base"], engine.Settings(), None, None, StepClock(last=0.0))
    first.update(accepted={"effect": "sensor_lag"}, spool={"effect": "input_delay"})
    rnd, b2, acc, rows = run()
    assert rnd.accepted["effect"] == "input_delay" and b2 == "b_spool" and acc == ["base", "spool"]
    assert rows == ["r1", "r2"] and calls[0][0] == ["base"] and "sensor_lag" in calls[0][1]
    first.update(spool=None)
    rnd, b2, acc, rows = run()
    assert rnd.accepted["effect"] == "sensor_lag" and b2 is b and acc == ["base", "first"] and len(calls) == 1
    first.update(accepted={"effect": "input_delay"}, spool={"effect": "line_dynamics"})
    rnd, b2, acc, rows = run()
    assert rnd.accepted["effect"] == "input_delay" and b2 is b and rows == ["r1"] and not calls
    # the transducer named, and the model with it has its spool back inside the datasheet's
    # tolerance (≤ 4.6 ms): the spool's lag was the transducer's, no second round
    model = SimpleNamespace(param_names=["valve.tau"], param_index=lambda n: 0)
    first.update(accepted={"effect": "sensor_lag"}, spool={"effect": "input_delay"},
                 stage=SimpleNamespace(p=np.array([4.0e-3]), model=model))
    rnd, b2, acc, rows = run()
    assert rnd.accepted["effect"] == "sensor_lag" and b2 is b and not calls
    # still pressed beyond it (5.5 ms): tried again with the spool restrained
    first.update(stage=SimpleNamespace(p=np.array([5.5e-3]), model=model))
    rnd, b2, acc, rows = run()
    assert rnd.accepted["effect"] == "input_delay" and len(calls) == 1


def test_actuator_bulk_modulus_below_oil_is_restrained_and_hoses_are_not(tmp_path):
    """The chambers' bulk modulus is found by role and restrained to oil's range only where
    the base fit left it below; a hose volume's low effective modulus is left alone."""
    from hydrocli.diagnose import restrain
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    ctx = Context(net, set(), {}, {}, {})
    bounds = {"cylinder.beta": (0.3e9, 2.5e9), "hose.beta": (0.1e9, 1.5e9)}
    assert restrain.limits(ctx, {"cylinder.beta": 1.4e9}, bounds) == {}
    lim = restrain.limits(ctx, {"cylinder.beta": 0.63e9, "hose.beta": 0.2e9}, bounds)
    assert lim == {"cylinder.beta": (restrain.OIL_MIN, 2.5e9)}
    out = restrain.apply(net, lim, {"cylinder.beta": 0.63e9})
    from hydrocli.model.builder import build_model
    m = build_model(out)
    info = m.params[m.param_index("cylinder.beta")]
    assert info.bounds == (restrain.OIL_MIN, 2.5e9) and info.value == restrain.OIL_MIN
    assert "cylinder.beta" in m.free_params


def test_a_restrained_base_that_cannot_be_simulated_falls_back_to_the_free_base(monkeypatch):
    """When no simulation of the restrained base succeeds (dev lift end stop: β raised to
    oil's against a stop the file lacks), the diagnosis goes on from the free base instead of
    failing the whole case."""
    from hydrocli.diagnose import engine, restrained
    from hydrocli.errors import IdentifyError, Problem
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    model = build_model(net)
    base = SimpleNamespace(net=net, model=model, p=np.array(model.param_vector({})))

    def failing(*a, **k):
        raise IdentifyError(Problem("every trial simulation failed (3)"))
    monkeypatch.setattr(engine.baseline, "identify", failing)
    said = []
    su = SimpleNamespace(train=[], validate=[], outputs=[])
    lim = {"cylinder.beta": (1.0e9, 2.5e9)}
    assert restrained.restrained_base(su, base, lim, engine.Settings(), said.append) is None
    assert any("cannot be simulated" in m for m in said)


def test_a_value_pushed_to_a_bound_far_from_the_files_is_restrained_near_the_file():
    """A Stribeck velocity the base fit widened ×15 to its upper bound (imitating a Coulomb
    force) is restrained to within ×3 of the file's value; one at a bound but near the file's
    value, one far but inside its range, and an optional term at its natural zero are not."""
    from hydrocli.diagnose import restrain
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    ctx = Context(net, set(), {}, {}, {})
    bounds = {"friction.vs_p": (1e-4, 5e-2), "friction.ks_m": (0.0, 2000.0), "valve.tau": (1e-3, 5e-3),
              "cylinder.c_el": (0.0, 1e-10)}
    initial = {"friction.vs_p": 3.41e-3, "friction.ks_m": 39.4, "valve.tau": 4e-3, "cylinder.c_el": 0.0}
    est = {"friction.vs_p": 5e-2, "friction.ks_m": 340.0, "valve.tau": 5e-3, "cylinder.c_el": 0.0}
    at = {"friction.vs_p", "valve.tau", "cylinder.c_el"}
    lim = restrain.limits(ctx, est, bounds, initial, at)
    assert lim == {"friction.vs_p": pytest.approx((3.41e-3 / 3, 3.41e-3 * 3))}
    m = build_model(restrain.apply(net, lim, est))
    info = m.params[m.param_index("friction.vs_p")]
    assert info.value == pytest.approx(3.41e-3 * 3) and "friction.vs_p" in m.free_params


def test_rod_seal_leak_forms_drain_the_chambers_that_have_a_rod_seal():
    """External leakage of a cylinder happens at its rod seals. A single-rod cylinder has one,
    on the rod side: a form that drains the rod-side (smaller-area) chamber only. A double-rod
    cylinder has one at each end: a conductance per seal, which its c_el (one conductance for
    both chambers) cannot express. Both forms can start from a c_el the base fit found
    (NewParam.takes_over). A vane (no rod seal) gets neither."""
    from hydrocli.model.builder import build_model
    lift = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    cands, _ = catalogue(Context(lift, set(), {}, {}, {}))
    rod = next(c for c in cands if c.key.endswith("#rod_seal"))
    aug = rod.build(lift)
    new = [n for n in aug.components if n not in lift.components]
    assert len(new) == 1 and aug.components[new[0]].ports["A"] == lift.components["cylinder"].ports["B"]
    assert set(p.name for p in rod.params) <= set(build_model(aug).free_params)
    assert all(p.takes_over == ("cylinder.c_el", 0.0, -1.0) for p in rod.params)
    eha = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    cands = catalogue(Context(eha, set(), {}, {}, {}))[0]
    assert not any(c.key.endswith("#rod_seal") for c in cands)
    seals = next(c for c in cands if c.key.endswith("#rod_seals"))
    aug = seals.build(eha)
    new = sorted(n for n in aug.components if n not in eha.components)
    ports = {aug.components[n].ports["A"] for n in new}
    assert len(new) == 2 and ports == {eha.components["cylinder"].ports["A"], eha.components["cylinder"].ports["B"]}
    assert all(p.takes_over == ("cylinder.c_el", 0.0, -1.0) for p in seals.params)
    assert set(p.name for p in seals.params) <= set(build_model(aug).free_params)
    vane = load_netlist(ROOT / "machines" / "rotary_drive.yaml")
    assert not any("rod_seal" in c.key for c in catalogue(Context(vane, set(), {}, {}, {}))[0])


def test_a_compliance_is_screened_at_more_than_one_size():
    """One log-scaled primary with a wide plausible range (a stiffness): the declared probe
    and two more sizes across the range; a shape companion keeps its probe; effects with two
    primaries or a position (a stop) keep the one probe."""
    from hydrocli.diagnose.candidates.base import NewParam
    from hydrocli.diagnose.workers import _probes
    k = NewParam("link.k", 1.5e10, (1.5e6, 1.5e11), (1.5e6, 7.5e9), 1.1e7, True)
    c = NewParam("link.c", 100.0, (1.0, 1e5), (1.0, 1e5), 30.0, True, primary=False)
    probes = _probes([k, c])
    ks = sorted(pr["link.k"] for pr in probes)
    assert len(probes) == 3 and all(pr["link.c"] == 30.0 for pr in probes)
    assert ks[0] < 1.5e7 < 1e8 < ks[1] < ks[2] < 7.5e9 and 1.1e7 in ks
    two = [k, NewParam("link2.k", 1.5e10, (1.5e6, 1.5e11), (1.5e6, 7.5e9), 1.1e7, True)]
    assert len(_probes(two)) == 1
    stop = NewParam("cyl.x_max", 0.3, (0.2, 0.4), (0.2, 0.4), 0.25, scale=0.2)
    assert len(_probes([stop])) == 1


def test_a_stop_fitted_beyond_the_recorded_positions_is_not_judged_but_one_must_be_engaged():
    """The Festo rig reaches its extended stop only: the retracted stop's fitted position lies
    beyond the positions recorded, bounded from one side, its standard error no test of the
    effect. An effect whose stops are both beyond the record is not found."""
    from hydrocli.diagnose.accept import judge
    from hydrocli.diagnose.candidates.base import NewParam
    reach = (-0.004, 0.204)
    params = [NewParam("c.x_min", -0.04, (-0.1, 0.004), (-0.1, 0.004), -0.001, scale=0.2, reach=reach),
              NewParam("c.x_max", 0.24, (0.196, 0.3), (0.196, 0.3), 0.201, scale=0.2, reach=reach),
              NewParam("c.k", 1e8, (1e5, 1e11), (1e5, 1e11), 3e8, True, primary=False)]
    cand = SimpleNamespace(params=params, checks=())          # a Candidate as judge reads it

    def fit(x_min, x_max):
        return {"names": ["c.x_min", "c.x_max", "c.k"], "estimates": [x_min, x_max, 1e10],
                "stderr": [0.4, 0.0005, 1e12], "cost": 0.5}
    ok = judge(cand, fit(-0.084, 0.1967), 1.0, 1000, 10.0, 1.0, 0.1)
    assert ok["passed"], ok["reasons"]
    # the same ±0.4 m on a stop INSIDE the record is a poorly determined effect
    bad = judge(cand, fit(-0.002, 0.1967), 1.0, 1000, 10.0, 1.0, 0.1)
    assert any("c.x_min poorly determined" in r for r in bad["reasons"])
    none_ = judge(cand, fit(-0.084, 0.26), 1.0, 1000, 10.0, 1.0, 0.1)
    assert "no stop engaged within the positions recorded" in none_["reasons"]


ONE_LAG = """
name: one_lag
inputs: {u: {unit: "1"}}
components:
  lag2:
    type: first_order_lag
    ports: {in: u, out: z}
    tau: {value: 0.07, free: true, bounds: [0.001, 1]}
    k: {value: 1.5, free: true, bounds: [0.1, 10]}
outputs: {z: lag2.y}
"""


def test_a_design_is_scored_after_the_rival_is_refitted_to_the_winner(tmp_path):
    """T-optimality (Atkinson & Fedorov 1975): a rival of the SAME structure with another
    parameter value is told apart by a test only until it is re-fitted — after the refit it
    predicts the winner's response (discrimination collapses); a rival of another structure
    (one lag against two in series) still misses the designed test after its refit."""
    from hydrocli.diagnose import design
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
    net = load_netlist_text(LAG, "lags.yaml")
    ma = build_model(net)
    t = np.arange(0, 4.0, 2e-3)
    u = np.sign(np.sin(2 * np.pi * 0.7 * t)) + 0.5 * np.sin(2 * np.pi * 3.1 * t)
    y = simulate(ma, InputTable(t, u[:, None]), t, p=ma.p0, opts=SolverOptions(rtol=1e-8)).Y[:, 0]
    train = [Experiment("train", "<synthetic>", InputTable(t, u[:, None]), t, measured={"z": y}, fit_outputs=["z"])]
    sigma = {"z": 0.01}
    q = ma.p0.copy()
    q[ma.param_index("lag2.tau")] = 0.08
    same = design.propose(("a", ma, ma.p0), ("b", ma, q), net, train, sigma, tmp_path / "same", "lags",
                          refit_iterations=10, band=0.1)
    assert same["discrimination_held"] > 1e3 and same["discrimination"] < 1e-3 * same["discrimination_held"]
    assert same["esr_gap"] < 0.01 and not same["decisive"]       # no test can tell them apart
    mb = build_model(load_netlist_text(ONE_LAG, "one_lag.yaml"))
    other = design.propose(("a", ma, ma.p0), ("b", mb, mb.p0), net, train, sigma, tmp_path / "other", "lags",
                           refit_iterations=10, band=0.1)
    assert other["discrimination"] > 100.0 and other["discrimination"] > 10 * same["discrimination"]
    assert other["esr_gap"] > 1.0 and other["decisive"]
    # the ESR gap is the one-lag model's ESR on the two-lag chain's noise-free prediction
    assert other["esr_gap"] == pytest.approx(sum(100 * (d / s) ** 2 * s ** 2 for d, s in
                                                 zip(other["predicted_difference"].values(), sigma.values()))
                                             / np.var(_two_lag_response(ma, other["text"], tmp_path)), rel=1e-6)


def _two_lag_response(model, text, tmp_path):
    """The winner's prediction of a proposed design, simulated the way the design module does."""
    from hydrocli.diagnose import design
    from hydrocli.experiments.experiment_file import load_experiment_file
    path = tmp_path / "proposal.yaml"
    path.write_text(text)
    return design._simulate(model, model.p0, load_experiment_file(path, model))[:, 0]


def test_end_stops_already_in_the_file_are_not_offered_as_missing():
    """The Festo rig's full machine has its steel stops (k_stop 1e8 N/m): where they sit is a
    parameter of the file, not missing physics, so no end_stop candidate (nor a cushion: it has
    them); the same machine without stops gets one."""
    out = {}
    for name in ("festo_tp511", "festo_tp511_no_endstops"):
        net = load_netlist(ROOT / "machines" / f"{name}.yaml")
        ctx0 = Context(net, set(), {}, {}, {})
        node = ctx0.parts(R.ACTUATOR)[0].node("motion")
        cands, skipped = catalogue(Context(net, set(), {node: (0.0, 0.195)}, {}, {}))
        out[name] = ([c for c in cands if c.effect == "end_stop"], [s for s in skipped if s.effect == "end_stop"])
    assert not out["festo_tp511"][0] and "already has end stops" in out["festo_tp511"][1][-1].reason
    assert any("cushioned in the machine already" in s.reason for s in out["festo_tp511"][1])
    assert [[p.name for p in c.params] for c in out["festo_tp511_no_endstops"][0] if not c.variant] == \
        [["cylinder.x_min", "cylinder.x_max", "cylinder.k_stop"]]
    # without its cushions and stops, a cushion at each end is offered as well (candidates/cushion.py)
    assert sorted(c.variant for c in out["festo_tp511_no_endstops"][0] if c.variant) == ["cushion_max", "cushion_min"]


def test_a_vane_actuator_offers_end_stops_in_its_own_units():
    """A rotary drive's vane swings between stops: the angle output gives the travel seen (the
    rotary family's end-stop cases were skipped for want of it), and the candidate's stiffness
    floor is set by the vane's torque per Pa (N·m/rad), not a cylinder's N/m — a 20 cm³/rad
    vane's softest stop (100 bar torque over a tenth of 1 rad) is 2000 N·m/rad, where the
    linear 1e5 N/m floor would have excluded a rubber bumper."""
    from hydrocli.diagnose import augment
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "rotary_drive.yaml")
    model = build_model(net)
    assert augment.output_symbols_expr(model, "theta") == {"arm_node"}
    cands, skipped = catalogue(Context(net, set(), {"arm_node": (-0.5, 0.5)}, {}, {}))
    stops = [c for c in cands if c.effect == "end_stop" and not c.variant]
    assert len(stops) == 1, [s.reason for s in skipped if s.effect == "end_stop"]
    # and a cushion at each end of the swing (end_cushion_rotary, candidates/cushion.py)
    assert sorted(c.variant for c in cands if c.effect == "end_stop" and c.variant) == ["cushion_max", "cushion_min"]
    by_name = {p.name: p for p in stops[0].params}
    assert set(by_name) == {"vane.theta_min", "vane.theta_max", "vane.k_stop"}
    d_v = net.components["vane"].params["D_v"].value
    assert by_name["vane.k_stop"].bounds[0] == pytest.approx(d_v * 1e7 / 0.1)      # 2000 N·m/rad
    assert by_name["vane.theta_max"].reach == pytest.approx((-0.6, 0.6))


def test_a_stop_the_training_never_pressed_is_withdrawn_beyond_every_recording():
    """Held-out seed 76's vane: trained over 0 … 0.52 rad against a bumper at 0.5 rad, run to
    −0.80 rad in the held-out record. The lower stop, never pressed in training, was withdrawn to
    its outer bound, −0.26 rad (half the travel seen below it), where the held-out run met it:
    validation ESR 139 → 1590 %. The outer bounds now lie a tenth of the travel beyond every
    recording, training and held-out; the plausible range and the reach stay the training's."""
    from hydrocli.diagnose.workers import withdraw_idle_stops
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "rotary_drive.yaml")
    ctx = Context(net, set(), {"arm_node": (0.0, 0.52)}, {}, {}, recorded_range={"arm_node": (-0.80, 0.52)})
    stop = next(c for c in catalogue(ctx)[0] if c.effect == "end_stop" and not c.variant)
    lo, hi = stop.params[0], stop.params[1]
    assert lo.bounds[0] == pytest.approx(-0.80 - 0.052) and lo.plausible[0] == pytest.approx(-0.26)
    assert hi.bounds[1] == pytest.approx(0.52 + 0.26)           # the training's half travel is further
    # a fit that leaves the stops where they started (never pressed): withdrawn to those bounds
    model = build_model(stop.build(net))
    names = [p.name for p in stop.params]
    res = SimpleNamespace(p=model.p0.copy(), names=names, estimates=None, cost=1.0)
    for prm in stop.params:
        res.p[model.param_index(prm.name)] = prm.start
    obj = SimpleNamespace(cost=lambda p: 1.0)
    stops = [{"name": q.name, "start": q.start, "seen": q.seen, "bounds": q.bounds, "scale": q.scale}
             for q in stop.params if q.seen]
    assert withdraw_idle_stops(obj, model, res, stops) == ["vane.theta_min", "vane.theta_max"]
    assert res.p[model.param_index("vane.theta_min")] < -0.80
    # without held-out travel beyond the training's, the bounds are as before
    plain = next(c for c in catalogue(Context(net, set(), {"arm_node": (0.0, 0.52)}, {}, {}))[0]
                 if c.effect == "end_stop" and not c.variant)
    assert plain.params[0].bounds[0] == pytest.approx(-0.26)


def test_an_unexplained_mismatch_says_when_held_out_positions_leave_the_training_range():
    """A stop touched only in the held-out recording cannot be found by fitting the training
    one: the summary says where the held-out data go beyond training, and only then."""
    from hydrocli.diagnose.summary import console_summary
    assert findings.beyond_training({"x": (0.046, 0.1125)}, {"x": (0.059, 0.1288)}) == \
        {"x": {"train": [0.046, 0.1125], "validate": [0.059, 0.1288]}}
    assert findings.beyond_training({"x": (0.046, 0.1125)}, {"x": (0.05, 0.115)}) == {}   # within 5 % of the span
    assert findings.beyond_training({"x": (0.0, 1.0)}, {"x": (-0.2, 0.5)})                # below as well
    d = {"accepted": [], "verdict": "unexplained_mismatch", "effects": ["none"], "runtime_s": 1.0, "ranking": [],
         "located": {"outputs": {}, "regimes": []}, "base_parameters": [], "measurement_model": {},
         "nuisance_parameters": {},
         "unexplained": {"outputs": {"P2": {"esr_validation": 3.2, "noise_floor": 0.35}}, "regimes": [],
                         "beyond_training": {"x": {"train": [0.046, 0.1125], "validate": [0.059, 0.1288]}}}}
    text = console_summary(SimpleNamespace(data=d))
    assert "beyond the training's 0.046 … 0.1125" in text and "Add a training recording" in text


def test_a_rotary_drive_offers_a_lag_of_its_angle_and_speed_sensor():
    """The sensor-lag candidate reads a rotary machine's angle/speed outputs as it reads a
    cylinder's position/velocity (rotary cases had no motion-sensor candidate at all): the
    augmented machine reads theta and w through a rotary_motion_sensor whose lag is free."""
    from hydrocli.diagnose.locate import output_quantities
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "rotary_drive.yaml")
    model = build_model(net)
    cands, _ = catalogue(Context(net, set(), {"arm_node": (-0.5, 0.5)}, output_quantities(model), {}))
    lag = [c for c in cands if c.effect == "sensor_lag" and c.component == "arm_node" and not c.variant]
    assert len(lag) == 1
    net2 = lag[0].build(net)
    aug = build_model(net2)
    tau = lag[0].params[0].name
    assert tau in aug.free_params
    sens = tau.rsplit(".", 1)[0]
    assert net2.components[sens].type == "rotary_motion_sensor"
    assert net2.outputs["w"].expr == f"{sens}.w" and net2.outputs["theta"].expr == f"{sens}.theta"
    assert net2.outputs["P1"].expr == net.outputs["P1"].expr


def test_a_speed_output_is_also_offered_its_own_second_order_filter():
    """A speed read by a tachogenerator or differentiated from a position goes through its own
    filter while the position is read directly: the speed-filter variant reads w through a
    rotary_speed_sensor (τ and ζ free, ζ from a Butterworth 0.71) and leaves theta as it was."""
    from hydrocli.diagnose.locate import output_quantities
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "rotary_drive.yaml")
    cands, _ = catalogue(Context(net, set(), {"arm_node": (-0.5, 0.5)}, output_quantities(build_model(net)), {}))
    filt = [c for c in cands if c.effect == "sensor_lag" and c.variant == "speed_filter"]
    assert [c.component for c in filt] == ["arm_node"]
    net2 = filt[0].build(net)
    tau, zeta = (p.name for p in filt[0].params)
    sens = tau.rsplit(".", 1)[0]
    assert net2.components[sens].type == "rotary_speed_sensor" and zeta == f"{sens}.zeta"
    assert {tau, zeta} <= set(build_model(net2).free_params)
    assert net2.outputs["w"].expr == f"{sens}.w" and net2.outputs["theta"].expr == net.outputs["theta"].expr
    assert filt[0].params[1].start == 0.71 and not filt[0].params[1].primary
    # a slow machine's speed may be counted over a gate time or filtered hard: a drum speed read
    # through a 0.82 Hz filter (τ = 0.19 s, dev winch) must lie inside the bounds AND the
    # plausible range of the filter and of the first-order lag of both readings, or it ends at a
    # bound and is refused
    for c in filt + [c for c in cands if c.effect == "sensor_lag" and c.component == "arm_node"]:
        q = c.params[0]
        assert q.bounds[0] < 0.19 < 0.5 < q.bounds[1] and q.plausible[0] < 0.19 < 0.5 < q.plausible[1], c.key


# the vane pendulum above without its weight, with its chamber volumes and no cross-vane leak
VANE_ON_MOUNT = (ROTARY.replace("  weight: {type: gravity_load, ports: {r: arm}, W: 5.0}\n", "")
                 .replace("D_v: 5.0e-6}", "D_v: 5.0e-6, V_1: 2.0e-5, V_2: 2.0e-5, R_v: 0.0}"))


def _mode_frequencies(model, pressures: float) -> list[float]:
    """Oscillation frequencies (Hz) of the model linearised at rest, chambers at ``pressures``
    (central differences of the generated right-hand side)."""
    f = model.numpy_evaluate()
    p = np.array([q.value for q in model.params])
    x0 = np.zeros(len(model.state_names))
    for s in ("c1.p", "c2.p"):
        x0[model.state_index(s)] = pressures

    def rhs(x):
        dx, *_ = f(0.0, list(x[:, None]), p, [np.zeros(1)])
        return np.array([np.asarray(d, float).ravel()[0] for d in dx])
    jac = np.zeros((x0.size, x0.size))
    for j in range(x0.size):
        h = 1e-6 * max(abs(x0[j]), 1.0)
        e = np.zeros(x0.size)
        e[j] = h
        jac[:, j] = (rhs(x0 + e) - rhs(x0 - e)) / (2 * h)
    w = np.abs(np.linalg.eigvals(jac).imag) / (2 * np.pi)
    return sorted({round(float(v), 3) for v in w if v > 1.0})


def test_a_mount_candidate_identifies_what_moves_on_it(tmp_path):
    """The mount candidate identifies the mass or inertia on the mount and its damping with
    the stiffness (a housing a quarter of the load rings at three times the frequency of a
    frame fixed at twice it). Reference: the two-degree-of-freedom closed form — the arm J on
    the oil spring k_h = D²·β·(1/V_1 + 1/V_2) (valve closed) against the frame J_f on its mount
    k: ω⁴·J·J_f − ω²·(J·(k_h + k) + J_f·k_h) + k_h·k = 0."""
    from hydrocli.diagnose import augment as A
    assert "gravity_load" not in VANE_ON_MOUNT and "R_v: 0.0" in VANE_ON_MOUNT
    net = load_netlist_text(VANE_ON_MOUNT, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {"arm.theta": (-0.5, 0.5)}, {"p1": "pressure", "angle": "angle"}, {"u": 0.0})
    mount = next(c for c in catalogue(ctx)[0] if c.effect == "structural_flexibility")
    k_name, j_name, c_name, h_name = (p.name for p in mount.params)
    assert [p.primary for p in mount.params] == [True, False, False, False] and h_name.endswith("_mount.hc")
    frame = mount.params[1]
    assert frame.bounds[0] <= 0.02 * 0.05 and frame.bounds[1] >= 2 * 0.05     # a light housing … a heavy frame
    assert set(p.name for p in mount.params) <= set(build_model(mount.build(net)).free_params)
    J, D, beta, V, k = 0.05, 5.0e-6, 1.5e9, 2.0e-5, 2000.0
    k_h = D ** 2 * beta * 2 / V
    for J_f in (0.004, 0.2):
        model = build_model(A.set_values(mount.build(net), {k_name: k, j_name: J_f, c_name: 1e-3}))
        a, b, c = J * J_f, -(J * (k_h + k) + J_f * k_h), k_h * k
        expected = sorted(np.sqrt((-b + s * np.sqrt(b * b - 4 * a * c)) / (2 * a)) / (2 * np.pi) for s in (-1, 1))
        assert _mode_frequencies(model, 5e6) == pytest.approx(expected, rel=0.005)


def test_more_fluid_compliance_than_the_drawn_chambers_hold_is_entrained_air():
    """A base fit that needs ×1.5 or more of the drawn volume in EVERY chamber, well determined
    and needed on held-out data, found a compliance in each chamber (air or a hose volume);
    one chamber grown (a spring between the chambers can do that), a poorly determined
    volume, or a gain inside the noise band is not a finding."""
    from hydrocli.diagnose.findings import Chambers, fluid_compliance_excess
    vane = Chambers("vane", ("vane.V_1", "vane.V_2"))

    def rows(r1, r2, se=1e-6):
        return [{"name": "vane.V_1", "value": 6e-5 * r1, "initial": 6e-5, "stderr": se},
                {"name": "vane.V_2", "value": 6e-5 * r2, "initial": 6e-5, "stderr": se},
                {"name": "vane.beta", "value": 1.8e9, "initial": 1.5e9, "stderr": 1e7}]
    asked = []

    def gain(values):
        asked.append(values)
        return 3.0, 0.5
    found = fluid_compliance_excess(rows(2.1, 2.6), [vane], gain)
    assert [f["effect"] for f in found] == ["entrained_air"] and found[0]["source"] == "base_fit"
    assert found[0]["alternatives"] == ["line_dynamics"]
    assert asked == [{"vane.V_1": 6e-5, "vane.V_2": 6e-5}]          # judged with the drawn volumes back
    assert fluid_compliance_excess(rows(2.1, 1.2), [vane], gain) == []
    assert fluid_compliance_excess(rows(2.1, 2.6, se=5e-5), [vane], gain) == []
    assert fluid_compliance_excess(rows(2.1, 2.6), [vane], lambda v: (0.4, 0.5)) == []
    assert fluid_compliance_excess(rows(0.4, 0.4), [vane], gain) == []


def test_every_actuator_names_its_chamber_volumes():
    for t in ("cylinder", "cylinder_double_rod", "vane_actuator", "hydraulic_motor"):
        role = registry.get(t).role(R.ACTUATOR)
        assert len(role.params_of("dead_volumes")) == 2, t


def test_on_a_mount_the_actuators_friction_rubs_against_the_body():
    """Seal friction acts between the rod and the cylinder BODY: on the mount candidate the
    friction element drawn from the rod to ground is re-connected to the frame, so relative
    motion rubs and the reaction loads the mount (dev rotary linear mount, seed 12, 3.7 %:
    named load_compliance with the friction left on ground, structural_flexibility with it on
    the frame, validation P1 0.30 → 0.087 %, noise 0.09). The load's own elements stay."""
    net = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    assert net.components["friction"].ports["b"] == "ground"
    ctx = Context(net, set(), {"rod": (0.1, 0.4)}, {"x": "position", "P1": "pressure"}, {"u": 0.0})
    mount = next(c for c in catalogue(ctx)[0] if c.effect == "structural_flexibility")
    out = mount.build(net)
    frame = out.components["cylinder"].ports["body"]
    assert frame != "ground"
    assert out.components["friction"].ports == {"a": "rod", "b": frame}
    assert out.components["load"].ports == net.components["load"].ports
    link = next(c for c in catalogue(ctx)[0] if c.effect == "load_compliance")
    assert link.build(net).components["friction"].ports["b"] == "ground"     # a rod–load link: seals on the piston


def test_once_a_leak_is_shortlisted_its_other_significant_law_is_fitted_too():
    """A leak's laminar and orifice laws are forms of one effect: the best-screening one holds
    the effect's slot, and the other joins it when its score test is significant (dev rotary
    orifice leak: the laminar law screened 95 % and lost to a valve underlap; the orifice law,
    screened lower, was never fitted). Forms of an effect without several laws do not."""
    from hydrocli.diagnose.shortlist import shortlist
    order, scores = _screened(
        ("overlap", "valve", "valve_overlap", 0.97), ("leak", "continuity", "internal_leakage", 0.95),
        ("ext", "continuity", "external_leakage", 0.51), ("edges", "valve", "valve_asymmetry", 0.3),
        ("ratio", "valve", "valve_asymmetry", 0.2), ("leak_orifice", "continuity", "internal_leakage", 0.1))
    assert [c.key for c in shortlist(order, scores, 3)] == ["overlap", "leak", "ext", "leak_orifice"]
    scores["leak_orifice"]["p_value"] = 0.2          # not significant: not fitted
    assert [c.key for c in shortlist(order, scores, 3)] == ["overlap", "leak", "ext"]
    # the leak not shortlisted: its second law is not added either; a valve asymmetry's second
    # form is not a law and stays out
    assert [c.key for c in shortlist(order[3:], scores, 1)] == ["edges"]


def test_valve_hysteresis_is_offered_as_a_play_and_as_dahl_loops_all_fitted(tmp_path):
    """The spool's hysteresis has two laws (a linkage's play holds the spool across its band,
    a Dahl loop snaps to the same offset) and two places: between the command and the valve,
    and inside the valve between the spool and its metering lands (after the spool's dynamics;
    the loop driven by the spool's speed). All build with their parameters free,
    and once one is shortlisted the others are fitted too (dev Dahl-type hysteresis with the
    play alone: held-out gap left at 60–75 %; a loop on the spool behind an 8 ms spool, fitted
    on the command: h 60 % high and P2 0.84 % against noise 0.22 %, on the spool: h and σ to
    1 % and P2 at the noise; a play there: ΔBIC −11726 against −5838 on the command, b to 1.3 %)."""
    from hydrocli.diagnose.candidates import LAWS
    from hydrocli.diagnose.shortlist import shortlist
    net = load_netlist_text(ROTARY, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {"arm.theta": (-0.5, 0.5)}, {"p1": "pressure", "angle": "angle"}, {"u": 0.0})
    hyst = [c for c in catalogue(ctx)[0] if c.effect == "valve_hysteresis"]
    assert sorted(c.variant for c in hyst) == ["", "dahl", "dahl_spool", "play_spool"] and "valve_hysteresis" in LAWS
    for c in hyst:
        aug = c.build(net)
        model = build_model(aug)
        assert {p.name for p in c.params} <= set(model.free_params)
        if c.variant.endswith("_spool"):
            # the valve's own play or loop: the command still drives the valve, the state is in it
            state = {"dahl_spool": "valve.zh", "play_spool": "valve.xe"}[c.variant]
            assert aug.components["valve"].ports["cmd"] == "u" and state in model.state_names
            continue
        element = next(n for n, d in aug.components.items() if d.type in ("play", "dahl_hysteresis"))
        valve_cmd = aug.components["valve"].ports["cmd"]
        assert aug.components[element].ports == {"in": "u", "out": valve_cmd} and valve_cmd != "u"
        assert not {"valve.zh", "valve.xe"} & set(model.state_names)
    order, scores = _screened(("play", "valve", "valve_hysteresis", 0.6), ("delay", "signal", "input_delay", 0.5),
                              ("dahl", "valve", "valve_hysteresis", 0.2))
    assert [c.key for c in shortlist(order, scores, 1)] == ["play", "delay", "dahl"]


def test_coulomb_friction_frees_the_band_it_reverses_over_as_a_companion(tmp_path):
    """A Coulomb candidate carries the friction element's reversal band (the role's ``band``)
    as a companion: started at the machine's value (the type's default for a new element),
    allowed to widen up to BAND_RANGE times it, judged as a widening; not offered when the
    base model already fits the band."""
    from hydrocli.diagnose.candidates.friction import BAND_RANGE
    net = load_netlist_text(ROTARY, str(tmp_path / "vane.yaml"))
    ctx = Context(net, set(), {"arm.theta": (-0.5, 0.5)}, {"p1": "pressure", "angle": "angle"}, {"u": 0.0})
    coul = next(c for c in catalogue(ctx)[0] if c.effect == "coulomb_friction")
    band = next(p for p in coul.params if p.name.endswith(".eps"))
    assert not band.primary and band.start == band.ref == 1e-3 and band.bounds[1] == BAND_RANGE * 1e-3
    assert band.bounds[0] < band.start < band.bounds[1]
    assert {p.name for p in coul.params} <= set(build_model(coul.build(net)).free_params)
    # an existing element: its own value; fitted in the base already: no companion
    text = ROTARY.replace("outputs:", "  fr: {type: rotary_friction, ports: {a: arm, b: ground}, tau_c: 0.0, eps: 0.004}\noutputs:")
    net = load_netlist_text(text, str(tmp_path / "vane2.yaml"))
    ctx = Context(net, set(), {"arm.theta": (-0.5, 0.5)}, {"p1": "pressure", "angle": "angle"}, {"u": 0.0})
    coul = next(c for c in catalogue(ctx)[0] if c.effect == "coulomb_friction")
    assert [(p.name, p.start) for p in coul.params if not p.primary] == [("fr.eps", 0.004)]
    ctx.free.add("fr.eps")
    coul = next(c for c in catalogue(ctx)[0] if c.effect == "coulomb_friction")
    assert all(p.primary for p in coul.params)


@pytest.mark.parametrize("machine", ["luffing_cylinder.yaml", "rotary_drive.yaml"])
def test_a_compliance_is_fitted_with_its_springs_hardening(machine, tmp_path):
    """A rod–load link and a mount carry their spring's cubic hardening (the Duffing spring
    F = k·d·(1 + hc·(k·d)²/3)) as a companion of the first fit, not in a later round: fitted as
    a linear spring a hard bushing may not pass at all (dev EHA cubic mount, 1.1 %: validation
    gain −0.005 % linear, ΔBIC −7934 and P2 0.87 → 0.48 % with hardening), and fitted with the
    force-carried law k·(1 + h·F²) a cubic link mispredicts a held-out run's larger loads (dev
    rotary cubic link: validation P1 10.2 % against 0.80 % with hc). Started negligible
    (hc·F₅₀² = 1e-6), tried at hc·F₅₀² = 1 and 10⁴ (F₅₀ the actuator's force at 50 bar; each
    shape a basin of its own, fitted from its best start), up to 10⁶, log scale.
    The link's rod side carries its own identified mass or inertia (log scale, from a tenth
    of the load's, also tried at four tenths)."""
    net, _ = with_pressure_sensors(load_netlist(ROOT / "machines" / machine))
    ctx = Context(net, set(build_model(net).free_params), {}, {})
    cands = catalogue(ctx)[0]
    f50 = ctx.size(next(iter(ctx.parts(R.ACTUATOR)))) * 5e6
    for effect, spring in (("load_compliance", "_coupling.hc"), ("structural_flexibility", "_mount.hc")):
        cand = next(c for c in cands if c.effect == effect)
        (h,) = [p for p in cand.params if p.name.endswith(spring)]
        assert not h.primary and h.log and h.start * f50 ** 2 == pytest.approx(1e-6)
        assert h.shapes == pytest.approx((1.0 / f50 ** 2, 1e4 / f50 ** 2)) and h.bounds[1] * f50 ** 2 == pytest.approx(1e6)
        assert h.basins
        assert h.name in build_model(cand.build(net)).free_params
        assert not [p for p in cand.params if p.name.endswith("_coupling.h") or p.name.endswith("_mount.h")]
    link = next(c for c in cands if c.effect == "load_compliance")
    (rod,) = [p for p in link.params if "_rod_mass." in p.name]
    load = _inertia_of(net)
    assert not rod.primary and rod.log and rod.start == pytest.approx(0.1 * load)
    assert rod.shapes == pytest.approx((0.4 * load,)) and rod.bounds == pytest.approx((0.01 * load, 2.0 * load))
    assert rod.name in build_model(link.build(net)).free_params
    assert not [c for c in cands if c.variant == "progressive"]


@pytest.mark.parametrize("machine", ["luffing_cylinder.yaml", "rotary_drive.yaml"])
def test_a_compliance_reaches_a_boom_mode_of_one_hertz_and_starts_near_it(machine):
    """A crane's or a loader's boom and its mounting ring ring at 1–3 Hz. The link's and the
    mount's stiffness reach the load alone on the spring at 0.5 Hz, k = (2π·0.5)²·m, within
    bounds and plausible range (until session 29 the floor was 5 Hz, and a counterbalanced
    lift's 1.8 Hz mount ended at it and was rejected); seven geometric starts span the
    plausible range, none more than a decade from its neighbour, one within ×3 of a 1.8 Hz
    mount under the file's load (2·10⁵ N/m under 1.5 t on the lift)."""
    net, _ = with_pressure_sensors(load_netlist(ROOT / "machines" / machine))
    ctx = Context(net, set(build_model(net).free_params), {}, {})
    cands = catalogue(ctx)[0]
    m = _inertia_of(net)
    k_half_hz, k_mount = (2 * np.pi * 0.51) ** 2 * m, (2 * np.pi * 1.8) ** 2 * m
    for effect in ("load_compliance", "structural_flexibility"):
        k = next(c for c in cands if c.effect == effect).params[0]
        assert k.primary and k.log and k.bounds[0] <= k_half_hz and k.plausible[0] <= k_half_hz
        assert k.plausible[1] >= (2 * np.pi * 300) ** 2 * m
        starts = sorted(s[k.name] for s in _log_grid([k]))
        assert len(starts) == 7 and np.max(np.diff(np.log10(starts))) < 1.0
        assert min(abs(np.log(s / k_mount)) for s in starts) < np.log(3.0)


def _inertia_of(net) -> float:
    """The file's load: the one mass or inertia element's value (SI)."""
    for comp in net.components.values():
        if comp.type in ("mass", "inertia"):
            prm = comp.params["m" if comp.type == "mass" else "J"]
            return float(prm.value)
    raise AssertionError("no load")


def test_a_bushing_nearly_free_around_zero_is_reached_by_a_start_of_the_grid():
    """A rubber bushing with a negligible linear part that firms up under load (held-out seed
    49's EHA mount: k = 10⁵ N/m, k₃ = 10¹¹ N/m³, 0.9–1.5 % effect ESR; at F₅₀ = 10.5 kN it
    deflects 4.7 mm, 45× stiffer than around zero). In the Duffing form F = k·d·(1 + hc·(k·d)²/3)
    it is hc = 3·k₃/k³, hc·F₅₀² ≈ 3·10⁴: inside the hardening's bounds (until session 30 they
    ended at 10³, and the fit went rigid: ``none``), and among the grid's starts (stiffness ×
    the strong shape) one deflects under F₅₀ within a factor two of the bushing, its
    neighbours 3× and more off (a stiffness step of 0.7 decade). Measured on that case: a fit
    from either start nearest the bushing reaches it, though both cost more than the rigid
    spring (the strong shape's cheapest start is a stiff one; the fit of the mild shape's
    cheapest start, workers._fit_starts with basins, is the one that found it in the run)."""
    from scipy.optimize import brentq

    net, _ = with_pressure_sensors(load_netlist(ROOT / "machines" / "eha_testbench.yaml"))
    ctx = Context(net, set(build_model(net).free_params), {}, {})
    f50 = ctx.size(next(iter(ctx.parts(R.ACTUATOR)))) * 5e6
    k_true, k3_true = 1e5, 1e11

    def deflection(k, hc):                      # F(d) = k·d·(1 + hc·(k·d)²/3) = F₅₀
        return brentq(lambda d: k * d * (1 + hc * (k * d) ** 2 / 3) - f50, 0.0, f50 / k)

    d_true = deflection(k_true, 3 * k3_true / k_true ** 3)
    assert d_true == pytest.approx((f50 / k3_true) ** (1 / 3), rel=0.05)     # the cubic carries it
    cand = next(c for c in catalogue(ctx)[0] if c.effect == "structural_flexibility")
    (h,) = [p for p in cand.params if p.name.endswith("_mount.hc")]
    assert h.bounds[0] < 3 * k3_true / k_true ** 3 < h.bounds[1]
    k = cand.params[0]
    strong = [s for s in _log_grid(cand.params) if s[h.name] == max(h.shapes)]
    ratios = [deflection(s[k.name], s[h.name]) / d_true for s in strong]
    near = sorted(abs(np.log(r)) for r in ratios)
    assert near[0] < np.log(2.0) and near[1] > np.log(3.0)


def test_both_seal_laws_are_fitted_once_pressure_dependent_friction_is_shortlisted():
    """Seals loaded by both chambers (the pressure sum) and a piston seal loaded by the
    pressure difference are laws of one effect: with the sum screening first, the difference
    law is fitted too, though it screens last (dev EHA piston seal: the sum, fitted alone,
    ended at μ ≈ 0 and a compliant mount was named; with both laws the seal was named,
    P1 1.07 → 0.238 % against a noise of 0.22 %)."""
    from hydrocli.diagnose.candidates import LAWS
    from hydrocli.diagnose.shortlist import shortlist
    assert "pressure_dependent_friction" in LAWS
    order, scores = _screened(
        ("sum", "force", "pressure_dependent_friction", 0.382), ("orifice", "continuity", "internal_leakage", 0.067),
        ("mount", "force", "structural_flexibility", 0.028), ("link", "force", "load_compliance", 0.018),
        ("dp", "force", "pressure_dependent_friction", 0.002))
    assert [c.key for c in shortlist(order, scores, 3)] == ["sum", "orifice", "mount", "dp", "link"]


def test_a_grown_volume_does_not_withhold_the_model_of_the_compliance_it_reads():
    """``engine.offered``: an effect a candidate modelled is not offered again except in its
    other forms on the same component; a base-fit volume finding (grown chamber volumes named
    line_dynamics) is only a reading of a compliance, so the hose candidates, with the
    inertance and resistance the volume lacks, stay on offer on top of it. Accepted and
    withdrawn keys, and ``only``, are honoured as before."""
    from hydrocli.diagnose.candidates import Candidate
    from hydrocli.diagnose.engine import offered

    def cand(effect, component, variant=""):
        return Candidate(effect, component, [], lambda net: net, "continuity", "", variant=variant)
    line, orifice = cand("line_dynamics", "valve"), cand("internal_leakage", "motor", "orifice")
    laminar, air = cand("internal_leakage", "motor", "laminar"), cand("entrained_air", "motor")
    pool = [line, orifice, laminar, air]
    grown = {"effect": "line_dynamics", "component": "motor", "source": "base_fit",
             "finding": "fluid_compliance_excess"}
    keys = lambda cs: [c.key for c in cs]   # noqa: E731
    assert keys(offered(pool, [grown])) == keys(pool)
    hose = {"effect": "line_dynamics", "component": "valve", "key": line.key, "source": "candidate"}
    assert keys(offered(pool, [grown, hose])) == keys([orifice, laminar, air])
    leak = {"effect": "internal_leakage", "component": "motor", "key": laminar.key, "source": "candidate"}
    assert keys(offered(pool, [leak])) == keys([line, orifice, air])        # its other form stays
    assert keys(offered(pool, [], {air.key}, ("entrained_air", "line_dynamics"))) == keys([line])


def test_a_payload_whose_swing_no_rope_makes_is_implausible():
    """Each of a payload's bounds alone admits a pair no rope makes: a heavy payload on a very
    soft rope swings far slower than a 50 m pendulum (dev winch: a shear-thinning drag answered
    by 105 kg·m² on 0.36 N·m/rad, 0.009 Hz). ``accept.judge`` refuses a fit whose √(k/J)/2π lies
    outside ``payload.F_RANGE``, with the frequency in its reasons; the same fit at a 1 Hz swing
    passes."""
    import math
    from hydrocli.diagnose import accept
    from hydrocli.diagnose.candidates import payload
    from hydrocli.model.builder import build_model
    net = load_netlist(ROOT / "machines" / "hoist_winch.yaml")
    cands, _ = catalogue(Context(net, set(build_model(net).free_params), {"drum_node": (0.0, 8.0)}, {}, {}))
    cand = next(c for c in cands if c.effect == "payload_swing")
    jp, kp, cp = (p.name for p in cand.params[:3])

    def judged(k, j):
        rest = cand.params[3:]                 # the rope's winding and the sheaves' friction, unused
        fit = {"names": [jp, kp, cp, *(q.name for q in rest)], "estimates": [j, k, 50.0, *(q.start for q in rest)],
               "stderr": [0.01 * j, 0.01 * k, 1.0, *(0.01 for _ in rest)], "cost": 0.5}
        return accept.judge(cand, fit, 1.0, 1e4, 3.0, 0.5, 0.4)
    slow = judged(0.36, 105.0)
    assert not slow["passed"] and any("0.0093 Hz is outside" in r for r in slow["reasons"]), slow["reasons"]
    one_hz = judged(20.0 * (2 * math.pi) ** 2, 20.0)
    assert one_hz["passed"], one_hz["reasons"]
    assert payload.F_RANGE[0] < 0.1 and payload._swing_outside(20.0 * (2 * math.pi * 31) ** 2, 20.0)


def test_a_compensated_pump_dips_after_a_demand_and_returns_to_its_set_pressure():
    """The second law of the supply (CircuitFamily._compensator): on the lift, a command step
    at 0.1 s opens the spool at its rate limit over 0.2 s; the rising demand draws the valve's
    supply pressure down (by k·τ·q′ while the flow ramps, the high-pass of the law) and once
    the flow is steady the pump's control brings it back to the set pressure within a few τ
    while the rod still moves, where the restriction law would hold its drop for as long as
    the flow lasts; at its start value the law leaves the machine as it was (≤ 0.01 bar)."""
    from hydrocli.diagnose.candidates import LAWS
    from hydrocli.experiments.experiment import Experiment
    from hydrocli.experiments.initial import initial_state
    from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
    net = load_netlist(ROOT / "machines" / "luffing_cylinder.yaml")
    model0 = build_model(net)
    ps = 1.6e7
    cands, _ = catalogue(Context(net, set(model0.free_params), inputs_start={"Ps": ps}))
    assert "supply_pressure_drop" in LAWS and "supply_pressure_drop@supply" in {c.key for c in cands}
    c = next(c for c in cands if c.key == "supply_pressure_drop@supply#compensator")
    k, tau = c.params
    assert k.primary and not tau.primary and k.start < 1e-3 * k.probe
    model = build_model(c.build(net))
    t = np.arange(0.0, 0.8, 1e-3)
    u = np.zeros((t.size, len(model.input_names)))
    u[:, model.input_names.index("Ps")] = ps
    u[t >= 0.1, model.input_names.index("u")] = 2.0
    e = Experiment("step", "step.csv", InputTable(t, u), t, measured={"x": np.zeros(t.size)})
    ip = model.state_index("supply_line.p")

    def run(kv, tv=0.03):
        p = model.param_vector({k.name: kv, tau.name: tv})
        tr = simulate(model, e.inputs, t, p=p, x0=initial_state(model, e, p), opts=SolverOptions(rtol=1e-7))
        return tr.X[:, ip], tr.X[:, model.state_index("rod.x")]

    off, _ = run(k.start)
    assert np.abs(off - ps).max() < 1e3
    p_v, x = run(k.probe)
    dip = ps - p_v.min()
    assert dip > 1e5                                        # the demand pulls the supply down
    assert abs(p_v[-1] - ps) < 0.02 * dip                   # and the control brings it back
    assert x[-1] - x[600] > 0.05                            # while the rod still moves


def test_held_out_errors_equal_within_the_noise_leave_the_choice_to_training_bic():
    """Dev winch s189, a command through a lag cascade: an input delay (ΔBIC −4068) and a spool's
    hysteresis (−4047) predicted the held-out record to 0.0003 % of each other (band 0.066 %);
    that difference is noise, and the training BIC names the delay. A held-out difference of
    a fifth of the band still decides for the held-out data."""
    from hydrocli.diagnose.ranking import rank_passing as _rank_passing
    hyst = (-4047.0, SimpleNamespace(effect="valve_hysteresis"), {"esr_validation": {"P1": 0.132097, "P2": 0.128612}})
    delay = (-4068.0, SimpleNamespace(effect="input_delay"), {"esr_validation": {"P1": 0.132315, "P2": 0.128700}})
    assert _rank_passing([hyst, delay], band=0.0657)[0] is delay
    assert _rank_passing([hyst, delay])[0] is hyst                         # no band: the held-out order
    clear = (-4047.0, SimpleNamespace(effect="valve_hysteresis"), {"esr_validation": {"P1": 0.119, "P2": 0.128612}})
    assert _rank_passing([clear, delay], band=0.0657)[0] is clear            # 0.0133 % apart: held-out decides
