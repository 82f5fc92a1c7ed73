"""Small rich-table helpers shared by the listing commands (check, components)."""
from __future__ import annotations

from rich.console import Console
from rich.table import Table


def console(stderr: bool = False) -> Console:
    """A console at least 120 columns wide: tables of parameters stay readable when the
    output goes to a file or a pipe (rich would assume 80 columns there)."""
    width = max(Console(stderr=stderr).width, 120)
    return Console(highlight=False, soft_wrap=False, width=width, stderr=stderr)


def table(title: str, *columns: str) -> Table:
    t = Table(title=title, title_justify="left", title_style="bold", show_lines=False, expand=False)
    for c in columns:
        t.add_column(c, overflow="fold")
    return t


def fmt(x, unit: str | None = None) -> str:
    """A number with 4 significant digits and an optional unit."""
    if x is None:
        return "—"
    if isinstance(x, (list, tuple)):
        return "[" + ", ".join(fmt(v) for v in x) + "]" + (f" {unit}" if unit and unit != "1" else "")
    text = f"{x:.4g}" if isinstance(x, (int, float)) else str(x)
    return f"{text} {unit}" if unit and unit != "1" else text
