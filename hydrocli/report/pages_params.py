"""Parameters (identified from /identify, else nominal from /parameters), the correlation
heat map of the estimates, the cost history, and — when the fit assessed its uncertainty —
the 95 % bootstrap intervals, what the data do not determine and the fixed parameters the
estimates depend on."""
from __future__ import annotations

import numpy as np
from matplotlib.ticker import FuncFormatter

from . import style
from .data import Loaded

ROWS = 24                # parameter rows per page
AT_BOUND = "#ffe3b3"
POORLY_DETERMINED = "#fde2e1"


def g(x) -> str:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return str(x)
    return "—" if not np.isfinite(x) else f"{x:.4g}"


def parameter_pages(out, run: Loaded) -> None:
    if run.res.identify:
        _identified_pages(out, run)
    else:
        _nominal_pages(out, run)


def _pages(out, title: str, subtitle: str, header, rows, widths, colours=None, note: str = "",
           width: float = 0.92) -> None:
    parts = max(1, -(-len(rows) // ROWS))
    for k in range(parts):
        fig = style.page(title + (f" ({k + 1}/{parts})" if parts > 1 else ""), subtitle)
        ax = fig.add_axes([0.04, 0.10, width, 0.78])
        sel = {i - k * ROWS: c for i, c in (colours or {}).items() if k * ROWS <= i < (k + 1) * ROWS}
        style.table(ax, header, rows[k * ROWS:(k + 1) * ROWS], widths, sel, left=2)
        if note:
            fig.text(0.04, 0.05, note, fontsize=8, color="0.3")
        out.add(fig)


def _nominal_pages(out, run: Loaded) -> None:
    free = _free_parameters(run.res.netlist_text)
    rows = [[n, u if u not in ("", "1") else "-", g(v), "yes" if n in free else ""] for n, v, u in run.res.parameters]
    _pages(out, f"Parameters of {run.res.machine}", "nominal values used for the runs (SI units; no identification "
           "in these results); 'free' marks the parameters the machine file leaves to identification",
           ["Parameter", "Unit (SI)", "Value", "Free"], rows, [0.45, 0.22, 0.22, 0.11], width=0.6)


def _free_parameters(netlist_text: str) -> set[str]:
    """``comp.param`` names listed under ``components.<comp>.free`` in the normalised netlist."""
    from ruamel.yaml import YAML
    try:
        doc = YAML(typ="safe").load(netlist_text) or {}
        return {f"{c}.{p}" for c, spec in (doc.get("components") or {}).items() for p in (spec or {}).get("free") or []}
    except Exception:  # an unreadable netlist only loses the column
        return set()


def _identified_pages(out, run: Loaded) -> None:
    d = run.res.identify
    names = [str(n) for n in d.get("names", [])]
    units = {n: u for n, _, u in run.res.parameters}
    cols = {k: np.atleast_1d(np.asarray(d.get(k, [np.nan] * len(names)), float))
            for k in ("initial", "estimates", "lower", "upper", "stderr")}
    ci = [np.atleast_1d(np.asarray(d[k], float)) for k in ("ci_lower", "ci_upper")] if "ci_lower" in d else None
    rows, colours = [], {}
    for i, n in enumerate(names):
        est, lo, hi, se = cols["estimates"][i], cols["lower"][i], cols["upper"][i], cols["stderr"][i]
        rel = abs(se / est) * 100 if est and np.isfinite(se) else np.nan
        span = hi - lo
        if np.isfinite(span) and span > 0 and min(est - lo, hi - est) <= 1e-3 * span:
            colours[i] = AT_BOUND
        elif np.isfinite(rel) and rel > 50 or not np.isfinite(se):
            colours[i] = POORLY_DETERMINED
        row = [n, units.get(n, "-") or "-", g(cols["initial"][i]), g(est), g(lo), g(hi), g(se), g(rel)]
        if ci is not None:
            row.append(f"{g(ci[0][i])} … {g(ci[1][i])}")
        rows.append(row)
    warnings = [w for w in np.atleast_1d(d.get("warnings", [])) if str(w).strip()]
    note = ("orange: estimate at a bound; red: standard error > 50 % of the estimate or undetermined.\n"
            "Standard errors from the Gauss–Newton covariance at the optimum"
            + (f", × √(n/n_eff) for correlated residuals (n_eff = {float(d['n_effective']):.0f})."
               if "stderr_white" in d and d.get("n_effective") else "."))
    if warnings:
        note += "\nwarnings: " + "; ".join(str(w) for w in warnings)[:300]
    subtitle = (f"method {d.get('method', '?')}, cost {g(d.get('cost_initial'))} → {g(d.get('cost'))}, "
                f"{int(float(d.get('n_evals', 0) or 0))} evaluations, {g(d.get('seconds'))} s"
                + (" (interrupted)" if int(float(d.get("interrupted", 0) or 0)) else "")
                + (f" — {d.get('message')}" if d.get("message") else ""))
    header = ["Parameter", "Unit (SI)", "Initial", "Identified", "Lower", "Upper", "Std. error", "Std. error %"]
    widths = [0.22, 0.12, 0.11, 0.11, 0.11, 0.11, 0.11, 0.11]
    if ci is not None:
        header.append("95 % interval")
        widths = [0.19, 0.08, 0.09, 0.09, 0.08, 0.08, 0.09, 0.08, 0.22]
        note += f"\n95 % interval: {d.get('ci_method', 'bootstrap')} (allows for coloured residuals)."
    _pages(out, f"Identified parameters of {run.res.machine}", subtitle, header, rows, widths, colours, note)
    _correlation_cost_page(out, run, names)
    if "identifiability" in d or "fixed_messages" in d:
        _assessment_page(out, run)


def _lines(d: dict, key: str) -> list[str]:
    return [str(m) for m in np.atleast_1d(d.get(key, [])) if str(m).strip()]


def _assessment_page(out, run: Loaded) -> None:
    """What the data do not determine, and the fixed parameters the estimates depend on."""
    import textwrap
    d = run.res.identify
    fig = style.page(f"Identification of {run.res.machine}: what the estimates rest on",
                     "from the sensitivities at the optimum: singular directions of the scaled Jacobian, "
                     "and dθ/dφ = −(JᵀJ)⁻¹JᵀJφ for the fixed parameters φ")
    fixed = _lines(d, "fixed_messages")
    n_fixed = len(_lines(d, "fixed_names"))
    blocks = [("Not determined by the data", _lines(d, "identifiability")
               or ["every free parameter is determined (relative uncertainty of every direction ≤ 10 %)"]),
              ("Fixed parameters the estimates are sensitive to", fixed
               or [f"a 10 % error in any of the {n_fixed} fixed parameters moves no estimate by more than "
                   f"two standard errors" if n_fixed else "not assessed (no sensitivities)"])]
    window = _lines(d, "window_messages")
    if window:
        blocks.append(("Model error: estimates that differ between parts of the recording", window))
    y = 0.86
    for title, items in blocks:
        fig.text(0.05, y, title, fontsize=11, weight="bold")
        y -= 0.035
        for m in items[:12]:
            for k, line in enumerate(textwrap.wrap(m, 120)):
                fig.text(0.06 if k == 0 else 0.08, y, ("• " if k == 0 else "") + line, fontsize=8.5)
                y -= 0.025
            y -= 0.008
            if y < 0.08:
                break
        y -= 0.03
    out.add(fig)


def _correlation_cost_page(out, run: Loaded, names: list[str]) -> None:
    d = run.res.identify
    fig = style.page(f"Identification of {run.res.machine}: correlation and convergence",
                     "correlation of the estimates (|r| near 1: not separately identifiable); best cost so far per evaluation")
    ax = fig.add_axes([0.10, 0.12, 0.42, 0.72])
    corr = np.asarray(d.get("correlation", np.full((len(names), len(names)), np.nan)), float)
    if corr.ndim == 2 and corr.size and corr.shape[0] == len(names):
        im = ax.imshow(corr, cmap="RdBu_r", vmin=-1, vmax=1)
        ax.set_xticks(range(len(names)), names, rotation=60, ha="right", fontsize=7 if len(names) > 10 else 8)
        ax.set_yticks(range(len(names)), names, fontsize=7 if len(names) > 10 else 8)
        ax.grid(False)
        if len(names) <= 12:
            for (i, j), r in np.ndenumerate(corr):
                if np.isfinite(r):
                    ax.text(j, i, f"{r:.2f}", ha="center", va="center", fontsize=9 if len(names) <= 6 else 6.5,
                            color="white" if abs(r) > 0.6 else "black")
        fig.colorbar(im, ax=ax, fraction=0.046, pad=0.03, label="correlation coefficient")
        ax.set_title("Correlation of the estimates", loc="left")
    else:
        ax.axis("off")
        ax.text(0.5, 0.5, "no correlation matrix", ha="center", transform=ax.transAxes)
    axc = fig.add_axes([0.70, 0.18, 0.27, 0.66])
    hist = np.atleast_1d(np.asarray(d.get("cost_history", []), float))
    hist = hist[np.isfinite(hist) & (hist > 0)]
    if hist.size:
        axc.semilogy(np.arange(1, hist.size + 1), hist, color=style.SIMULATED, lw=1.2)
        if hist.max() < 10 * hist.min():     # less than a decade: plain numbers, not 2.6×10⁻² minor labels
            plain = FuncFormatter(lambda v, _: f"{v:.4g}")
            axc.yaxis.set_major_formatter(plain)
            axc.yaxis.set_minor_formatter(plain)
        axc.set_xlabel("cost evaluation")
        axc.set_ylabel("cost (best so far, log scale)")
        axc.set_title(f"Cost history: {g(hist[0])} → {g(hist[-1])}", loc="left")
    else:
        axc.axis("off")
        axc.text(0.5, 0.5, "no cost history", ha="center", transform=axc.transAxes)
    out.add(fig)
