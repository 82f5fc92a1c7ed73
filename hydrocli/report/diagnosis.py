"""The diagnosis PDF (A4 portrait, built on the report stack: ``report.style`` figures,
``report.document.write_pdf``, atomic write): 1) residual localisation — residual over time
with the worst windows shaded, regime concentration, residual spectra, equation errors;
2) the candidate ranking; 3) before/after on training data; 4) before/after on validation
data. One function per page. ``diag`` is a :class:`hydrocli.diagnose.engine.Diagnosis`
(read only: its ``data`` dict, experiments, outputs and base/final fits)."""
from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np

from ..errors import HydroError
from ..units import si_factor
from . import style
from .document import write_pdf


def write_report(diag, path: str | Path) -> int:
    """Write the four diagnosis pages to ``path`` (atomically); returns the page count."""
    name = Path(diag.data["machine"]).name

    def fill(pages) -> None:
        for page in (_localisation, _ranking, _before_after_train, _before_after_validation):
            pages.add(page(diag))

    return write_pdf(path, fill, f"Diagnosis of {name} — {_dt.date.today().isoformat()}",
                     {"Title": f"Diagnosis of {name}", "Creator": "hydrocli (hydro diagnose)"})


def _localisation(diag):
    d, base = diag.data, diag.base
    fig = style.figure(style.PORTRAIT)
    fig.suptitle(f"Diagnosis of {Path(d['machine']).name}: where the base model fails\n"
                 f"verdict: {d['verdict']} ({', '.join(d['effects'])})", fontsize=11)
    gs = fig.add_gridspec(4, 2, hspace=0.6, wspace=0.35)
    e, Y = diag.train[0], base.Y_train[0]
    ax = fig.add_subplot(gs[0, :])
    for o in (o for o in diag.outputs if o in e.measured):
        y = e.measured[o]
        ax.plot(e.t_out, (Y[:, base.model.output_names.index(o)] - y) / (np.std(y) or 1), lw=0.5, label=o)
    for w in d["located"]["windows"][:8]:
        if w["experiment"] == e.name:
            ax.axvspan(w["t0"], w["t1"], color="orange", alpha=0.2)
    ax.set(title=f"normalised residual (ŷ − y)/std(y), {e.name}; shaded: worst windows", xlabel="t [s]")
    ax.legend(fontsize=7, ncol=len(diag.outputs))
    ax = fig.add_subplot(gs[1, 0])
    reg = d["located"]["regimes"]
    ax.barh([r["regime"] for r in reg], [r["concentration"] for r in reg], color="tab:red")
    ax.axvline(1.0, color="k", lw=0.8)
    ax.set(title="regime concentration (error share / time share)", xlabel="×")
    ax.tick_params(labelsize=7)
    ax = fig.add_subplot(gs[1, 1])
    shares = d["located"]["outputs"]
    ax.bar(list(shares), [100 * v for v in shares.values()])
    ax.set(title="share of the residual per output", ylabel="%")
    ax = fig.add_subplot(gs[2, :])
    for o, s in d["located"]["spectrum"].items():
        f, P = np.array(s["f"]), np.array(s["psd"])
        if f.size > 1:
            ax.loglog(f[1:], P[1:], lw=0.7, label=f"{o} (peak {s['peak_hz']:.2g} Hz)")
    ax.set(title="residual spectrum (Welch)", xlabel="f [Hz]", ylabel="PSD")
    ax.legend(fontsize=7)
    ax = fig.add_subplot(gs[3, :])
    ax.axis("off")
    eq = d["located"].get("equations", {})
    text = ["Equation errors along the measured trajectory:"] + \
        [f"  {v['balance']}: RMS error {v['relative_rms']:.2g} × RMS of the measured rate" for v in eq.values()]
    text += ["", "Base parameters judged implausible:"] + \
        [f"  {p['name']} = {p['value']:.4g}: {p['why']}" for p in d["base_parameters"] if p["implausible"]][:8]
    ax.text(0, 1, "\n".join(text), va="top", family="monospace", fontsize=7)
    return fig


def _ranking(diag):
    d = diag.data
    fig = style.figure(style.PORTRAIT)
    ax = fig.add_subplot(111)
    ax.axis("off")
    rows = [f"{'round':>5} {'effect':<28} {'component':<22} {'score':>7} {'ΔBIC':>9} {'pass':>5}"]
    for r in d["ranking"][:40]:
        dbic = f"{r['delta_bic']:+.0f}" if "delta_bic" in r else "-"
        rows.append(f"{r['round']:>5} {r['effect']:<28} {r['component'][:22]:<22} {100 * r['score']:>6.1f}% "
                    f"{dbic:>9} {('yes' if r.get('passed') else 'no' if r.get('fitted') else '-'):>5}")
    stop = d.get("stopped_at_noise_floor")
    if stop:
        rows += ["", f"Round {stop['round']} not screened: validation ESR {stop['esr_validation']:.3g} % against a noise "
                     f"floor of {stop['noise_floor']:.3g} %;", f"no effect could gain the {stop['noise_band']:.3g} % "
                     "it needs (no model predicts held-out data better than their noise)."]
    rows += ["", "Skipped:"] + [f"  {s['effect']}: {s['reason']}" for s in d["skipped"]][:20]
    ax.text(0, 1, "Candidate ranking (score: explained share of the residual — screening, or train SSR "
                  "reduction when re-identified)\n\n" + "\n".join(rows), va="top", family="monospace", fontsize=6.5)
    return fig


def _before_after(diag, exps, before, after, title):
    fig = style.figure(style.PORTRAIT)
    fig.suptitle(title, fontsize=11)
    e, Yb, Ya = exps[0], before[0], after[0]
    outs = [o for o in diag.outputs if o in e.measured]
    gs = fig.add_gridspec(len(outs), 3, hspace=0.35, wspace=0.3)
    worst = _worst_window(e, Yb, diag)
    for k, o in enumerate(outs):
        f, unit = _display(diag.final.model, o)
        y = e.measured[o] / f
        yb = Yb[:, diag.base.model.output_names.index(o)] / f
        ya = Ya[:, diag.final.model.output_names.index(o)] / f
        for col, span in ((slice(0, 2), None), (2, worst)):
            ax = fig.add_subplot(gs[k, col])
            m = slice(None) if span is None else (e.t_out >= span[0]) & (e.t_out <= span[1])
            ax.plot(e.t_out[m], y[m], "k", lw=0.6, label="measured")
            ax.plot(e.t_out[m], yb[m], lw=0.7, label="base")
            ax.plot(e.t_out[m], ya[m], lw=0.7, ls="--", label="augmented")
            ax.tick_params(labelsize=6)
            if span is None:
                ax.set_ylabel(f"{o} [{unit}]", fontsize=8)
                if k == 0:
                    ax.legend(fontsize=7, ncol=3)
            elif k == 0:
                ax.set_title("zoom: worst 2 s of the base model", fontsize=7)
    return fig


def _display(model, o: str) -> tuple[float, str]:
    """(SI per display unit, display unit) of an output: the machine file's unit (bar, mm)."""
    unit = model.output_units.get(o) or ""
    try:
        return (si_factor(unit), unit) if unit else (1.0, model.output_unit_si(o) or "-")
    except HydroError:
        return 1.0, model.output_unit_si(o) or "-"


def _worst_window(e, Yb, diag, width=2.0):
    """Centre a zoom window where the base model's normalised residual energy is largest."""
    r = np.zeros(e.t_out.size)
    for o in (o for o in diag.outputs if o in e.measured):
        y = e.measured[o]
        r += ((Yb[:, diag.base.model.output_names.index(o)] - y) / (np.std(y) or 1.0)) ** 2
    n = max(int(width / max(float(np.median(np.diff(e.t_out))), 1e-9)), 1)
    k = int(np.argmax(np.convolve(np.nan_to_num(r), np.ones(n), "same")))
    t0 = max(e.t_out[k] - width / 2, e.t_out[0])
    return t0, t0 + width


def _before_after_train(diag):
    b, a = diag.data["esr_train_base"], diag.data["esr_train_final"]
    return _before_after(diag, diag.train, diag.base.Y_train, diag.final.Y_train,
                         f"Training ({diag.train[0].name}): ESR " + _pair(b, a))


def _before_after_validation(diag):
    b, a = diag.data["esr_validation_base"], diag.data["esr_validation_final"]
    return _before_after(diag, diag.validate, diag.base.Y_validation, diag.final.Y_validation,
                         f"Validation ({diag.validate[0].name}): ESR " + _pair(b, a))


def _pair(b, a):
    return ", ".join(f"{o} {b[o]:.3g}→{a[o]:.3g} %" for o in b)
