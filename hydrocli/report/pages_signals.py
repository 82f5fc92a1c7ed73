"""Per experiment: measured vs simulated per output with the residual beneath, then the
windows with the largest residual energy zoomed in, next to the experiment's metric table."""
from __future__ import annotations

import numpy as np
from matplotlib.gridspec import GridSpec, GridSpecFromSubplotSpec

from . import style
from .data import Loaded, decimate, display, worst_windows

PER_PAGE = 3             # outputs per overview page
ZOOM_ROWS = 5            # outputs per zoom page


def _signals(run: Loaded, name: str):
    res = run.res
    sim, unit = display(res, "outputs", name, res.outputs[name])
    meas = display(res, "measured", name, res.measured[name])[0] if name in res.measured else None
    return sim, meas, unit


def _windows(run: Loaded) -> list[tuple[float, float]]:
    res = run.res
    return worst_windows(res.t, [res.measured[n] - res.outputs[n] for n in res.outputs if n in res.measured])


def experiment_pages(out, run: Loaded) -> None:
    names = list(run.res.outputs)
    windows = _windows(run)
    n_pages = -(-len(names) // PER_PAGE)
    for k in range(n_pages):
        _overview_page(out, run, names[k * PER_PAGE:(k + 1) * PER_PAGE], windows, f"{k + 1}/{n_pages}")
    measured = [n for n in names if n in run.res.measured]
    for k in range(0, len(measured), ZOOM_ROWS):
        _zoom_page(out, run, measured[k:k + ZOOM_ROWS], windows)


def _overview_page(out, run: Loaded, names: list[str], windows, part: str) -> None:
    res = run.res
    metrics = run.metrics()
    fig = style.page(f"Experiment {res.experiment}: measured vs simulated ({part})",
                     f"{res.machine} — shaded: the windows with the largest residual energy (zoomed on the next page)")
    outer = GridSpec(len(names), 1, figure=fig, left=0.08, right=0.97, top=0.87, bottom=0.10, hspace=0.32)
    t = res.t
    for i, name in enumerate(names):
        sim, meas, unit = _signals(run, name)
        inner = GridSpecFromSubplotSpec(2, 1, outer[i, 0], height_ratios=[2.4, 1], hspace=0.08)
        ax = fig.add_subplot(inner[0])
        axr = fig.add_subplot(inner[1], sharex=ax)
        if meas is not None:
            ax.plot(*decimate(t, meas), color=style.MEASURED, label="measured")
        ax.plot(*decimate(t, sim), color=style.SIMULATED, label="simulated", alpha=0.85)
        for a, b in windows:
            ax.axvspan(a, b, color=style.WINDOW, alpha=0.25, lw=0)
        m = metrics.get(name)
        ax.set_title(f"{name}" + (f"   ESR {m['esr']:.3g} %, NRMSE {100 * m['nrmse']:.3g} %, fit {m['fit']:.3g} %"
                                  if m else "   (not measured)"), loc="left", pad=3)
        ax.set_ylabel(f"{name} [{unit}]")
        ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=2, frameon=False, borderaxespad=0.1)
        ax.tick_params(labelbottom=False)
        if meas is not None:
            axr.plot(*decimate(t, meas - sim), color=style.RESIDUAL, lw=0.7)
            axr.axhline(0.0, color="0.4", lw=0.6)
        else:
            axr.text(0.5, 0.5, "no measurement: no residual", ha="center", va="center", color="0.4",
                     transform=axr.transAxes)
            axr.set_yticks([])
        axr.set_ylabel(f"resid. [{unit}]")
        if i == len(names) - 1:
            axr.set_xlabel("time [s]")
        ax.set_xlim(t[0], t[-1])
    out.add(fig)


def _zoom_page(out, run: Loaded, names: list[str], windows) -> None:
    res = run.res
    span = ", ".join(f"{a:.2f}–{b:.2f} s" for a, b in windows) or "none"
    fig = style.page(f"Experiment {res.experiment}: where the error is largest",
                     f"windows with the largest rolling residual energy (all measured outputs, normalised): {span}")
    _metric_table(fig, run)
    ncol = max(len(windows), 1)
    gs = GridSpec(len(names), ncol, figure=fig, left=0.42, right=0.98, top=0.88, bottom=0.10, hspace=0.55, wspace=0.28)
    for i, name in enumerate(names):
        sim, meas, unit = _signals(run, name)
        for j, (a, b) in enumerate(windows or [(res.t[0], res.t[-1])]):
            ax = fig.add_subplot(gs[i, j])
            sel = (res.t >= a) & (res.t <= b)
            ax.plot(res.t[sel], meas[sel], color=style.MEASURED, label="measured")
            ax.plot(res.t[sel], sim[sel], color=style.SIMULATED, label="simulated", alpha=0.85)
            ax.set_xlim(a, b)
            if j == 0:
                ax.set_ylabel(f"{name} [{unit}]")
            if i == 0:
                ax.set_title(f"window {j + 1}: {a:.2f}–{b:.2f} s", pad=3)
                if j == 0:
                    fig.legend(loc="upper right", bbox_to_anchor=(0.98, 0.965), ncol=2, frameon=False)
            if i == len(names) - 1:
                ax.set_xlabel("time [s]")
    out.add(fig)


def _metric_table(fig, run: Loaded) -> None:
    rows = []
    for name, m in run.metrics().items():
        sim, meas, unit = _signals(run, name)
        r = meas - sim
        rows.append([name, f"{m['esr']:.3g}", f"{100 * m['nrmse']:.3g}", f"{m['fit']:.3g}",
                     f"{np.sqrt(np.nanmean(r ** 2)):.3g} {unit}", f"{np.nanmax(np.abs(r)):.3g} {unit}"])
    fig.text(0.04, 0.88, "Metrics", weight="bold", va="top")
    ax = fig.add_axes([0.04, 0.10, 0.34, 0.75])
    bottom = style.table(ax, ["Output", "ESR %", "NRMSE %", "Fit %", "RMS resid.", "max |resid.|"], rows,
                [0.14, 0.14, 0.16, 0.13, 0.22, 0.21], font=8)
    fig.text(0.04, bottom - 0.03, METRICS_HELP, fontsize=8, color="0.3", va="top", linespacing=1.5)


METRICS_HELP = ("ESR = 100·Var(y − ŷ)/Var(y): share of the signal's variance\n"
                "the model does not explain (offsets do not count).\n"
                "NRMSE = RMS(y − ŷ)/(max y − min y).\n"
                "Fit = 100·(1 − ‖y − ŷ‖/‖y − mean y‖).\n"
                "y measured, ŷ simulated; residual = y − ŷ.")
