"""Where a diagnosis's wall time goes: the seconds of each step, in the order they ran
(``timings`` in diagnosis.json, the console summary's last line, the family benchmark's share of each kind of step).

Issue 10 asks for ≤ 60 s per 30 s recording; the total alone (``runtime_s``) does not say
which step to make faster. Session 58 measured one case by hand from its progress log (the
shared ``eha_pressure_dependent_friction``: base fit 4 s, the restrained round 422 s, the free
round 275 s); this records it for every diagnosis."""
from __future__ import annotations

import time
from dataclasses import dataclass, field


@dataclass
class StepClock:
    """Laps of one diagnosis: :meth:`lap` closes the step that ran since the last lap."""
    laps: list[tuple[str, float]] = field(default_factory=list)
    last: float = field(default_factory=time.perf_counter)

    def lap(self, step: str) -> None:
        now = time.perf_counter()
        self.laps.append((step, now - self.last))
        self.last = now

    def report(self) -> list[dict]:
        """[{"step", "seconds"}, …] in the order the steps ran (a step may recur: round 2, …)."""
        return [{"step": s, "seconds": round(t, 3)} for s, t in self.laps]


def line(timings: list[dict], total: float) -> str:
    """The console's line, e.g. "Time: 587 s — base fit and the restrained base 10 s, round 1 from
    the restrained base 301 s, round 1 276 s." (steps under 0.5 s left out)."""
    parts = [f"{t['step']} {t['seconds']:.0f} s" for t in timings if t["seconds"] >= 0.5]
    return f"Time: {total:.0f} s" + (" — " + ", ".join(parts) if parts else "") + "."
