"""Verdicts that do not come from an added candidate.

* **Base-fit findings** (DESIGN.md: ``source: base_fit``). A machine file may already carry an
  effect's parameter FREE from its "no effect" value (``c_el: {value: 0, free: true}``). When
  the base fit moves it to a plausible, well-determined value that the held-out data need,
  the effect IS present: the fit found it. Judged with the catalogue's own data (the
  candidate that would set that parameter free gives its "off" value ``ref`` and plausibility
  range) and the acceptance rule's standards: |θ̂ − ref| inside the plausible range,
  > ``Z_MIN`` inflated standard errors from ref, and switching it back off worsens the
  validation ESR by more than a share of the error above the noise (:func:`accept.need` with
  ``selected=False``: a declared parameter carries no look-elsewhere margin).
* **Fluid compliance in excess** (:func:`fluid_compliance_excess`): the base fit needs a
  chamber's volume ×1.5 or more of the drawing's and every chamber's grown alike, well
  determined — entrained air (or a hose volume the file lacks), ``source: base_fit``.
* **Unexplained mismatch**. Nothing passes, yet some output's validation ESR stays above its
  noise floor by more than ``MISMATCH_ESR`` and by more than the floor itself: the model is
  missing something the catalogue cannot express. Said so, with where it lies (outputs,
  regimes, windows), never a bare ``none``. When the held-out recordings move beyond the
  positions the training recordings cover (:func:`beyond_training`), that is said too: what
  is missing may act only where training never went (an end stop, a position-dependent
  load), and no fit to the training data can find it — a training recording over that range
  is what is needed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

Z_MIN = 3.0          # a finding must sit this many (inflated) standard errors from "off"
MISMATCH_ESR = 1.0   # % validation ESR above the noise floor that the benchmark calls detectable
BEYOND = 0.05        # held-out positions further than this share of the training span outside it
EXCESS = 1.5         # × the file's chamber volume in every chamber: more than a drawing's tolerance
ALIKE = 0.5          # or one chamber ×EXCESS and every other grown by this share of its growth: alike
EXCESS_FINDING = "fluid_compliance_excess"   # the finding's ``finding`` key (restrained and tested: engine)


@dataclass(frozen=True)
class OffValue:
    """What the catalogue says about a parameter that is an effect's own: the effect, the
    value meaning "no effect" and the plausible |θ − ref| range."""
    effect: str
    component: str
    ref: float
    plausible: tuple[float, float]
    primary: bool


def off_values(cands) -> dict[str, OffValue]:
    """{parameter: OffValue} from catalogue candidates built as if nothing were free."""
    out = {}
    for c in cands:
        for p in c.params:
            if p.scale:          # positions (stops) have no "off" value
                continue
            out.setdefault(p.name, OffValue(c.effect, c.component, p.ref, p.plausible, p.primary))
    return out


def base_fit_findings(judged: list[dict], offs: dict[str, OffValue], gain_of) -> list[dict]:
    """Effects the base fit found. ``judged``: baseline.judge rows (name, value, initial,
    stderr); ``gain_of(names) -> (gain %, need %)``: validation ESR gain of the fitted model
    over the same model with those parameters back at "off", and the noise band it must
    beat."""
    groups: dict[tuple[str, str], list[tuple[dict, OffValue]]] = {}
    for j in judged:
        off = offs.get(j["name"])
        if off is None or not np.isclose(j["initial"], off.ref, rtol=0.0, atol=1e-3 * off.plausible[0]):
            continue
        groups.setdefault((off.effect, off.component), []).append((j, off))
    found = []
    for (effect, comp), rows in groups.items():
        moved = [(j, off) for j, off in rows if off.primary and _determined(j, off)]
        if not moved:
            continue
        gain, need = gain_of([j["name"] for j, _ in rows])
        if not gain > need:
            continue
        found.append({"effect": effect, "component": comp, "source": "base_fit",
                      "parameters": [{"name": j["name"], "value": j["value"], "stderr": j["stderr"],
                                      "file_value": j["initial"], "plausible": list(off.plausible)}
                                     for j, off in rows],
                      "validation_gain": gain, "noise_band": need,
                      "description": f"the base fit moved {', '.join(j['name'] for j, _ in moved)} off its "
                                     f"'no effect' value to a well-determined one the held-out data need"})
    return found


@dataclass(frozen=True)
class Feeder:
    """A free volume on a chamber's side of the circuit (found by :func:`.sides.feeders`): its
    volume and bulk-modulus parameters, and their file values."""

    volume: str
    modulus: str
    volume_file: float
    modulus_file: float


@dataclass(frozen=True)
class Chambers:
    """An actuator's chamber volumes at the reference position (role slot ``dead_volumes``),
    its oil's bulk modulus (slot ``bulk_modulus``), and per chamber the free volumes on that
    side of the circuit (:func:`.sides.feeders`)."""
    component: str
    volumes: tuple[str, ...]
    modulus: str | None = None
    feeders: tuple[tuple[Feeder, ...], ...] = ()
    modulus_file: float = float("nan")     # the file's bulk modulus (used when it is not free)


def fluid_compliance_excess(judged: list[dict], actuators: list[Chambers], gain_of) -> list[dict]:
    """Entrained air found by the base fit through the chambers' volumes. A vane's or a
    cylinder's volume at the reference position is a drawing dimension (chamber, ports,
    fittings). When the base fit needs ``EXCESS`` × or more of it in one chamber and EVERY
    chamber grown alike (:func:`grown_alike`), well determined (> ``Z_MIN`` standard errors
    from the file's value), the chambers hold a
    compliance the oil in the drawn volumes cannot: a compliance in each chamber that does not
    scale with the stroke — free air in the oil (or hose volume the file leaves out, named as
    the alternative). A compliant mount or rod–load link cannot stand in for it: a spring in
    series with the motion adds compliance only BETWEEN the chambers (their pressure
    difference drives it), not to both. ``gain_of({name: value}) -> (gain %, need %)``: the
    validation ESR lost when the volumes go back to the file's values, and the band it must
    beat (``accept.need``, ``selected=False``)."""
    rows = {j["name"]: j for j in judged}
    found = []
    for act in actuators:
        js = [rows.get(n) for n in act.volumes]
        if len(js) < 2 or any(j is None for j in js):
            continue
        if not grown_alike(net_of_feeders(act, js, rows)):
            continue
        found += _volume_finding(act, js, gain_of, "entrained_air", "line_dynamics", EXCESS_FINDING,
                                 lambda ratios: "the base fit needs more fluid compliance in every chamber "
                                                f"of '{act.component}' than oil in the drawn volumes has "
                                                f"({ratios}): free air in the oil, or hose volume the file "
                                                "leaves out")
    return found


def undrawn_volume(judged: list[dict], actuators: list[Chambers], gain_of) -> list[dict]:
    """Fluid volume the drawing leaves out on ONE side: the base fit needs ``EXCESS`` × or more
    of the drawn volume, well determined, in some chamber of an actuator, but the chambers are
    not grown alike (:func:`grown_alike`). A
    chamber's volume at the reference position is a drawing dimension; what the oil between the
    valve and that chamber adds beyond it is the hose or pipe on that side (its volume is what a
    line does at the frequencies a commissioning test excites; its inertance and resistance come
    later), so the effect is ``line_dynamics`` with free air trapped on that side as the
    alternative. Air carried by the oil would soften every chamber (:func:`fluid_compliance_excess`).

    A grown volume also stands in for other effects — a rod–load link on a gravity-loaded
    cylinder puts its compliance on the loaded side, a delayed command is mimicked by slower
    pressure build-up — so this finding comes LAST: judged on the final model, after the
    catalogue's candidates had their chance to take the volume back to the drawing's
    (``engine.diagnose``). ``gain_of({name: value}) -> (gain %, need %)`` as there."""
    rows = {j["name"]: j for j in judged}
    found = []
    for act in actuators:
        js = [rows.get(n) for n in act.volumes]
        if any(j is None for j in js):
            continue
        net = net_of_feeders(act, js, rows)
        grown = [j for j, n in zip(js, net) if _grown(n)]
        if not grown or grown_alike(net):
            continue
        found += _volume_finding(act, grown, gain_of, "line_dynamics", "entrained_air", "undrawn_volume",
                                 lambda ratios: f"the fit needs more fluid volume on one side of "
                                                f"'{act.component}' than the drawing has ({ratios}): a hose "
                                                "or pipe between the valve and that chamber the file leaves "
                                                "out, or air trapped there")
    return found


def _volume_finding(act: Chambers, grown: list[dict], gain_of, effect: str, alternative: str, kind: str,
                    describe) -> list[dict]:
    """[the finding] when the held-out data need the ``grown`` volumes (back at the drawing's,
    the validation ESR rises by more than the band), else []. ``describe(ratios)`` words it,
    given "V_A0 ×3.1, …"."""
    gain, need = gain_of({j["name"]: j["initial"] for j in grown})
    if not gain > need:
        return []
    ratios = ", ".join(f"{j['name']} ×{j['value'] / j['initial']:.2g}" for j in grown)
    return [{"effect": effect, "component": act.component, "source": "base_fit", "finding": kind,
             "parameters": [{"name": j["name"], "value": j["value"], "stderr": j["stderr"],
                             "file_value": j["initial"]} for j in grown],
             "validation_gain": gain, "noise_band": need, "alternatives": [alternative],
             "description": describe(ratios)}]


def net_of_feeders(act: Chambers, js: list[dict], rows: dict[str, dict]) -> list[dict]:
    """The chambers' fitted volumes less the compliance the fit took from the free volumes on
    the same side (:mod:`.sides`), as oil at the chamber's fitted bulk modulus:
    V_net = V − β·Σ(V_f,file/β_f,file − V_f/β_f). Growing a chamber by what the line beyond a
    counterbalance valve lost keeps the side's compliance what the drawing has: no fluid is
    missing (dev counterbalanced lift, null case: V_A0 ×1.70 while the line's 0.3 L went to
    its 0.05 L bound at a stiffer modulus, ×1.09 net). Only a loss counts: a feeder the fit
    grew is not chamber volume. Rows without feeders come back unchanged."""
    mod = rows.get(act.modulus) if act.modulus else None
    beta = mod["value"] if mod else act.modulus_file
    out = []
    for j, side in zip(js, act.feeders or [()] * len(js)):
        if not side:
            out.append(j)
            continue
        taken = 0.0
        for f in side:
            v = rows.get(f.volume)
            b = rows.get(f.modulus)
            v_fit = v["value"] if v else f.volume_file
            b_file = f.modulus_file if np.isfinite(f.modulus_file) else beta
            b_fit = b["value"] if b else b_file
            taken += f.volume_file / b_file - v_fit / b_fit
        taken = taken * beta if np.isfinite(beta) and np.isfinite(taken) else 0.0
        out.append(dict(j, value=j["value"] - taken) if taken > 0 else j)
    return out


def grown_alike(js: list[dict]) -> bool:
    """Every chamber of an actuator grown: each by ``EXCESS`` × or more of the drawing's
    volume, or one by that much and every other by at least ``ALIKE`` of its growth, each well
    determined. Air carried by the oil softens every chamber (more where the pressure is
    lower), a hose grows the side it feeds and leaves the other at the drawing's (within its
    tolerance). Read chamber by chamber against the one cut, free air that grew one chamber
    ×1.57 and the other ×1.49 was a hose on one side (dev rotary, isothermal dissolving air,
    seeds 34 and 37), while a one-sided hose leaves the other chamber at ×1.0–1.4 of a ×1.7–5
    growth (dev lifts)."""
    if all(_grown(j) for j in js):
        return True
    if not any(_grown(j) for j in js):
        return False
    top = max(j["value"] / j["initial"] for j in js) - 1.0
    return all(_above_drawing(j) and j["value"] / j["initial"] - 1.0 >= ALIKE * top for j in js)


def _grown(j: dict) -> bool:
    """Grown ``EXCESS`` × or more of the drawing's volume, well determined."""
    return _above_drawing(j) and j["value"] >= EXCESS * j["initial"]


def _above_drawing(j: dict) -> bool:
    """Above the drawing's volume by more than ``Z_MIN`` standard errors."""
    v, v0, se = j["value"], j["initial"], j["stderr"]
    return v0 > 0 and np.isfinite(se) and v - v0 > Z_MIN * se


def _determined(j: dict, off: OffValue) -> bool:
    size = abs(j["value"] - off.ref)
    se = j["stderr"]
    return (off.plausible[0] <= size <= off.plausible[1] and np.isfinite(se)
            and size > Z_MIN * se)


def unexplained(esr_validation: dict, noise: dict, located: dict) -> dict | None:
    """Where the validation error stays above the noise floor, or None when it does not."""
    excess = {o: esr_validation[o] - noise.get(o, 0.0) for o in esr_validation}
    outs = {o: e for o, e in excess.items() if e > max(MISMATCH_ESR, noise.get(o, 0.0))}
    if not outs:
        return None
    return {"outputs": {o: {"esr_validation": esr_validation[o], "noise_floor": noise.get(o, 0.0)}
                        for o in sorted(outs, key=lambda k: -outs[k])},
            "regimes": [r for r in located.get("regimes", []) if r.get("concentration", 0) > 1.2][:3],
            "windows": located.get("windows", [])[:3]}


def beyond_training(train: dict[str, tuple[float, float]], validate: dict[str, tuple[float, float]]) -> dict:
    """{position/angle output: {"train": [lo, hi], "validate": [lo, hi]}} for the outputs whose
    held-out range leaves the training range by more than ``BEYOND`` of the training span."""
    out = {}
    for o, (vlo, vhi) in validate.items():
        if o not in train:
            continue
        tlo, thi = train[o]
        margin = BEYOND * max(thi - tlo, 0.0)
        if vhi > thi + margin or vlo < tlo - margin:
            out[o] = {"train": [tlo, thi], "validate": [vlo, vhi]}
    return out
