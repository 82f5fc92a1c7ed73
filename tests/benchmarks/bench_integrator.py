"""Benchmark of the compiled RODAS integrator (plain script; not collected by pytest).

    cd /work/main && python tests/benchmarks/bench_integrator.py [--quick]

1. Seed-004 electro-hydraulic actuator (7 states, 20 s, 1 kHz output): hand-written C
   model through hydrocli.solve.compiled vs the same model in Python with
   scipy.integrate.solve_ivp(method="BDF"), at equal accuracy versus a Radau
   (rtol=1e-10) reference.  Prints the speed ratio for every coefficient set
   (HY_METHOD 1 Rodas4, 2 Rodas4P, 3 Rodas5P = default): median time, error,
   steps accepted+rejected.
2. Scaling: 1/10/50 cylinder subsystems, block-diagonal (independent) and arrow
   (all share one supply-pressure state), cost per simulated second.
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import tempfile
import time
from bisect import bisect_right
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # no BLAS spin threads on a 2-core box

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from hydrocli.solve.compiled import CompiledModel, build_library  # noqa: E402

# ----------------------------------------------------------------------------- model
PARAMS = dict(
    K_rl=5000.0, smax=20.0, tau=4e-3, Kv=4.68e-7, dp_lam=5e4, beta=1.73e9, A=2.0994e-3,
    V10=2.11e-4, V20=6.75e-4, c_il=2.18e-11, m=74.11, Pd=1e5, eps=1e-4,
    kvp=1.21e4, kcp=1140.0, ksp=244.37, tsp=3.41e-3,
    kvn=1.37e4, kcn=1180.0, ksn=39.36, tsn=1.96e-3,
)
PNAMES = list(PARAMS)
P = np.array([PARAMS[k] for k in PNAMES])
X0 = np.array([0.0, 0.0, 0.0, 5e6, 5e6, 0.07, 0.0])
SCALE = np.array([0.1, 0.1, 25.0, 1e7, 1e7, 0.1, 0.1])  # typical magnitudes (for atol)
T_END = 20.0

# C body of one cylinder: states xs[0..6], inputs uc (valve), Ps, Fext; writes ds[0..6];
# returns flow drawn from supply in `qs`.
CYL_C = r"""
    {
    const double K_rl=p[0], smax=p[1], tau=p[2], Kv=p[3], dpl=p[4], beta=p[5], A=p[6];
    const double V10=p[7], V20=p[8], cil=p[9], m=p[10], Pd=p[11], eps=p[12];
    const double xr=xs[0], xv=xs[1], xvd=xs[2], P1=xs[3], P2=xs[4], x=xs[5], v=xs[6];
    double xvp = xv > 0 ? xv : 0.0, xvn = xv < 0 ? -xv : 0.0, d, q1, q2, F, V1, V2;
    #define QOR(dp) (Kv*(dp)/sqrt(sqrt((dp)*(dp) + dpl*dpl)))
    ds[0] = smax*tanh(K_rl*(uc - xr)/smax);
    ds[1] = xvd;
    ds[2] = (xr - xv - 2.0*tau*xvd)/(tau*tau);
    q1 = xvp*QOR(Ps - P1) - xvn*QOR(P1 - Pd);
    q2 = xvn*QOR(Ps - P2) - xvp*QOR(P2 - Pd);
    qs += xvp*QOR(Ps - P1) + xvn*QOR(Ps - P2);
    #undef QOR
    V1 = V10 + A*x; V2 = V20 - A*x;
    if (V1 <= 0.0 || V2 <= 0.0) return 1;
    d = cil*(P1 - P2);
    ds[3] = beta*(q1 - A*v - d)/V1;
    ds[4] = beta*(q2 + A*v + d)/V2;
    {
        const double th = tanh(v/eps);
        if (v >= 0) F = p[13]*v + p[14]*th + p[15]*th*exp(-fabs(v)/p[16]);
        else        F = p[17]*v + p[18]*th + p[19]*th*exp(-fabs(v)/p[20]);
    }
    ds[5] = v;
    ds[6] = (A*(P1 - P2) - F + Fext)/m;
    }
"""

CYL_PATTERN = [  # (row, col) within one cylinder
    (0, 0), (1, 2), (2, 0), (2, 1), (2, 2),
    (3, 1), (3, 3), (3, 4), (3, 5), (3, 6),
    (4, 1), (4, 3), (4, 4), (4, 5), (4, 6),
    (5, 6), (6, 3), (6, 4), (6, 6),
]


def eha_c_source(ncyl: int = 1, arrow: bool = False) -> str:
    """C model of `ncyl` cylinders (7 states each); arrow: one extra supply-pressure
    state fed by a pump (flow source) and drained by all valves."""
    nx = 7 * ncyl + (1 if arrow else 0)
    pat = set()
    for c in range(ncyl):
        o = 7 * c
        pat.update((o + r, o + k) for r, k in CYL_PATTERN)
        pat.update((o + i, o + i) for i in range(7))
        if arrow:
            s = nx - 1
            pat.update({(o + 3, s), (o + 4, s), (s, o + 1), (s, o + 3), (s, o + 4)})
    if arrow:
        pat.add((nx - 1, nx - 1))
    pat = sorted(pat)
    rows = ",".join(str(r) for r, _ in pat)
    cols = ",".join(str(c) for _, c in pat)
    if arrow:
        ps_expr = "x[HY_NX-1]"
        tail = (
            "    /* supply node: pump flow + relief (regulates to ~1e7 Pa), drained by valves */\n"
            "    dx[HY_NX-1] = 1.5e9*(%d*(1.2e-4 - 1.2e-10*(x[HY_NX-1] - 9e6)) - qs)/%g;\n"
            % (ncyl, 2e-3 * ncyl)
        )
    else:
        ps_expr = "u[1]"
        tail = ""
    return f"""
#include <math.h>
#define HY_NX {nx}
#define HY_NP {len(PNAMES)}
#define HY_NU 3
#define HY_NY 1
#define HY_NNZ {len(pat)}
static const int HY_JAC_ROW[HY_NNZ] = {{{rows}}};
static const int HY_JAC_COL[HY_NNZ] = {{{cols}}};
static int hy_rhs(double t, const double *x, const double *p, const double *u, double *dx)
{{
    const double uc = u[0], Fext = u[2], Ps = {ps_expr};
    double qs = 0.0;
    int c;
    (void)t;
    for (c = 0; c < {ncyl}; ++c) {{
        const double *xs = x + 7*c;
        double *ds = dx + 7*c;
{CYL_C}
    }}
{tail}    return 0;
}}
static int hy_out(double t, const double *x, const double *p, const double *u, double *y)
{{
    (void)t; (void)p; (void)u;
    y[0] = x[5];
    return 0;
}}
"""


def inputs(t_end: float = T_END, fs: float = 1000.0):
    t = np.linspace(0.0, t_end, int(round(t_end * fs)) + 1)
    u = 0.1 * np.sin(2 * np.pi * 0.5 * t) + 0.05 * np.sign(np.sin(2 * np.pi * 0.2 * t))
    ps = 1e7 + 5e4 * np.sin(2 * np.pi * 25 * t)
    fext = 2000.0 * np.sin(2 * np.pi * 1.6 * t)
    return t, np.column_stack([u, ps, fext])


def python_rhs_factory(t_in, U):
    """Scalar Python RHS (math module + bisect lookup; as fast as plain Python gets)."""
    ti = t_in.tolist()
    cols = [U[:, j].tolist() for j in range(U.shape[1])]
    n = len(ti)
    (K_rl, smax, tau, Kv, dpl, beta, A, V10, V20, cil, m, Pd, eps,
     kvp, kcp, ksp, tsp, kvn, kcn, ksn, tsn) = P.tolist()
    sqrt, tanh, exp = math.sqrt, math.tanh, math.exp

    def interp(t):
        k = bisect_right(ti, t) - 1
        if k < 0:
            return [c[0] for c in cols]
        if k >= n - 1:
            return [c[-1] for c in cols]
        th = (t - ti[k]) / (ti[k + 1] - ti[k])
        return [c[k] + th * (c[k + 1] - c[k]) for c in cols]

    def q(dp):
        return Kv * dp / sqrt(sqrt(dp * dp + dpl * dpl))

    def rhs(t, s):
        uc, Ps, Fext = interp(t)
        xr, xv, xvd, P1, P2, x, v = s
        xvp = xv if xv > 0 else 0.0
        xvn = -xv if xv < 0 else 0.0
        q1 = xvp * q(Ps - P1) - xvn * q(P1 - Pd)
        q2 = xvn * q(Ps - P2) - xvp * q(P2 - Pd)
        d = cil * (P1 - P2)
        th = tanh(v / eps)
        if v >= 0:
            F = kvp * v + kcp * th + ksp * th * exp(-abs(v) / tsp)
        else:
            F = kvn * v + kcn * th + ksn * th * exp(-abs(v) / tsn)
        return [
            smax * tanh(K_rl * (uc - xr) / smax),
            xvd,
            (xr - xv - 2 * tau * xvd) / (tau * tau),
            beta * (q1 - A * v - d) / (V10 + A * x),
            beta * (q2 + A * v + d) / (V20 - A * x),
            v,
            (A * (P1 - P2) - F + Fext) / m,
        ]

    return rhs


def err_metric(X, Xref):
    """max over states of max-abs error relative to that state's reference range."""
    scale = np.max(np.abs(Xref), axis=0) + 1e-30
    return float(np.max(np.max(np.abs(X - Xref), axis=0) / scale))


METHODS = {"rodas4": 1, "rodas4p": 2, "rodas5p": 3}


def median_time(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t1 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t1)
    return statistics.median(times), out


def best_time(fn, repeat):
    best = math.inf
    out = None
    for _ in range(repeat):
        t1 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t1)
    return best, out


def bench_eha(cache, quick=False):
    t_in, U = inputs()
    hold = np.zeros(3, dtype=int)
    t_out = t_in.copy()
    so = build_library(eha_c_source(1), cache_dir=cache)
    model = CompiledModel(so, 7, len(PNAMES), 3, 1)
    rhs = python_rhs_factory(t_in, U)

    print("== seed-004 EHA, 7 states, 20 s, 1 kHz output ==")
    # reference
    t1 = time.perf_counter()
    if quick:
        r = model.simulate(P, t_in, U, hold, 0.0, X0, t_out, rtol=1e-11, atol=1e-11 * SCALE)
        Xref = r.X
        print(f"reference: compiled (default method) rtol=1e-11 ({time.perf_counter() - t1:.2f} s)")
    else:
        ref = solve_ivp(rhs, (0, T_END), X0, method="Radau", rtol=1e-10, atol=1e-10 * SCALE,
                        t_eval=t_out)
        Xref = ref.y.T
        print(f"reference: scipy Radau rtol=1e-10 ({time.perf_counter() - t1:.1f} s, "
              f"nfev={ref.nfev}, status={ref.status})")
        rc = model.simulate(P, t_in, U, hold, 0.0, X0, t_out, rtol=1e-11, atol=1e-11 * SCALE)
        print(f"  compiled rtol=1e-11 vs Radau reference: err={err_metric(rc.X, Xref):.2e}")

    methods = {name: CompiledModel(build_library(f"#define HY_METHOD {k}\n" + eha_c_source(1),
                                                 cache_dir=cache), 7, len(PNAMES), 3, 1)
               for name, k in METHODS.items()}
    rows = []
    for rtol_bdf in ([1e-5] if quick else [1e-4, 1e-5, 1e-6]):
        tb, sol = best_time(lambda: solve_ivp(rhs, (0, T_END), X0, method="BDF", rtol=rtol_bdf,
                                              atol=rtol_bdf * SCALE, t_eval=t_out), 1)
        e_bdf = err_metric(sol.y.T, Xref)
        print(f"BDF rtol={rtol_bdf:.0e}: {tb:7.3f} s  nfev={sol.nfev:6d}  err={e_bdf:.2e}")
        for name, mod in methods.items():
            # loosest compiled tolerance (quarter decades) that is at least as accurate
            chosen = None
            for k in range(-8, 25):
                rt = rtol_bdf * 10 ** (-k / 4)
                r = mod.simulate(P, t_in, U, hold, 0.0, X0, t_out, rtol=rt, atol=rt * SCALE)
                e = err_metric(r.X, Xref)
                if r.status == 0 and e <= e_bdf:
                    chosen = (rt, e)
                    break
            rt, e = chosen
            tc, r = median_time(lambda: mod.simulate(P, t_in, U, hold, 0.0, X0, t_out, rtol=rt,
                                                     atol=rt * SCALE), 21)
            rows.append((rtol_bdf, name, tb, sol.nfev, e_bdf, rt, tc, r.stats, e))
            print(f"   {name:8s} rtol={rt:.2e}: {tc * 1e3:7.3f} ms (median)  steps="
                  f"{r.stats['steps_accepted']}+{r.stats['steps_rejected']} "
                  f"nfev={r.stats['rhs_evals']} err={e:.2e} | ratio {tb / tc:7.0f}x")
    return rows


def bench_scaling(cache):
    print("== scaling: N cylinders (7 states each), 20 s, rtol=1e-6 ==")
    t_in, U = inputs()
    hold = np.zeros(3, dtype=int)
    t_out = t_in[::10].copy()  # 100 Hz output to keep the output cost out of the picture
    for arrow in (False, True):
        base = None
        for n in (1, 10, 50):
            src = eha_c_source(n, arrow=arrow)
            nx = 7 * n + (1 if arrow else 0)
            model = CompiledModel(build_library(src, cache_dir=cache), nx, len(PNAMES), 3, 1)
            x0 = np.concatenate([X0] * n + ([np.array([1e7])] if arrow else []))
            sc = np.concatenate([SCALE] * n + ([np.array([1e7])] if arrow else []))
            tc, r = best_time(lambda: model.simulate(P, t_in, U, hold, 0.0, x0, t_out, rtol=1e-6,
                                                     atol=1e-6 * sc), 3 if n < 50 else 2)
            per_s = tc / T_END
            if base is None:
                base = per_s
            print(f"{'arrow' if arrow else 'block'} N={n:3d} nx={nx:4d}: {tc * 1e3:8.2f} ms "
                  f"({per_s * 1e3:.3f} ms per simulated s), status={r.status}, "
                  f"steps={r.stats['steps_accepted']}, nfev/step="
                  f"{r.stats['rhs_evals'] / max(1, r.stats['steps_accepted']):.1f}, "
                  f"cost/(N*cost1)={per_s / (n * base):.2f}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="compiled reference, one BDF run")
    ap.add_argument("--cache", default=None)
    args = ap.parse_args()
    cache = Path(args.cache) if args.cache else Path(tempfile.mkdtemp(prefix="hybench_"))
    bench_eha(cache, quick=args.quick)
    bench_scaling(cache)


if __name__ == "__main__":
    main()
