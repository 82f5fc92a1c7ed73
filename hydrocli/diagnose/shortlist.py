"""Which screened candidates a round re-identifies (:func:`shortlist`): the best form of
the best effects, rivals from other balances, every law of a leak, and the other members of
a group whose members a score test ranks poorly against each other; what is left for the
next wave when none of them passes (:func:`after_wave`); the friction laws that a
compliance fitted as a creep stands for (:func:`creeping`); and the stops, when what nothing
explains lies at the ends of the stroke (:func:`at_the_ends`)."""
from __future__ import annotations

from .candidates import BANDS, COMPLIANCES, FRICTIONS, LAGS, LAWS, Candidate
from .locate import END_OF_STROKE

RIVAL_P = 1e-3      # a balance whose best candidate's score test is significant at this level …
RIVAL_SHARE = 1 / 3  # … and explains at least a third of what the top candidate explains is fitted too
# compliances (declared by their families, candidates.COMPLIANCES): each adds a mode whose
# frequency moves with its stiffness, so a score test — a secant at a few stiffnesses — ranks
# them poorly against each other (a rod–load link with a sticking joint screened 2.9 % beside a
# mount's 6.1 %, and fitted, explained 5× more): once one is shortlisted, every significant
# other is fitted too and the fits decide
# lags (declared by their families, candidates.LAGS): a transport delay retards every command
# change by T, a play in the valve retards the spool after each reversal by b/|du/dt| (long at
# slow reversals, short at fast ones), a slow transducer retards only the pressure readings; a
# secant at one probe value ranks them by how much each resembles the others at that value (a
# dev EHA with a Dahl-type valve hysteresis: the delay screened 21 %, the play was never fitted;
# fitted alone it passed at ΔBIC −2752). Once one is shortlisted, the others are fitted too.
# Dead bands of one element (candidates.BANDS: a spool's overlap and its play) likewise.
GROUPS = (COMPLIANCES, LAGS, BANDS)
# a compliance whose fitted mode is damped beyond this ratio rings at no frequency: what it adds
# is a force that follows the speed (the true mounts of the dev family fitted at ζ 0.08–0.78;
# mounts and rod–load links standing in for seals that reverse over a 2 mm/s band, at 3.4–23)
OVERDAMPED = 2.0


def shortlist(order: list[Candidate], scores: dict, n_fit: int, readings: frozenset = frozenset()) -> list[Candidate]:
    """The candidates to re-identify: the best-screening form of each of the ``n_fit`` best
    EFFECTS (two forms of one effect must not crowd out a different effect), plus the best
    candidate of each other balance (the equation it acts in: continuity, force, valve, signal,
    measurement) that competes: its score test is significant (p < ``RIVAL_P``) and it explains
    at least ``RIVAL_SHARE`` of what the top candidate explains. Effects that act in
    different balances can mimic each other over the conditions recorded (air in the chamber
    against a compliant mount, a line against a sensor lag); a screening score alone, a
    linearisation at one probe value, must not decide between them — the fits do. Once one
    compliance is in, the best form of every other significant compliance joins it
    (``COMPLIANCES``); likewise for the lags (``LAGS``: an input delay, a valve play, a slow
    reading) and a spool's dead bands (``BANDS``: overlap, play). An effect offered in more
    than one law (``LAWS``: a leak, laminar or through an orifice) has every significant law
    fitted once it is shortlisted: which law, like which effect, is for the fits to decide (dev
    rotary orifice leak across the vane: the laminar law screened first and lost to a valve
    underlap, whose edge leakage has the orifice's shape). ``readings``: effects whose best
    form is fitted whatever it screens — the readings of a base-fit finding on trial (grown
    chamber volumes: air or a hose, :func:`base_findings.labelled`), which the grown volumes
    leave nothing to screen for (dev rotary, air and a distributed hose alike: both screened
    0.0 %, neither was fitted, and the finding kept its default name)."""
    picked, effects = [], set()
    for e in sorted(readings):            # a finding's readings: fitted, to be compared
        c = next((c for c in order if c.effect == e), None)
        if c is not None:
            picked.append(c)
    for c in order:                       # the best FORM of each of the n_fit best effects
        if len(effects) >= n_fit:
            break
        if c.effect not in effects:
            if c not in picked:
                picked.append(c)
            effects.add(c.effect)
    if not order:
        return picked
    top = scores[order[0].key]["dr2"]
    seen = {c.equation for c in picked}
    for c in order:
        if (c not in picked and c.equation not in seen and scores[c.key]["p_value"] < RIVAL_P
                and scores[c.key]["dr2"] >= RIVAL_SHARE * top):
            picked.append(c)
            seen.add(c.equation)
    for c in order:                       # every significant law of a shortlisted leak
        if (c.effect in LAWS and c not in picked and c.effect in {p.effect for p in picked}
                and scores[c.key]["p_value"] < RIVAL_P):
            picked.append(c)
    for group in GROUPS:
        have = {c.effect for c in picked}
        if group & have:
            for c in order:               # the best form of each other significant member
                if c.effect in group and c.effect not in have and scores[c.key]["p_value"] < RIVAL_P:
                    picked.append(c)
                    have.add(c.effect)
    return picked


def after_wave(remaining: list[Candidate], fitted: set) -> list[Candidate]:
    """The candidates a further wave may still fit, in screening order, once the keys in
    ``fitted`` were fitted and none passed: an effect that was fitted is done, except an effect
    offered in several laws (``LAWS``), which the law that failed does not rule out — its
    other laws stay (Festo rig without its stops: a cushion at the lower end screened 50 % and
    failed; the plain stop at the upper end, 12 %, was never fitted and a sensor lag was named)."""
    done = {c.effect for c in remaining if c.key in fitted and c.effect not in LAWS}
    return [c for c in remaining if c.key not in fitted and c.effect not in done]


def creeping(best: list[Candidate], fits: dict, judged: dict, remaining: list[Candidate]) -> tuple[list, list]:
    """``(stand_ins, frictions)``: the compliances of a wave whose fit could be named (passed, or
    failed only on the precision, a bound or the size of a value: :func:`accept.judge`) with
    their mode damped beyond ``OVERDAMPED``, as (candidate, ζ); and, when there are any, every
    form and law of every friction effect (``FRICTIONS``) still in ``remaining``, to be fitted
    before one is named. An overdamped spring–damper in series with the machine's own dry
    friction makes a force that turns over a band of speeds at each reversal — a seal or a
    Coulomb contact that reverses over a band, a viscous drag — and the score test, a secant at
    one probe, ranks such a friction far below what its fit explains (dev lift_cbv, seals pressed
    by both chambers reversing over 2 mm/s: the rod-seal law screened 3.5 % beside a mount's
    10.5 % and was not shortlisted; the mount was named at ζ 23 with held-out v 2.35 → 1.56 %;
    fitted, the seals' law took held-out P1 0.51 → 0.013 %, v → 0.79 %, ΔBIC −12 727 against
    the mount's −1984)."""
    stand_ins = []
    for c in best:
        f, row = fits.get(c.key), judged.get(c.key, {})
        if c.mode is None or f is None or f.get("error") is not None:
            continue
        if not any(row.get(k) for k in ("passed", "imprecise", "bounded", "small")):
            continue
        z = c.damping_ratio(dict(zip(f["names"], f["estimates"])))
        if z is not None and z > OVERDAMPED:
            stand_ins.append((c, z))
    return stand_ins, ([c for c in remaining if c.effect in FRICTIONS] if stand_ins else [])


def at_the_ends(mismatch: dict | None, remaining: list[Candidate]) -> list[Candidate]:
    """The stops and cushions still in ``remaining`` (candidates with a position on the travel,
    which carries the travel it is judged against: ``NewParam.seen``, ``NewParam.reach``) when
    the unexplained mismatch (``findings.unexplained``: the verdict the round would otherwise
    end on) lists the ends of the stroke among the regimes where the error concentrates; else
    none. A stop acts at the ends and nowhere else, which is where the engineer looks next;
    its score test cannot say so: the base fit bends itself (its friction, its stiffness) to
    keep the replayed piston inside the recorded travel, so a stop probed just beyond the
    recorded end is barely touched by the base trajectory (dev
    EHA, a rubber bumper pressed 1.5 mm at the head, effect ESR 28 %: the stop screened 0.2 %
    beside a leak's 10 %, was never fitted and the answer was an unexplained mismatch "at the
    end of stroke"; fitted, it took the held-out P2 from 23.2 to 0.99 %)."""
    if mismatch is None or not any(r.get("regime") == END_OF_STROKE for r in mismatch.get("regimes", [])):
        return []
    return [c for c in remaining if any(p.seen or p.reach for p in c.params)]
