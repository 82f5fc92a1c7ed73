"""``hydro identify``: fit free parameters to recordings (single, staged, steady, batch).

    hydro identify MACHINE --experiment E1 [--experiment E2 …] [--free comp.param[=lo:hi] …]
        [--method least-squares|nelder-mead|differential-evolution] [--cost esr|seed004|wls]
        [--outputs P1,P2,v] [--mode dynamic|steady] --out identified.yaml [--results run.h5]
        [--max-evals N] [--set comp.param=VALUE …] [--add-free comp.param[=lo:hi] …] [--rtol 1e-6]
        [--gradient auto|sensitivities|finite-differences] [--workers 2] [--profile comp.param|all …]
    hydro identify MACHINE --stages stages.yaml --out identified.yaml [--results run.h5]
    hydro identify MACHINE --batch 'experiments/festo/*.yaml' --jobs N [--scheduler tcp://HOST:PORT]
        --out table.csv

``--out`` is the machine YAML with the identified values written back (comments and units
kept; a diff is printed), or in batch mode the CSV table. ``--results run.h5`` simulates each
experiment with the identified parameters and writes it with ``/identify``; with several
experiments the files are ``run_<experiment>.h5`` next to the given name.

A dynamic fit also prints 95 % block-bootstrap intervals, what the data do not determine,
and the fixed parameters whose error would move the estimates (free one with ``--add-free``);
``--max-evals`` caps every simulation and the progress bar counts the same simulations.
It names the estimates that move between parts of the recording more than the noise explains
(a model error no interval can bound). ``--profile NAME`` (repeatable, or ``all``) adds
profile-likelihood intervals from refits with NAME held at trial values (a few refits each).
"""
from __future__ import annotations

import glob
from pathlib import Path

import typer

from .options import SET


def register(app: typer.Typer) -> None:
    @app.command("identify")
    def identify_cmd(
        machine: Path = typer.Argument(..., help="machine YAML file"),
        experiment: list[str] = typer.Option(None, "--experiment", "-e", help="experiment YAML or recording; repeatable"),
        free: list[str] = typer.Option(None, "--free", help="free parameter comp.param or comp.param=lo:hi (SI or units); "
                                                             "default: those marked free in the machine"),
        method: str = typer.Option("least-squares", "--method", help="least-squares | nelder-mead | differential-evolution"),
        cost: str = typer.Option("esr", "--cost", help="esr | seed004 | wls"),
        outputs: str = typer.Option(None, "--outputs", help="outputs to fit, e.g. P1,P2,v (default: the experiment's 'fit:')"),
        mode: str = typer.Option("dynamic", "--mode", help="dynamic (whole transients) | steady (plateau averages)"),
        out: Path = typer.Option(None, "--out", "-o", help="identified machine YAML (batch: CSV table)"),
        results: Path = typer.Option(None, "--results", help="HDF5 result with /identify (several experiments: run_<exp>.h5)"),
        max_evals: int = typer.Option(400, "--max-evals", help="maximum number of simulations (residuals, Jacobian "
                                                               "columns and sensitivity runs all count)"),
        add_free: list[str] = typer.Option(None, "--add-free", help="free this parameter too, comp.param or "
                                                                    "comp.param=lo:hi; repeatable"),
        gradient: str = typer.Option("auto", "--gradient", help="least-squares Jacobian: auto | sensitivities | "
                                                                "finite-differences"),
        stages: Path = typer.Option(None, "--stages", help="stages YAML file (staged identification)"),
        batch: str = typer.Option(None, "--batch", help="glob of experiment files, each fitted separately"),
        jobs: int = typer.Option(2, "--jobs", "-j", help="batch: parallel worker processes"),
        scheduler: str = typer.Option(None, "--scheduler", help="batch: Dask scheduler address tcp://HOST:PORT"),
        workers: int = typer.Option(2, "--workers", help="threads for a Jacobian: finite-difference columns, "
                                    "or a sensitivity run pipelined in two threads (states | columns)"),
        rtol: float = typer.Option(1e-6, "--rtol", help="relative tolerance of the integrator while fitting"),
        profile: list[str] = typer.Option(None, "--profile", help="profile-likelihood interval of this free "
                                                                  "parameter (refits; repeatable, or 'all')"),
        sets: list[str] = SET,
    ) -> None:
        """Identify uncertain parameters from recordings and write the identified machine."""
        from .main import run_guarded
        run_guarded(_run, locals())


def _usage(msg: str) -> None:
    from ..errors import UsageError
    raise UsageError(msg)


METHODS = ("least-squares", "nelder-mead", "differential-evolution")
COSTS = ("esr", "seed004", "wls")
MODES = ("dynamic", "steady")


def _check_options(a: dict) -> None:
    """Option values out of range are usage errors (exit 2), before anything is loaded."""
    from .options import check_choice, check_positive
    check_choice("--method", a["method"], METHODS)
    check_choice("--cost", a["cost"], COSTS)
    check_choice("--mode", a["mode"], MODES)
    check_positive("--max-evals", a["max_evals"])
    check_positive("--workers", a["workers"])
    check_positive("--jobs", a["jobs"])
    check_positive("--rtol", a["rtol"], upper=1.0)


def _run(a: dict) -> None:
    from ..runner import load_machine
    from ..solve.simulate import SolverOptions

    n_modes = sum(bool(x) for x in (a["experiment"], a["stages"], a["batch"]))
    if n_modes != 1:
        _usage("give --experiment (one or more), --stages FILE, or --batch GLOB (exactly one of them)")
    if a["out"] is None:
        _usage("--out is required (identified machine YAML, or the CSV table with --batch)")
    _check_options(a)
    from ..fileio import guard_output
    inputs = [a["machine"], a["stages"], *(a["experiment"] or [])]
    guard_output(a["out"], inputs, "--out")
    if a["results"] is not None:
        guard_output(a["results"], inputs, "--results")
    net, model = load_machine(a["machine"], a["sets"])
    for w in model.warnings:
        typer.echo(f"warning: {w}", err=True)
    free, bounds = parse_free(a["free"], model)
    if a.get("add_free"):
        extra, extra_bounds = parse_free(a["add_free"], model)
        free = list(dict.fromkeys((free or model.free_params) + extra))
        bounds.update(extra_bounds)
    opts = SolverOptions(rtol=a["rtol"])
    outputs = [o.strip() for o in a["outputs"].split(",") if o.strip()] if a["outputs"] else None
    if a["batch"]:
        return _batch(a, model, free, bounds, outputs, opts)
    from ..experiments.experiment_file import load_all
    from .identify_output import print_fit, progress_bar, write_outputs
    if a["stages"]:
        from ..identify.staged import combine, load_stages, run_stages
        stages = load_stages(a["stages"], model)
        paths = list(dict.fromkeys(path for st in stages for path in st.experiments))
        loaded = {path: load_all(path, model) for path in paths}   # each file once; data errors before fitting
        from ..netlist.writer import check_write_back     # the write-back and the outputs, before any fitting
        check_write_back(net, list(dict.fromkeys(n for st in stages for n in st.free)))
        from ..fileio import guard_output
        guard_output(a["out"], (), "--out")
        with progress_bar(sum(s.max_evals for s in stages)) as prog:
            p, res_list = run_stages(model, stages, loaded.__getitem__, opts=opts,
                                     progress=prog.update, workers=a["workers"],
                                     on_stage=lambda i, s: prog.stage(f"stage {i + 1}/{len(stages)}: {s.name}"))
        for st, r in zip(stages, res_list):
            typer.echo(f"\n== stage: {st.name} ({st.mode}) ==")
            print_fit(r)
        exps = [e for path in paths for e in loaded[path]]
        names = [n for r in res_list for n in r.names]
        write_outputs(net, model, exps, p, names, combine(res_list, stages), a["out"], a["results"], opts)
        return
    if a.get("profile"):                         # before the fit, not after it
        names = free if free is not None else model.free_params
        unknown = [n for n in a["profile"] if n != "all" and n not in names]
        if unknown:
            _usage(f"--profile {', '.join(unknown)}: not a free parameter of this fit ({', '.join(names)})")
    exps = [e for path in a["experiment"] for e in load_all(path, model)]
    _check_before_fit(net, model, free, a, exps, outputs)
    with progress_bar(a["max_evals"]) as prog:
        kw = dict(method=a["method"], cost=a["cost"], outputs=outputs, bounds=bounds, max_evals=a["max_evals"],
                  opts=opts, progress=prog.update, workers=a["workers"])
        if a["mode"] == "steady":
            from ..identify.steady import fit_steady
            kw.pop("cost")
            res, plateaus = fit_steady(model, exps, free, **kw)
            typer.echo(f"steady-state fit on {len(plateaus)} plateau(s)")
        elif a["mode"] == "dynamic":
            from ..identify.fit import fit
            res = fit(model, exps, free, gradient=a["gradient"], assess=True, **kw)
    print_fit(res)
    ident = res.as_dict()
    if a.get("profile"):
        ident.update(_profile(model, exps, res, a, bounds, outputs, opts))
    write_outputs(net, model, exps, res.p, res.names, ident, a["out"], a["results"], opts)


def _profile(model, exps, res, a, bounds, outputs, opts) -> dict:
    """Profile-likelihood intervals of --profile's parameters, printed and for /identify."""
    import numpy as np

    from ..identify.profile import profile_intervals
    if a["mode"] != "dynamic" or a["method"] != "least-squares":
        _usage("--profile needs a dynamic least-squares fit")
    names = res.names if "all" in a["profile"] else list(dict.fromkeys(a["profile"]))
    unknown = [n for n in names if n not in res.names]
    if unknown:
        _usage(f"--profile {', '.join(unknown)}: not a free parameter of this fit ({', '.join(res.names)})")
    typer.echo(f"profile-likelihood 95 % intervals (refits with the parameter held; {len(names)} parameter(s)):")
    out = profile_intervals(model, exps, res, names, bounds=bounds, cost=a["cost"], outputs=outputs, opts=opts,
                            gradient=a["gradient"], workers=a["workers"])
    for pi in out:
        i = res.names.index(pi.name)
        lo = "bound " if pi.at_bound[0] else ""
        hi = " bound" if pi.at_bound[1] else ""
        typer.echo(f"  {pi.name}: {res.estimates[i]:.5g} in [{lo}{pi.lower:.5g}, {pi.upper:.5g}{hi}] "
                   f"(bootstrap [{res.uncertainty.ci_lower[i]:.5g}, {res.uncertainty.ci_upper[i]:.5g}]; "
                   f"{pi.refits} refits)" if res.uncertainty is not None else
                   f"  {pi.name}: {res.estimates[i]:.5g} in [{lo}{pi.lower:.5g}, {pi.upper:.5g}{hi}] ({pi.refits} refits)")
        if not pi.reliable:
            typer.echo(f"    unreliable: a refit at the estimate misses the optimum's cost by {pi.precision:.1f}× the "
                       f"threshold (the refits do not converge precisely enough for this interval)")
    return {"profile_names": np.array([p.name for p in out], dtype=object),
            "profile_lower": np.array([p.lower for p in out]), "profile_upper": np.array([p.upper for p in out])}


def _check_before_fit(net, model, free, a, exps, outputs) -> None:
    """Everything that would make the end of a long fit fail, checked before it starts: the
    identified values can be written back, and the outputs (now that every input is read)
    are not inputs."""
    from ..fileio import guard_output
    from ..netlist.writer import check_write_back
    names = free if free is not None else [p.name for p in model.params if p.free]
    if not names:
        _usage("no free parameter: mark some 'free: true' in the machine or give --free comp.param")
    check_write_back(net, names)
    _check_samples_left(exps, outputs)
    guard_output(a["out"], (), "--out")
    if a["results"] is not None:
        guard_output(a["results"], (), "--results")


def _check_samples_left(exps, outputs) -> None:
    """A fit needs residuals: refuse when masks (or NaN) leave no sample of any fitted output."""
    import numpy as np

    from ..errors import DataError, Location, Problem
    total = 0
    for exp in exps:
        for o in [o for o in (outputs or exp.fit_outputs or list(exp.measured)) if o in exp.measured]:
            y = np.asarray(exp.measured[o], dtype=float)
            total += int((np.isfinite(y) & exp.mask.get(o, np.ones_like(y, dtype=bool))).sum())
    if total == 0:
        raise DataError(Problem("no sample is left to fit: every sample of the fitted outputs is masked or NaN",
                                Location(exps[0].file if exps else None, path="mask"),
                                "loosen 'mask:' or the 'window:', or fit other outputs"))


def parse_free(items, model) -> tuple[list[str] | None, dict[str, tuple[float, float]]]:
    """``comp.param`` or ``comp.param=lo:hi`` (numbers in SI, or strings with units). A bad
    option is a usage error (exit 2), with the parameter's did-you-mean."""
    from ..errors import HydroError, Location, Problem, UsageError
    from ..units import to_si
    if not items:
        return None, {}
    names, bounds = [], {}
    for item in items:
        name, eq, rng = item.partition("=")
        name = name.strip()
        try:
            i = model.param_index(name)
            if eq:
                parts = rng.split(":")
                if len(parts) != 2:
                    raise UsageError(Problem(f"--free {item}: bounds must be lo:hi", Location(path=f"--free {item}"),
                                             "e.g. --free valve.Kv=1e-7:2e-6 or --free cylinder.beta='0.5 GPa:2 GPa'"))
                unit = model.params[i].unit
                lo, hi = (to_si(p.strip(), unit, location=Location(path=f"--free {item}"), what=name) for p in parts)
                bounds[name] = (lo, hi)
        except UsageError:
            raise
        except HydroError as err:
            raise UsageError(err.problems) from None
        names.append(name)
    return names, bounds


def _batch(a, model, free, bounds, outputs, opts) -> None:
    from ..experiments.experiment_file import load_all
    from ..identify.batch import run_batch
    paths = sorted(glob.glob(a["batch"]))
    if not paths:
        from ..errors import DataError, Problem
        raise DataError(Problem(f"--batch '{a['batch']}' matches no file", hint="quote the glob so the shell keeps it"))
    exps = [e for p in paths for e in load_all(p, model)]
    where = a["scheduler"] or f"{a['jobs']} local process(es)"
    typer.echo(f"batch: {len(exps)} experiment(s) from {len(paths)} file(s) on {where}")
    options = dict(method=a["method"], cost=a["cost"], outputs=outputs, bounds=bounds, max_evals=a["max_evals"],
                   opts=opts)
    res = run_batch(model, exps, free, jobs=a["jobs"], scheduler=a["scheduler"], options=options,
                    on_done=lambda i, r: typer.echo(f"  [{i + 1}/{len(exps)}] {r['experiment']}: "
                                                   + (f"cost {r['cost']:.4g} in {r['seconds']:.1f} s" if "error" not in r
                                                      else "FAILED: " + r["error"].splitlines()[0])))
    from .identify_output import print_table
    print_table(res.table_rows())
    res.write_csv(a["out"])
    typer.echo(f"table → {a['out']}")
