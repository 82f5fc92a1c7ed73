"""Which of the passing candidates is named: BIC on the training data, the held-out data
among those the training data barely tell apart, the simpler law when the data do not
separate two, and an imprecise candidate that beats every precise one (:mod:`.engine`'s
round)."""
from __future__ import annotations

from . import residuals
from .candidates import REDUCES_TO

ALTERNATIVE = 0.8   # another passing effect with ΔBIC ≥ 80 % of the winner's is reported as nearly as good
TIE = 0.05          # of the noise band: held-out ESRs closer than this are equal, and training BIC decides


def dominant(imprecise: list, passing: list, rows: dict, alone: bool = True):
    """The (ΔBIC, candidate, fit) of an imprecise candidate (:func:`accept.judge`: it fails on
    the precision of its size alone) that beats EVERY passing candidate on both tests — a lower
    ΔBIC and a larger held-out gain — or None. The data then prefer an explanation whose size
    they cannot pin down; naming the precise runner-up instead would name the wrong physics
    (dev EHA, isothermal air: air ΔBIC −15 879 and gain 0.88 %, its amount ±56 % against a free
    bulk modulus; a hose passed at −1027 and 0.53 % and was named). With no passing candidate
    an imprecise one that passes BIC and the held-out band is named likewise — unless
    ``alone`` is False (a candidate whose value ended at its bound, ``accept.judge``'s
    "bounded": preferred to a passing one it beats, never named on its own)."""
    if not passing and not alone:
        return None
    gain = {c.key: rows[c.key]["validation_gain"] for _, c, _ in imprecise + passing}
    for d, c, f in sorted(imprecise, key=lambda x: x[0]):
        if all(d < d2 and gain[c.key] > gain[c2.key] for d2, c2, _ in passing):
            return d, c, f
    return None


def rank_passing(passing: list, band: float | None = None) -> list:
    """Passing candidates, the accepted one first. BIC ranks them on the training data; among
    those whose ΔBIC is within ``ALTERNATIVE`` of the best (the training data barely tell them
    apart, e.g. seal friction on a gravity-loaded cylinder, whose |p_A − p_B| hardly varies,
    against Coulomb friction) the held-out data decide: the lowest summed validation ESR.

    With the noise ``band``: a passing candidate that predicts the held-out data better than
    the head by more than the band goes first, however far behind on training BIC. The two
    tests then disagree, and a training advantage the held-out record does not confirm is the
    signature of a law that fits what only the training record holds (a hook load hardly
    excited in training, 0.12 % there and 0.86 % held out: a compliant mount fitted the
    training twice as well, ΔBIC −8719 against −4415, and left 0.68 % of held-out error
    against the payload's 0.16 %, band 0.18 %). On 267 recorded cases with a passing
    candidate no round was decided this way before the payload cases."""
    passing = sorted(passing, key=lambda x: x[0])
    best = passing[0][0]
    close = [p for p in passing if p[0] <= ALTERNATIVE * best]
    rest = [p for p in passing if p[0] > ALTERNATIVE * best]
    close.sort(key=lambda x: residuals.total(x[2]["esr_validation"]))
    if band is not None:
        # held-out ESRs within TIE of the band of the lowest are one figure measured with noise:
        # among them training BIC, the other test, decides (dev winch, a command through a lag
        # cascade: an input delay at ΔBIC −4068 and a spool's hysteresis at −4047 predicted
        # the held-out record to 0.0003 % of each other, band 0.066 %, and the hysteresis was
        # named on that difference)
        low = residuals.total(close[0][2]["esr_validation"])
        tied = [p for p in close if residuals.total(p[2]["esr_validation"]) <= low + TIE * band]
        lead = min(tied, key=lambda x: x[0])
        close = [lead] + [p for p in close if p is not lead]
    ranked = close + rest
    if band is not None:
        head = residuals.total(ranked[0][2]["esr_validation"])
        better = [p for p in ranked[1:] if residuals.total(p[2]["esr_validation"]) < head - band]
        if better:
            first = min(better, key=lambda x: residuals.total(x[2]["esr_validation"]))
            ranked = [first] + [p for p in ranked if p is not first]
    return ranked


def simplest(ranked: list, band: float) -> list:
    """The ranked passing candidates with the head replaced by its special case when the data
    do not tell them apart (``REDUCES_TO``, declared by the families): a seal friction
    μ·A·(p_A + p_B) on a symmetric actuator fed at a constant supply is a constant force, a
    Coulomb friction with one dependence more that these data do not exercise (the project's
    concealed Coulomb case: ΔBIC −1106 for the seal law against −1102 for Coulomb, validation
    ESR 1.408 against 1.416 %, noise band 0.17 %). Naming the simpler law claims only what was
    recorded; the richer one stays the rival, with the test that would separate them."""
    if not ranked:
        return ranked
    head = ranked[0]
    close = ALTERNATIVE * min(p[0] for p in ranked)
    for i, other in enumerate(ranked[1:], 1):
        if ((head[1].effect, other[1].effect) in REDUCES_TO and other[0] <= close
                and not separated(head[2], other[2], band)):
            return [other] + ranked[:i] + ranked[i + 1:]
    return ranked


def separated(f: dict, f2: dict, band: float) -> bool:
    """Two fitted candidates are told apart by the data when their summed ESRs differ by more
    than the noise band on the held-out data or on ANY one training experiment: an experiment
    designed to separate them (:mod:`.design`), once recorded and added, is where one predicts
    within the noise and the other does not, even if the pooled ΔBICs stay close."""
    gaps = [residuals.total(f["esr_validation"]) - residuals.total(f2["esr_validation"])]
    gaps += [a - b for a, b in zip(f.get("esr_train_each", []), f2.get("esr_train_each", []))]
    return any(abs(g) >= band for g in gaps)


def by_importance(accepted: list[dict]) -> list[str]:
    """The accepted effects' names, each once, the effects a round's candidate added ordered by
    what they are worth to the final model: the held-out ESR its removal costs when backward
    elimination measured it (``removal_gain``, :func:`.backward.backward`: an earlier effect
    kept beside a later one), else the gain of the step that added it. Base-fit findings and
    other entries keep their places. The rounds add effects greedily, so the first is the best
    SINGLE stand-in for what is missing; when a later effect is worth more than the first is
    beside it, the later one leads (dev lift, a rod seal pressed by the rod side: a mount was
    accepted first, 2.5 × the floor, the seal in round 2 gained 8.9 × the floor; the mount kept
    only what the seal did not explain)."""
    def worth(a: dict) -> float:
        if "removal_gain" in a:
            return a["removal_gain"]
        return residuals.total(a["esr_validation_before"]) - residuals.total(a["esr_validation_after"])
    slots = [i for i, a in enumerate(accepted) if a.get("source") == "candidate" and "esr_validation_after" in a]
    ordered = sorted((accepted[i] for i in slots), key=worth, reverse=True)
    out = list(accepted)
    for i, a in zip(slots, ordered):
        out[i] = a
    return list(dict.fromkeys(a["effect"] for a in out))
