"""The project's error hierarchy.

Every error a user can cause is a :class:`HydroError` carrying one or more located
:class:`Problem` records (file, line, column, YAML path, what is wrong, how to fix it).
The CLI maps each subclass to an exit code (DESIGN.md): 2 for usage errors, 3 for invalid netlist, units,
topology or data; 4 for solver or identification failure.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path


@dataclass(frozen=True)
class Location:
    """Where a problem sits in an input file (line and column are 1-based)."""

    file: str | None = None
    line: int | None = None
    col: int | None = None
    path: str | None = None  # YAML path, e.g. "components.valve.Kv"

    def __str__(self) -> str:
        parts = []
        if self.file:
            parts.append(str(self.file))
        if self.line is not None:
            parts.append(str(self.line))
            if self.col is not None:
                parts.append(str(self.col))
        text = ":".join(parts)
        if self.path:
            text = f"{text} ({self.path})" if text else self.path
        return text


@dataclass(frozen=True)
class Problem:
    """One thing that is wrong, where, and how to fix it."""

    message: str
    location: Location = field(default_factory=Location)
    hint: str | None = None

    def at(self, location: Location) -> "Problem":
        """The same problem, located elsewhere (e.g. a unit error moved to its YAML value)."""
        return Problem(self.message, location, self.hint)

    def render(self, with_source: bool = True) -> str:
        head = f"{self.location}: " if str(self.location) else ""
        text = f"{head}{self.message}"
        if with_source:
            snippet = _source_snippet(self.location)
            if snippet:
                text += "\n" + snippet
        if self.hint:
            text += f"\n  hint: {self.hint}"
        return text


def _source_snippet(loc: Location) -> str:
    """The offending line with a caret under the column, Cantera style."""
    if not loc.file or loc.line is None:
        return ""
    try:
        lines = Path(loc.file).read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return ""
    if not 1 <= loc.line <= len(lines):
        return ""
    src = lines[loc.line - 1]
    out = [f"  {loc.line:4d} | {src}"]
    if loc.col is not None:
        out.append("       | " + " " * max(loc.col - 1, 0) + "^")
    return "\n".join(out)


class HydroError(Exception):
    """Base of all user-facing errors; holds a list of problems reported together."""

    exit_code = 3
    kind = "error"

    def __init__(self, problems: list[Problem] | Problem | str, *, location: Location | None = None,
                 hint: str | None = None):
        if isinstance(problems, str):
            problems = [Problem(problems, location or Location(), hint)]
        elif isinstance(problems, Problem):
            problems = [problems]
        self.problems: list[Problem] = list(problems)
        super().__init__(self.render(with_source=False))

    def render(self, with_source: bool = True) -> str:
        n = len(self.problems)
        head = f"{self.kind}: " if n == 1 else f"{self.kind}: {n} problems\n"
        body = "\n".join(p.render(with_source) for p in self.problems)
        return head + body


class UsageError(HydroError):
    """A bad command line: an option value out of range, an output path that is an input…"""

    exit_code = 2
    kind = "usage error"


class NetlistError(HydroError):
    kind = "invalid machine file"


class UnitError(HydroError):
    kind = "unit error"


class TopologyError(HydroError):
    kind = "invalid topology"


class DataError(HydroError):
    kind = "invalid data"


class SolverError(HydroError):
    exit_code = 4
    kind = "solver failure"
    #: the trajectory up to the failure (samples before the time reached), when known
    partial = None


class IdentifyError(HydroError):
    exit_code = 4
    kind = "identification failure"


class ProblemCollector:
    """Collects problems so a whole file is checked before failing."""

    def __init__(self) -> None:
        self.problems: list[Problem] = []

    def add(self, message: str, location: Location | None = None, hint: str | None = None) -> None:
        self.problems.append(Problem(message, location or Location(), hint))

    def extend(self, err: HydroError) -> None:
        self.problems.extend(err.problems)

    def raise_if_any(self, cls: type[HydroError] = NetlistError) -> None:
        if self.problems:
            raise cls(self.problems)

    def __bool__(self) -> bool:
        return bool(self.problems)
