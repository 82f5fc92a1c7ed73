"""A discriminating experiment for two candidates the data cannot tell apart.

When two effects fit the recordings equally well (ΔBIC and validation gain within the
margin; e.g. entrained air and a compliant mount: both soften the chamber–load stiffness
over the pressures seen), the diagnosis proposes a test that separates them — what a
commissioning engineer would do by hand (a slow pressure ramp at standstill shows whether a
stiffness depends on pressure; a low-frequency small-amplitude sine shows a dead band or a
compliance without exciting the rest).

Method (optimal input design by simulation, Ljung 1999 §13; Atkinson & Fedorov 1975 for
T-optimal model discrimination): a small family of designed experiments is built from the
machine's own inputs and the ranges the training data visited (the command input of each
metering valve moves; the others are held or ramped over their recorded range). Both fitted
candidate models are simulated on every design, and the design with the largest predicted
discrimination Σ_o N·(RMS(ŷ_a − ŷ_b)/σ_o)² (the χ² a likelihood-ratio test between the two
models would see, σ_o the output's measurement noise) is written as an experiment YAML with
designed signals, next to the predicted difference per output.

A difference predicted with both models' parameters held at their current fits overstates
what the test will show: once recorded, both models are re-fitted with it, and the rival
adapts (session 4: a 5 Hz sine predicted χ² ≈ 5300 between air and a compliant coupling; after
both re-fitted on its recording they predicted it within 0.1 % ESR). T-optimality proper
(Atkinson & Fedorov 1975) scores a design by what is left after the rival is RE-FITTED to the
winner's prediction: min over θ_b of Σ‖η_a(d) − η_b(d, θ_b)‖²/σ², the rival keeping its fit
to the training data. With ``refit_iterations`` > 0 the ``REFIT_TOP`` designs of largest
held-parameter discrimination are scored so (the rival re-identified on the training
experiments plus the winner's noise-free prediction of the design, from its current fit),
and the best of them after the refit is proposed; ``discrimination`` is then the after-refit
χ², ``discrimination_held`` the held-parameter one.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..components import registry
from ..components import roles as R
from ..errors import HydroError
from ..netlist import yamldoc as Y
from ..units import from_si

DURATION = 12.0    # s of each designed test
RATE = 500.0       # Hz
SUPPLY_LEVELS = (1.0, 0.6, 0.35)   # shares of the recorded supply pressure in the pressure-level test
REFIT_TOP = 3      # designs scored after re-fitting the rival
MAX_STEP = 2.0 / RATE   # s: designs hold an input for seconds and then change it within 10 ms; the
                        # diagnosis's loose nominal-tolerance integration (residuals.OPTS) can step
                        # across such a change after a long hold (a two-lag chain on the step design:
                        # 0.46 off at rtol 1e-5, exact at 1e-8), so designs are simulated with steps
                        # no longer than two samples


@dataclass(frozen=True)
class Design:
    name: str
    description: str
    inputs: dict[str, object]      # machine input → YAML signal (in the input's declared unit)


def command_inputs(net) -> set[str]:
    """Machine inputs that drive a metering valve's command (by role)."""
    return _inputs_on(net, R.METERING_VALVE, "command")


def supply_inputs(net) -> set[str]:
    """Machine inputs that set a pressure source's pressure (by role): the supply."""
    return _inputs_on(net, R.PRESSURE_SOURCE, "reference")


def _inputs_on(net, role_name: str, slot: str) -> set[str]:
    """Machine inputs connected to the ``slot`` port of components offering ``role_name``."""
    out = set()
    for d in net.components.values():
        cls = registry.get(d.type)
        role = cls.role(role_name) if cls is not None else None
        if role is not None and role.port(slot) in d.ports:
            node = d.ports[role.port(slot)]
            if node in net.inputs:
                out.add(node)
    return out


def _stats(model, train) -> dict[str, tuple[float, float, float, float]]:
    """Per input (SI): mean, std, min, max over the training experiments."""
    out = {}
    for j, n in enumerate(model.input_names):
        u = np.concatenate([e.inputs.U[:, j] for e in train])
        out[n] = (float(np.mean(u)), float(np.std(u)), float(np.min(u)), float(np.max(u)))
    return out


def designs(model, net, train) -> list[Design]:
    """The candidate tests: sines of the command at three frequencies and two amplitudes,
    command steps, and a slow ramp of each other input over its recorded range at a held
    command (standstill)."""
    st = _stats(model, train)
    cmds = command_inputs(net) or set(model.input_names[:1])
    unit = model.input_units

    def val(n, v):
        return float(from_si(v, unit[n])) if unit.get(n) else float(v)

    def held(except_=()):
        return {n: val(n, st[n][0]) for n in model.input_names if n not in except_}

    # the command's "centre": where the actuator holds (the median command of the training data)
    centre = {n: float(np.median(np.concatenate([e.inputs.U[:, model.input_names.index(n)] for e in train])))
              for n in cmds}

    def sines(frac, f):
        """Every input held at its mean, each command a sine of ``frac``·std around its centre."""
        ins = held(cmds)
        for n in cmds:
            ins[n] = {"sine": {"amplitude": val(n, frac * st[n][1]) - val(n, 0.0), "frequency": f"{f} Hz",
                               "offset": val(n, centre[n])}}
        return ins

    out = []
    for frac in (0.1, 0.3):
        for f in (0.2, 1.0, 5.0):
            ins = sines(frac, f)
            out.append(Design(f"sine_{f:g}Hz_{int(100 * frac)}", f"command sine, {f:g} Hz, {frac:g}·std of the "
                              "recorded command around its median, other inputs held at their means", ins))
    ins = held(cmds)
    for n in cmds:
        a = val(n, centre[n] + 0.3 * st[n][1])
        b = val(n, centre[n] - 0.3 * st[n][1])
        c = val(n, centre[n])
        ins[n] = {"table": {"t": [0, 2, 2.01, 4, 4.01, 6, 6.01, 8, 8.01, DURATION],
                            "values": [c, c, a, a, c, c, b, b, c, c]}}
    out.append(Design("command_steps", "command steps of ±0.3·std around its median, held 2 s each", ins))
    # the same small sine with the supply lowered in steps (a relief valve set lower: always
    # safe for the machine): a stiffness that depends on pressure — undissolved air, which
    # softens as the chamber pressure falls (Gholizadeh, Burton & Schoenau 2011) — moves the
    # response between the levels; a mount's or a link's does not. The levels are shares of
    # the recorded supply (a load the machine holds with a third of its supply stays held)
    supplies = sorted(supply_inputs(net) & set(model.input_names))
    for f in (1.0, 5.0) if supplies else ():
        ins = sines(0.1, f)
        for n in supplies:
            ins[n] = {"table": _levels([val(n, st[n][0] * k) for k in SUPPLY_LEVELS])}
        out.append(Design(f"sine_{f:g}Hz_supply_levels",
                          f"command sine, {f:g} Hz, 0.1·std of the recorded command around its median, the supply "
                          "pressure held at " + ", ".join(f"{k:g}" for k in SUPPLY_LEVELS) + " of its recorded "
                          "mean in turn: shows whether a stiffness depends on pressure", ins))
    for other in (n for n in model.input_names if n not in cmds):
        lo, hi = st[other][2], st[other][3]
        if hi - lo <= 1e-12 * max(abs(hi), 1.0):
            continue
        ins = held((other,) + tuple(cmds))
        for n in cmds:
            ins[n] = val(n, centre[n])
        ins[other] = {"table": {"t": [0, 1, DURATION / 2, DURATION - 1, DURATION],
                                "values": [val(other, lo), val(other, lo), val(other, hi), val(other, lo), val(other, lo)]}}
        out.append(Design(f"ramp_{other}", f"slow ramp of '{other}' over its recorded range and back, the "
                          "command held at its median (standstill): shows whether a stiffness depends on pressure", ins))
    return out


def _levels(values: list[float], ramp: float = 0.5) -> dict:
    """A table holding each value for an equal share of the test, ramping between them in
    ``ramp`` seconds."""
    span = DURATION / len(values)
    t, out = [0.0], [values[0]]
    for k, v in enumerate(values):
        if k:
            t.append(k * span + ramp)
            out.append(v)
        t.append((k + 1) * span)
        out.append(v)
    return {"t": t, "values": out}


def experiment_text(d: Design, machine_name: str, effects: tuple[str, ...] = ()) -> str:
    decide = "".join(f" --only {e}" for e in effects)
    doc = {"name": f"discriminate_{d.name}",
           "description": f"proposed by hydro diagnose for {machine_name}: {d.description}. Record the machine's "
                          "outputs on it, add a 'data:' file and 'outputs:' mapping, and diagnose again with it "
                          "among the training experiments" + (f" ({decide.strip()} to decide between them)" if decide
                                                              else "") + ".",
           "duration": f"{DURATION:g} s", "rate": f"{RATE:g} Hz", "inputs": d.inputs}
    return Y.dump_text(doc)


def _simulate(model, p, exp) -> np.ndarray | None:
    from ..experiments.initial import initial_state
    from ..solve.simulate import simulate
    try:
        return simulate(model, exp.inputs, exp.t_out, p=p, x0=initial_state(model, exp, p), opts=_opts()).Y
    except HydroError:
        return None


def _opts():
    from .residuals import OPTS
    return replace(OPTS, max_step=MAX_STEP)


def _compared(ma, mb, noise_sigma: dict[str, float]) -> list[str]:
    """Outputs both models have and whose measurement noise is known."""
    return [o for o, s in noise_sigma.items() if o in ma.output_names and o in mb.output_names and s > 0]


def _discrimination(ma, ya, mb, yb, noise_sigma: dict[str, float]) -> tuple[float, dict, dict, float]:
    """Σ_o N·(RMS(ŷ_a − ŷ_b)/σ_o)², per output the RMS difference (SI) and RMS/σ, and the ESR
    gap Σ_o 100·mean((ŷ_a − ŷ_b)²)/var(ŷ_a): how much worse than ``a`` model ``b`` would score
    on the test if ``a`` were right — the measure the diagnosis decides on (ranking.separated)."""
    diff, z, score, gap = {}, {}, 0.0, 0.0
    for o in _compared(ma, mb, noise_sigma):
        s = noise_sigma[o]
        ref = ya[:, ma.output_names.index(o)]
        dy = ref - yb[:, mb.output_names.index(o)]
        rms = float(np.sqrt(np.mean(dy ** 2)))
        diff[o], z[o] = rms, rms / s
        score += dy.size * (rms / s) ** 2
        gap += 100.0 * rms ** 2 / max(float(np.var(ref)), 1e-300)
    return score, diff, z, gap


def _after_refit(a, b, train, eb, ya, noise_sigma: dict[str, float], iterations: int):
    """The rival ``b`` re-identified on the training experiments plus the winner's noise-free
    prediction ``ya`` of the design (experiment ``eb``), from its current fit; what it still
    misses of that prediction."""
    from . import baseline
    (_, ma, _), (_, mb, pb) = a, b
    outs = _compared(ma, mb, noise_sigma)
    synth = replace(eb, measured={o: ya[:, ma.output_names.index(o)] for o in outs}, mask={}, fit_outputs=outs)
    res = baseline.identify(mb, list(train) + [synth], p_start=pb, iterations=iterations, opts=_opts())
    yb = _simulate(mb, res.p, synth)
    return None if yb is None else _discrimination(ma, ya, mb, yb, noise_sigma)


def propose(a, b, net, train, noise_sigma: dict[str, float], workdir: Path, machine_name: str,
            refit_iterations: int = 0, band: float | None = None) -> dict | None:
    """The design that separates the fitted candidates ``a`` and ``b`` best. Each is
    (name, model, p). Returns {"name", "description", "text", "discrimination",
    "predicted_difference": {output: RMS difference in SI}, "z": {output: RMS/σ},
    "esr_gap": summed ESR % by which b would miss a's prediction} or None; with
    ``refit_iterations`` also "discrimination_held" (see the module docstring); with ``band``
    (the noise band the diagnosis decides with) "decisive": whether the chosen test's ESR gap
    exceeds it — if not, recording it will not let the re-diagnosis tell them apart, and the
    pair is honestly undecidable with these tests. The test is chosen by χ², not by the ESR
    gap: a test at standstill has a tiny output variance, so a small difference is a large
    ESR gap there, but its recording is mostly noise and, weighted by that small variance in
    the ESR-scaled fit, it would dominate the re-identification (measured: air then no
    longer identifiable at all)."""
    from ..experiments.experiment_file import load_experiment_file
    (_, ma, pa), (_, mb, pb) = a, b
    scored = []
    workdir.mkdir(parents=True, exist_ok=True)
    for d in designs(ma, net, train):
        path = workdir / f"design_{d.name}.yaml"
        text = experiment_text(d, machine_name, (a[0], b[0]))
        path.write_text(text)
        try:
            ea, eb = load_experiment_file(path, ma), load_experiment_file(path, mb)
        except HydroError:
            continue
        ya, yb = _simulate(ma, pa, ea), _simulate(mb, pb, eb)
        if ya is None or yb is None:
            continue
        score, diff, z, gap = _discrimination(ma, ya, mb, yb, noise_sigma)
        scored.append(({"name": d.name, "description": d.description, "text": text, "discrimination": score,
                        "predicted_difference": diff, "z": z, "esr_gap": gap}, eb, ya))
    if not scored:
        return None
    scored.sort(key=lambda x: -x[0]["discrimination"])
    best = scored[0][0] if refit_iterations <= 0 else None
    for prop, eb, ya in (scored[:REFIT_TOP] if refit_iterations > 0 else []):
        after = _after_refit(a, b, train, eb, ya, noise_sigma, refit_iterations)
        if after is None:
            continue
        prop = dict(prop, discrimination_held=prop["discrimination"], discrimination=after[0],
                    predicted_difference=after[1], z=after[2], esr_gap=after[3])
        if best is None or prop["discrimination"] > best["discrimination"]:
            best = prop
    if best is not None and band is not None:
        best = dict(best, band=band, decisive=bool(best["esr_gap"] > band))
    return best
