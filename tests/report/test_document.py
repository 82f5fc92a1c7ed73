"""report.document.write_pdf: the one PDF writer (model report and diagnosis) — atomic,
numbered pages, and importing the report stack never switches matplotlib's backend."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest


from hydrocli.report import style
from hydrocli.report.document import write_pdf

ROOT = Path(__file__).resolve().parents[2]


def _pages(n):
    def fill(pages):
        for k in range(n):
            fig = style.page(f"page {k + 1}")
            fig.add_subplot(111).plot([0, 1], [k, k + 1])
            pages.add(fig)
    return fill


def test_writes_numbered_pages(tmp_path):
    out = tmp_path / "r.pdf"
    assert write_pdf(out, _pages(3), "footer") == 3
    data = out.read_bytes()
    assert data[:4] == b"%PDF"
    assert data.count(b"/Type /Page") - data.count(b"/Type /Pages") == 3


def test_a_failing_page_leaves_the_old_file_and_no_temporary(tmp_path):
    out = tmp_path / "r.pdf"
    out.write_bytes(b"old")

    def fill(pages):
        _pages(1)(pages)
        raise RuntimeError("page 2 failed")

    with pytest.raises(RuntimeError):
        write_pdf(out, fill)
    assert out.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.pdf"]


def test_unwritable_target_is_a_clear_error(tmp_path):
    """A folder that is a file: the output guard refuses it (a usage error, exit 2), and
    nothing is written."""
    from hydrocli.errors import HydroError
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(HydroError, match="is not a folder") as exc:
        write_pdf(blocker / "sub" / "r.pdf", _pages(1))
    assert exc.value.exit_code == 2 and blocker.read_text() == "x"


def test_importing_the_report_stack_keeps_the_callers_backend():
    code = ("import matplotlib; matplotlib.use('pdf'); "
            "import hydrocli.report.build, hydrocli.report.diagnosis; print(matplotlib.get_backend())")
    got = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={"PYTHONPATH": str(ROOT), "PATH": ""}, timeout=120)
    assert got.returncode == 0, got.stderr
    assert got.stdout.strip() == "pdf"
