"""``hydro bench``: speed of the compiled model against what a user writes today.

Baseline (run in the same process): seed 004's EHA written by hand as a Python
right-hand side and integrated with ``scipy.integrate.solve_ivp(method="BDF")`` (and
``LSODA``). Contender: the same machine from ``machines/eha_testbench.yaml`` through the
builder, generated C and the compiled Rosenbrock integrator. Both are compared with a
tight-tolerance reference (the hand-written model under Radau, rtol 1e-10) so ratios are
quoted at equal or better accuracy. Also: cost per simulated second for 1, 10 and 50
cylinder circuits, and model build time (cold compile vs warm cache).
"""
from __future__ import annotations

import math
import statistics
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .model.builder import build_model
from .netlist.loader import load_netlist, load_netlist_text
from .solve.library import compiled
from .solve.simulate import InputTable, SolverOptions, simulate

EHA = Path(__file__).resolve().parent.parent / "machines" / "eha_testbench.yaml"


def eha_inputs(t_end: float = 20.0, rate: float = 1000.0):
    """The benchmark excitation: valve sine + square, supply ripple, sinusoidal load."""
    t = np.arange(0.0, t_end + 0.5 / rate, 1.0 / rate)
    u = 0.1 * np.sin(2 * np.pi * 0.5 * t) + 0.05 * np.sign(np.sin(2 * np.pi * 0.2 * t))
    ps = 1e7 + 5e4 * np.sin(2 * np.pi * 25 * t)
    fext = 2000.0 * np.sin(2 * np.pi * 1.6 * t)
    return t, np.column_stack([u, ps, fext])


@dataclass
class EhaParams:
    """Seed 004 §V identified values (the machine file's values)."""

    Kv: float = 4.68e-7
    tau: float = 4e-3
    zeta: float = 1.0
    s_max: float = 20.0
    tau_rl: float = 1e-4
    eps_x: float = 1e-4
    dp_lam: float = 5e4
    A: float = 2.0994e-3
    V10: float = 2.11e-4
    V20: float = 6.75e-4
    beta: float = 1.73e9
    c_il: float = 2.18e-11
    m: float = 74.11
    kv: tuple = (1.21e4, 1.37e4)
    kc: tuple = (1.14e3, 1.18e3)
    ks: tuple = (244.37, 39.36)
    vs: tuple = (3.41e-3, 1.96e-3)
    eps_v: float = 1e-4
    p_tank: float = 1e5


def handwritten_rhs(t_in, U, P: EhaParams):
    """Seed 004 eqs. 1–12 written by hand (state: xr, xv, xv_dot, P1, P2, v, x)."""
    sqrt, tanh, exp = math.sqrt, math.tanh, math.exp
    u_col, ps_col, f_col = U[:, 0], U[:, 1], U[:, 2]

    def opening(x, o=0.0):
        d = x - o
        return 0.5 * (d + sqrt(d * d + P.eps_x * P.eps_x))

    def q(dp):
        return dp / sqrt(sqrt(dp * dp + P.dp_lam * P.dp_lam))

    def rhs(t, s):
        xr, xv, xd, p1, p2, v, x = s
        u = np.interp(t, t_in, u_col)
        ps = np.interp(t, t_in, ps_col)
        fext = np.interp(t, t_in, f_col)
        dxr = P.s_max * tanh((u - xr) / (P.tau_rl * P.s_max))
        dxd = (xr - xv - 2 * P.zeta * P.tau * xd) / (P.tau * P.tau)
        ap, an = opening(xv), opening(-xv)
        qa = P.Kv * ap * q(ps - p1) - P.Kv * an * q(p1 - P.p_tank)
        qb = P.Kv * an * q(ps - p2) - P.Kv * ap * q(p2 - P.p_tank)
        leak = P.c_il * (p1 - p2)
        dp1 = (qa - P.A * v - leak) * P.beta / (P.V10 + P.A * x)
        dp2 = (qb + P.A * v + leak) * P.beta / (P.V20 - P.A * x)
        k = 0 if v >= 0 else 1
        fr = P.kv[k] * v + (P.kc[k] + P.ks[k] * exp(-abs(v) / P.vs[k])) * tanh(v / P.eps_v)
        dv = (P.A * (p1 - p2) - fr + fext) / P.m
        return [dxr, xd, dxd, dp1, dp2, dv, v]
    return rhs


HAND_ORDER = ["valve.xr", "valve.xv", "valve.xv_dot", "chamber_1.p", "chamber_2.p", "piston.v", "piston.x"]
X0 = {"chamber_1.p": 5e6, "chamber_2.p": 5e6, "piston.x": 0.07}
ATOL_HAND = np.array([1e-5, 1e-5, 1e-3, 1e2, 1e2, 1e-5, 1e-5])


def _median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def _errors(Xa: np.ndarray, Xref: np.ndarray) -> tuple[float, float]:
    """Max pressure error [bar] and max velocity error [mm/s] (hand-written state order)."""
    dp = np.max(np.abs(Xa[:, 3:5] - Xref[:, 3:5])) / 1e5
    dv = np.max(np.abs(Xa[:, 5] - Xref[:, 5])) * 1e3
    return float(dp), float(dv)


def bench_eha(repeat: int = 5, t_end: float = 20.0, baseline_rtol: float = 1e-6, echo=print) -> dict:
    from scipy.integrate import solve_ivp

    t, U = eha_inputs(t_end)
    model = build_model(load_netlist(EHA))
    order = [model.state_index(n) for n in HAND_ORDER]
    x0 = model.x0.copy()
    for k, v in X0.items():
        x0[model.state_index(k)] = v
    x0_hand = x0[order]
    rhs = handwritten_rhs(t, U, EhaParams())
    echo(f"EHA (seed 004), {t_end:g} s simulated, {t.size} output samples")
    ref = solve_ivp(rhs, (0, t_end), x0_hand, method="Radau", t_eval=t, rtol=1e-10, atol=ATOL_HAND * 1e-4)
    Xref = ref.y.T
    results = {}
    for method in ("BDF", "LSODA"):
        secs, sol = _median_time(lambda: solve_ivp(rhs, (0, t_end), x0_hand, method=method, t_eval=t,
                                                   rtol=baseline_rtol, atol=ATOL_HAND * 1e-2), 1 if method == "BDF" else repeat)
        results[method] = (secs, _errors(sol.y.T, Xref))
        echo(f"  scipy {method:5s} (Python rhs, rtol {baseline_rtol:g}): {secs * 1e3:9.1f} ms   "
             f"max error {results[method][1][0]:.2e} bar, {results[method][1][1]:.2e} mm/s")
    inputs = InputTable(t, U)
    compiled(model)
    best = None
    for rtol in (1e-4, 1e-5, 1e-6, 1e-7):
        opts = SolverOptions(rtol=rtol)
        secs, tr = _median_time(lambda: simulate(model, inputs, t, x0=x0, opts=opts), repeat)
        err = _errors(tr.X[:, order], Xref)
        echo(f"  hydrocli compiled (rtol {rtol:g}):          {secs * 1e3:9.2f} ms   max error {err[0]:.2e} bar, "
             f"{err[1]:.2e} mm/s   {int(tr.stats.get('steps_accepted', 0))} steps")
        if best is None and err[0] <= results["BDF"][1][0] and err[1] <= results["BDF"][1][1]:
            best = (rtol, secs, err)
    if best is None:
        best = (rtol, secs, err)
    ratio = results["BDF"][0] / best[1]
    echo(f"  → at equal or better accuracy (rtol {best[0]:g}): {ratio:,.0f}× faster than BDF, "
         f"{results['LSODA'][0] / best[1]:,.0f}× faster than LSODA")
    return {"bdf_s": results["BDF"][0], "lsoda_s": results["LSODA"][0], "hydro_s": best[1],
            "hydro_rtol": best[0], "ratio_bdf": ratio}


def n_cylinder_machine(n: int) -> str:
    """n EHA circuits on one supply line (a volume fed through an orifice): every circuit
    couples to the shared supply pressure, so the Jacobian has an arrow pattern."""
    lines = ["name: bench_%d" % n, "fluid: {beta: 1.73 GPa, p_tank: 1 bar}",
             "inputs: {u: {unit: '%'}, Ps: {unit: Pa}, Fext: {unit: N}}",
             "templates:", "  axis:", "    ports: [P, T, cmd, F]", "    components:"]
    comps = {
        "valve": "{type: valve_4_3, ports: {P: P, T: T, A: c1, B: c2, cmd: cmd}, Kv: 4.68e-7, tau: 4 ms, s_max: 2000 %/s}",
        "cyl": "{type: cylinder_double_rod, ports: {A: c1, B: c2, rod: rod, body: ground}, A: 2.0994e-3, "
               "V_A0: 2.11e-4, V_B0: 6.75e-4, c_il: 2.18e-11}",
        "load": "{type: mass, ports: {m: rod}, m: 74.11}",
        "fr": "{type: friction, ports: {a: rod, b: ground}, kv_p: 1.21e4, kv_m: 1.37e4, kc_p: 1140, kc_m: 1180, "
              "ks_p: 244.37, ks_m: 39.36}",
        "ext": "{type: force_source, ports: {a: rod, F: F}}",
    }
    lines += [f"      {k}: {v}" for k, v in comps.items()]
    lines += ["components:", "  supply: {type: pressure_source, ports: {P: pump, ref: Ps}}",
              "  supply_line: {type: orifice, ports: {A: pump, B: sl}, Kv: 1.0e-5}",
              "  supply_volume: {type: volume, ports: {P: sl}, V: 1 L}",
              "  tank: {type: tank, ports: {T: rl}}"]
    lines += [f"  ax{i}: {{template: axis, ports: {{P: sl, T: rl, cmd: u, F: Fext}}}}" for i in range(n)]
    lines += ["initial:", "  sl.p: 100 bar"] + [f"  ax{i}.rod.x: 0.07\n  ax{i}.c1.p: 50 bar\n  ax{i}.c2.p: 50 bar" for i in range(n)]
    return "\n".join(lines) + "\n"


def bench_scaling(sizes=(1, 10, 50), t_end: float = 5.0, repeat: int = 3, echo=print) -> dict:
    t, U = eha_inputs(t_end)
    out = {}
    echo(f"Scaling: n cylinder circuits on one supply, {t_end:g} s simulated")
    for n in sizes:
        model = build_model(load_netlist_text(n_cylinder_machine(n), f"<bench {n}>"))
        t0 = time.perf_counter()
        compiled(model)
        build_s = time.perf_counter() - t0
        secs, _ = _median_time(lambda: simulate(model, InputTable(t, U), t, opts=SolverOptions(rtol=1e-5)), repeat)
        out[n] = secs / t_end
        echo(f"  n = {n:3d}: {len(model.state_names):4d} states, {secs / t_end * 1e3:8.2f} ms per simulated s "
             f"({out[n] / out[sizes[0]] / n:5.2f} × linear), compile {build_s:.2f} s")
    return out


def bench_build(echo=print) -> dict:
    """Model build time: cold (empty cache: codegen + compile) and warm (cache hit)."""
    import os

    with tempfile.TemporaryDirectory() as tmp:
        old = os.environ.get("HYDRO_CACHE_DIR")
        os.environ["HYDRO_CACHE_DIR"] = tmp
        try:
            times = {}
            for label in ("cold", "warm"):
                t0 = time.perf_counter()
                m = build_model(load_netlist(EHA))
                compiled(m)
                times[label] = time.perf_counter() - t0
        finally:
            if old is None:
                os.environ.pop("HYDRO_CACHE_DIR", None)
            else:
                os.environ["HYDRO_CACHE_DIR"] = old
    echo(f"Model build (load + build + compile): cold {times['cold']:.2f} s, warm cache {times['warm'] * 1e3:.0f} ms")
    return times


def run_all(quick: bool = False, echo=print) -> dict:
    return {"eha": bench_eha(repeat=3 if quick else 7, echo=echo),
            "scaling": bench_scaling(t_end=2.0 if quick else 5.0, echo=echo),
            "build": bench_build(echo=echo)}
