"""Per-candidate work that runs in worker processes (``--jobs``): build the augmented
model from its YAML text, screen it (score test), and the pieces of its re-identification
(its starts, idle stops; the fits themselves: :mod:`.candidate_fits`). Payloads are plain
picklable data (text, arrays, experiments); compiled models are cached on disk."""
from __future__ import annotations

import numpy as np

from ..model.builder import build_model
from ..netlist.loader import load_netlist_text
from ..progress import status
from . import residuals, stats


def model_from_text(text: str, file: str):
    return build_model(load_netlist_text(text, file))


def warm_vector(model, names: list[str], values: np.ndarray) -> np.ndarray:
    p = model.p0
    idx = {n: i for i, n in enumerate(model.param_names)}
    for n, v in zip(names, values):
        if n in idx:
            p[idx[n]] = v
    return p


def screen_one(job: dict) -> dict:
    """Score test: secant output sensitivities of the new parameters, regressed on the
    current residual after projecting out the current model's own sensitivities."""
    try:
        model = model_from_text(job["text"], job["file"])
        p = warm_vector(model, job["names"], job["values"])
        obj = residuals.objective(model, job["train"])
        for prm in job["params"]:
            p[model.param_index(prm.name)] = prm.start
        r0 = obj.residuals(p)
        # the signature: secants of the parameters that have one (a shape companion probed at its
        # start value only shapes the effect once the amount is there), taken with the companions
        # at their start and at each of their typical shapes
        probed = [prm for prm in job["params"] if prm.probe != prm.start]
        idx = [model.param_index(prm.name) for prm in probed]
        res, best_shape = None, {}
        for shape in _shapes(job["params"]):
            q = model.param_vector(shape, base=p)
            rq = obj.residuals(q) if shape else r0
            columns: dict = {}   # the probes differ in the primary's size only: the rest is shared
            for probe in _probes(probed):
                steps = [probe[prm.name] - prm.start for prm in probed]
                S = residuals.sensitivities(obj, q, idx, steps, rq, memo=columns)
                trial = stats.screen(job["r"], S, job["B"], job["n_eff"])
                if res is None or trial["dr2"] > res["dr2"]:
                    res, best_shape = trial, shape
        step = {prm.name: prm.start - c for prm, c in zip(probed, res["coef"])}   # Gauss–Newton step: r ≈ S·coef
        starts = [{prm.name: prm.start for prm in job["params"]}, {prm.name: prm.probe for prm in job["params"]},
                  {prm.name: float(np.clip(step.get(prm.name, best_shape.get(prm.name, prm.start)), *_inner(prm.bounds)))
                   for prm in job["params"]}]
        starts += _log_grid(job["params"]) + _one_end_probes(job["params"])
        return {"key": job["key"], "dr2": res["dr2"], "t": res["t"].tolist(), "p_value": res["p"], "error": None,
                "starts": starts, "transfers": _transfer_starts(job["params"], model, p)}
    except Exception as exc:  # a candidate that cannot be built or simulated is reported, not fatal
        return {"key": job["key"], "dr2": 0.0, "t": [], "p_value": 1.0, "error": f"{type(exc).__name__}: {exc}"}


def _transfer_starts(params, model, p: np.ndarray) -> list[dict]:
    """The base re-expressed in the candidate's law (:attr:`NewParam.takes_over`): each such
    parameter set to what the base parameter holds (value ** power: a resistance from the
    base's conductance), the base parameter back at its "off" value, the other new parameters
    at their start. None when the base parameter is off (nothing to take over) or when the
    re-expressed value falls outside the parameter's bounds."""
    over = [prm for prm in params if prm.takes_over]
    if not over:
        return []
    start = {prm.name: prm.start for prm in params}
    for prm in over:
        name, off, power = prm.takes_over
        if name not in model.param_names:
            return []
        v = float(p[model.param_index(name)])
        if v == off or not v > 0:
            return []
        held = v ** power
        if not prm.bounds[0] <= held <= prm.bounds[1]:
            return []
        start[prm.name] = held
        start[name] = off
    return [start]


def _probes(probed) -> list[dict]:
    """Where the screening's secant is taken: the declared probe, and — for an effect sized by
    ONE log-scaled primary whose "off" value is zero (a stiffness, a conductance, an amount of
    air) — two more sizes a decade and more apart across its plausible range. A compliance's
    signature is a resonance whose frequency moves with the stiffness: a secant at one size
    can miss an effect of another size that the fit would find (a rod–load link at 2·10⁷ N/m
    probed at 10⁷ against 10¹⁰: scored below a mount that then won), so the best of three
    decides (its Gauss–Newton step is one of the fit's starts)."""
    out = [{prm.name: prm.probe for prm in probed}]
    prim = [prm for prm in probed if prm.primary]
    if len(prim) == 1 and prim[0].log and prim[0].ref == 0 and prim[0].plausible[0] > 0 and not prim[0].scale:
        q = prim[0]
        lo, hi = np.log(q.plausible[0]), np.log(q.plausible[1])
        if hi - lo > np.log(100.0):
            inner = (q.bounds[0] * 1.05, q.bounds[1] / 1.05)
            for f in (1 / 6, 1 / 2, 5 / 6):
                v = float(np.clip(np.exp(lo + f * (hi - lo)), *inner))
                if all(abs(np.log(v / o[q.name])) > np.log(3.0) for o in out) and len(out) < 3:
                    out.append({**out[0], q.name: v})
    return out


def _shapes(params) -> list[dict]:
    """The companions as started ({}), then at each of their typical shapes (the k-th shape of
    every companion that declares some, together)."""
    shaped = [p for p in params if p.shapes]
    return [{}] + [{p.name: p.shapes[k] for p in shaped if k < len(p.shapes)}
                   for k in range(max((len(p.shapes) for p in shaped), default=0))]


def _log_grid(params) -> list[dict]:
    """Extra starts across the PLAUSIBLE range of the primary parameters whose "no effect"
    value is 0 (geometric points, jointly, as many as the densest of them declares
    (``NewParam.grid``); companions at their start). A stiffness,
    conductance or overlap started where the outputs hardly depend on it (a rigid link, a
    closed orifice, a zero-lap spool) has no gradient to follow, and re-identified base
    parameters may already mimic a small effect, so the optimiser must be offered starts
    where the effect is fully visible."""
    grid = [p for p in params if p.primary and p.ref == 0 and not p.scale and p.plausible[0] > 0]
    if not grid:
        return []
    shapes = _shapes(params)
    n = max(p.grid for p in grid)
    out = []
    for f in np.linspace(0, 1, n + 2)[1:-1]:
        d = {p.name: p.start for p in params}
        for p in grid:
            lo, hi = np.log(p.plausible[0]), np.log(p.plausible[1])
            inner = (p.bounds[0] * 1.05, p.bounds[1] / 1.05) if p.log and p.bounds[0] > 0 else _inner(p.bounds)
            d[p.name] = float(np.clip(np.exp(lo + f * (hi - lo)), *inner))
        out.extend({**d, **shape} for shape in shapes)
    return out


def _one_end_probes(params) -> list[dict]:
    """Starts with ONE stop at its probe position and the others out of reach (the rest at
    their probe values). A machine often presses one end of its travel only — a head stop
    reached at the top of a lift, the bottom merely a turning point — and a start that
    puts stops at both recorded ends then costs more than one far past both, where the fit
    stays: the stop the data press is never met (concealed end-stop bench: x_max started
    5 mm beyond the head stop ended there, cost 0.127 against 0.077 from the head alone).
    Each is also offered at the companions' typical shapes (a soft bumper's stiffness)."""
    ends = [p for p in params if p.seen]
    if len(ends) < 2:
        return []
    return [{**{p.name: (p.start if (p.seen and p is not end) else p.probe) for p in params}, **shape}
            for end in ends for shape in _shapes(params)]


def _inner(bounds, margin=0.02):
    lo, hi = bounds
    return lo + margin * (hi - lo), hi - margin * (hi - lo)


IDLE_STOP = 0.01       # share of the travel seen a stop must sit beyond it to count as never pressed


def withdraw_idle_stops(obj, model, res, stops: list[dict]) -> list[str]:
    """Stops the training data never press, moved out of reach (in place in ``res``).

    A stop fitted beyond every position recorded (by more than IDLE_STOP of the travel seen)
    was never pressed by the machine: pressed, it would have been compressed, and the record
    would reach past it. If the fit still leans on it, it does so where the simulated
    trajectory strays from the record (an open-loop drift held by a stop that is not there),
    and a held-out run that goes a little further meets a stop the data never showed. It is
    moved to its outer bound, out of reach, and the cost is the withdrawn model's (ΔBIC is
    judged on what is kept). ``stops``: {name, start, seen (min, max), bounds, scale} of the
    candidate's stop positions."""
    q = np.array(res.p, dtype=float)
    names = []
    for s in stops:
        i = model.param_index(s["name"])
        lo, hi = s["seen"]
        tol = IDLE_STOP * s["scale"]
        if s["start"] < lo and q[i] < lo - tol:
            q[i], _ = s["bounds"]
        elif s["start"] > hi and q[i] > hi + tol:
            _, q[i] = s["bounds"]
        else:
            continue
        names.append(s["name"])
    if not names:
        return []
    c0, c1 = obj.cost(np.asarray(res.p, dtype=float)), obj.cost(q)
    res.cost = res.cost * c1 / c0 if c0 > 0 else c1
    res.p = q
    res.estimates = np.array([q[model.param_index(n)] for n in res.names])
    return names


def parameter_rows(params, estimates: dict[str, float], stderr: dict[str, float], withdrawn) -> list[dict]:
    """A candidate's new parameters as diagnosis.json lists them, the withdrawn stops marked."""
    idle = set(withdrawn)
    return [{"name": p.name, "value": estimates[p.name], "stderr": stderr.get(p.name), "plausible": list(p.plausible)}
            | ({"withdrawn": "pressed by nothing in the training data: moved out of reach"} if p.name in idle else {})
            for p in params if p.name in estimates]


def _fit_starts(obj, p: np.ndarray, model, starts: list[dict], drawn: np.ndarray | None = None,
                each_base: bool = False, basins: dict[str, tuple[float, ...]] | None = None,
                transfers: list[dict] | None = None, stops: list[dict] | None = None) -> list[np.ndarray]:
    """Where a candidate's fit starts: the start of lowest cost, and — when that is the effect
    switched off (``starts[0]``, as :func:`screen_one` lists them) — also the best start with
    the effect present. Base parameters re-identified without the effect may already mimic
    part of it (a Stribeck term widened into a Coulomb one): adding the effect on top of them
    costs more at first, and a fit from "off" then stays in the base's local minimum. Both
    fits run; the lower final cost wins.

    Every start is offered twice: on the current fit's base parameters ``p`` and on the
    machine as drawn (``drawn``: the file's values of the base parameters). A base fit that
    lacks a strong effect can wander far from the drawing to imitate it (dev rotary with much
    air and a low-supply test: inertia ×0.23, viscous friction ×8, train ESR of speed 20 %);
    from there the effect's own fit stays in that basin, while from the drawing — which
    differs from the machine by its tolerances — the effect is where the data put it.

    ``each_base``: the best start with the effect present is fitted from EACH base as well. A
    compliance adds a mode whose frequency is set by its stiffness together with the base's
    masses and volumes, and a base fit without it bends those (chamber volume ×2.6, load mass
    ×0.42 against a hose): from the bent base the new stiffness tunes a mode in the wrong place
    and the fit stays in that minimum (dev lift, hoses: ΔBIC −78), from the drawing it finds the
    mode the data hold (−3086). The cost of a start, a single simulation, cannot tell the two
    basins apart: both are far from the record until the fit has moved.

    ``basins``: {parameter: its shapes} of companions whose shapes are basins of their own
    (:attr:`NewParam.basins`): the best start at each shape value is fitted as well. For a
    bushing nearly free around zero and firm under load, the cost rises so steeply with the
    deflection under load that the rigid start is the cheapest of all (held-out seed 49's EHA
    mount: rigid 0.036; the strong-hardening starts nearest the bushing, 1.8× and 2.9× off in
    deflection, 0.048 and 0.050), and the cheapest start with the effect present is a
    near-rigid one: both fits went rigid. With the best start of each shape fitted as well,
    the bushing is found (k within 5 %, k₃ and the frame mass within 40 % of the truth, ΔBIC
    −14 900) — measured, by the mild shape's best start: with the strong shape's alone (a
    stiff spring, k 2·10⁶ N/m, the cheapest of that shape) the answer stays ``none``.

    ``stops``: the candidate's stop positions ({name, start}, :func:`stage.stops_of`): each
    end pressed alone (the other at its start, out of reach) is a basin of its own at each
    shape, and the best start of each is fitted. A machine pressing one end only, started with
    a soft bumper at the wrong end, never meets the one it presses: seed 64's vane
    bumper (3000 N·m/rad at 0.50 rad) ended on a stiff stop at 0.517 rad, 2.6·10¹⁰ N·m/rad,
    while from the soft start at the upper end it is found (3068 N·m/rad at 0.4999 rad).

    ``transfers``: the current base re-expressed in the candidate's law
    (:func:`_transfer_starts`), fitted whatever they cost: a shared leak the base found, put on
    each seal, costs what the base costs, and a cheaper start that adds a little leak on top of
    it ends in the base's minimum."""
    bases = [p] + ([drawn] if drawn is not None and not np.array_equal(drawn, p) else [])
    vecs = []                                # (cost, vector, effect off)
    for b in bases:
        for k, start in enumerate(starts):
            q = model.param_vector(start, base=b)
            vecs.append((obj.cost(q), q, k == 0))
    order = sorted(range(len(vecs)), key=lambda i: vecs[i][0])
    best = vecs[order[0]]
    out = [best[1]]
    if best[2] and len(starts) > 1:
        on = [i for i in order[1:] if not vecs[i][2] and not np.array_equal(vecs[i][1], best[1])]
        if on:
            out.append(vecs[on[0]][1])
    n = len(starts)

    def add_cheapest(picked):
        """The cheapest start with the effect present among ``picked`` (start indices), unless
        already chosen."""
        on = [i for i in order if i % n != 0 and picked(i)]
        if on and not any(np.array_equal(vecs[on[0]][1], q) for q in out):
            out.append(vecs[on[0]][1])

    ends = [{s["name"]: s["start"] for s in stops if s is not end} for end in stops or []] or [{}]
    for name, values in (basins or {}).items():
        for v in values:
            for off in ends:
                add_cheapest(lambda i: starts[i % n].get(name) == v
                             and all(starts[i % n].get(e) == x for e, x in off.items()))
    if each_base and n > 1:
        for j in range(len(bases)):
            add_cheapest(lambda i: i // n == j)
    for start in transfers or []:
        q = model.param_vector(start, base=p)
        if not any(np.array_equal(q, o) for o in out):
            out.append(q)
    return out


def run_all(fn, jobs: list[dict], pool=None, progress=None, what: str = "done") -> list[dict]:
    """``fn`` over ``jobs`` on the diagnosis's executor (identify's: a process pool, or a Dask
    client when a scheduler was named), in this process when there is none; results in the
    jobs' order, ``progress``'s status told "what k/n" as they complete."""
    n = len(jobs)
    status(progress, f"{what} 0/{n}")
    if pool is None or n <= 1:
        out = []
        for k, j in enumerate(jobs, 1):
            out.append(fn(j))
            status(progress, f"{what} {k}/{n}")
        return out
    if hasattr(pool, "gather"):          # dask.distributed.Client
        from distributed import as_completed

        def completed(fs):
            # the executor's client is not the process's default one (set_as_default=False):
            # without its loop, as_completed looks for a default client and fails
            return as_completed(fs, loop=pool.loop)
        futures = [pool.submit(fn, j, pure=False) for j in jobs]
    else:
        from concurrent.futures import as_completed as completed
        futures = [pool.submit(fn, j) for j in jobs]
    for k, _ in enumerate(completed(futures), 1):
        status(progress, f"{what} {k}/{n}")
    return [f.result() for f in futures]
