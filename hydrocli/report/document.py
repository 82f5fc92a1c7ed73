"""One PDF document writer for every report (``hydro report``, the diagnosis): the report
style's rc settings, numbered pages with a footer, PDF metadata, and an atomic write (a
temporary file in the target folder, then a rename: a crash never leaves a half PDF)."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from ..errors import DataError, Location, Problem
from ..fileio import atomic_path
from . import style


def write_pdf(out: str | Path, fill: Callable[[style.Pages], None], footer: str = "",
              info: dict[str, str] | None = None) -> int:
    """Write the PDF whose pages ``fill(pages)`` adds (``pages.add(fig)``); returns the
    number of pages. An unwritable target is a DataError (exit 3) naming the file."""
    out = Path(out)
    try:
        with atomic_path(out, suffix=".tmp.pdf") as tmp:
            return _write(tmp, fill, footer, info or {})
    except OSError as exc:
        raise DataError(Problem(f"cannot write the report {out}: {exc.strerror or exc}", Location(str(out)),
                                "choose a writable folder with --out")) from None


def _write(path: str, fill, footer: str, info: dict[str, str]) -> int:
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfPages

    with matplotlib.rc_context(style.RC), PdfPages(path) as pdf:
        pages = style.Pages(pdf, footer)
        fill(pages)
        pdf.infodict().update(info)
        return pages.count
