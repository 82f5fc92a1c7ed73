"""Validation verdicts as JUnit XML (for CI) and as a Markdown summary table."""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from itertools import groupby

from ..validate import Row, Verdict


def fmt(x: float, digits: int = 3) -> str:
    return "n/a" if x is None or not math.isfinite(x) else f"{x:.{digits}g}"


def _status(row: Row) -> str:
    return {None: "—", True: "pass", False: "FAIL"}[row.passed]


def failure_message(row: Row) -> str:
    if row.note:
        return f"ESR({row.output}) cannot be computed: {row.note} (threshold {fmt(row.threshold)} %)"
    return f"ESR({row.output}) = {fmt(row.esr)} % > threshold {fmt(row.threshold)} %"


def junit_xml(verdict: Verdict) -> str:
    """One <testsuite> per experiment, one <testcase> per output with a threshold."""
    root = ET.Element("testsuites", name=f"hydro validate {verdict.machine}",
                      tests=str(len(verdict.checked)), failures=str(len(verdict.failed)))
    for exp, rows in groupby(verdict.checked, key=lambda r: r.experiment):
        rows = list(rows)
        suite = ET.SubElement(root, "testsuite", name=f"{verdict.machine}.{exp}", tests=str(len(rows)),
                              failures=str(sum(r.passed is False for r in rows)), errors="0", skipped="0")
        for r in rows:
            case = ET.SubElement(suite, "testcase", classname=f"{verdict.machine}.{exp}",
                                 name=f"ESR({r.output}) <= {fmt(r.threshold)} %")
            if r.passed is False:
                f = ET.SubElement(case, "failure", message=failure_message(r), type="threshold")
                f.text = _details(r)
            out = ET.SubElement(case, "system-out")
            out.text = _details(r)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _details(r: Row) -> str:
    return (f"experiment {r.experiment}, output {r.output}: ESR {fmt(r.esr)} %, NRMSE {fmt(100 * r.nrmse)} %, "
            f"fit {fmt(r.fit)} %, max ESR {fmt(r.threshold)} %" + (f" ({r.note})" if r.note else ""))


def markdown(verdict: Verdict) -> str:
    lines = [f"# Validation of {verdict.machine}", "",
             "| Experiment | Output | ESR % | NRMSE % | Fit % | Max ESR % | Result |",
             "|---|---|---:|---:|---:|---:|:---:|"]
    for r in verdict.rows:
        lines.append(f"| {r.experiment} | {r.output} | {fmt(r.esr)} | {fmt(100 * r.nrmse)} | {fmt(r.fit)} | "
                     f"{fmt(r.threshold) if r.threshold is not None else ''} | {_status(r)} |")
    lines += ["", summary(verdict), ""]
    lines += [f"- {n}" for n in verdict.notes]
    return "\n".join(lines).rstrip() + "\n"


def summary(verdict: Verdict) -> str:
    n, bad = len(verdict.checked), len(verdict.failed)
    if not n:
        return "No thresholds given: metrics only, nothing to gate (pass)."
    if bad:
        return f"**FAIL**: {bad} of {n} threshold checks failed."
    return f"**PASS**: all {n} threshold checks passed."
