/*
 * hy_integrator.c -- compiled stiff ODE integrator for hydrocli models.
 *
 * This file is #included textually at the END of a generated model translation
 * unit which has already defined HY_NX, HY_NP, HY_NU, HY_NY, HY_NNZ,
 * HY_JAC_ROW[], HY_JAC_COL[], hy_rhs() and hy_out() (see hydrocli/solve/compiled.py).
 * Only `hy_simulate` and `hy_model_info` are exported; everything else is static
 * so the compiler can inline the model right-hand side into the stage loops.
 *
 * METHOD
 * ------
 * A stiffly accurate, L-stable Rosenbrock(-Wanner) method of the RODAS family,
 * selected at compile time by HY_METHOD:
 *   1  RODAS4: 6 stages, order 4(3), E. Hairer, G. Wanner, "Solving Ordinary
 *      Differential Equations II", 2nd ed., Springer 1996, Sec. IV.7 (code RODAS,
 *      METH=1), order-3 dense output from the same code.
 *   2  RODAS4P: G. Steinebach, "Order-reduction of ROW-methods for DAEs and method
 *      of lines applications", Preprint 1741, TH Darmstadt 1995.  Same structure and
 *      cost as RODAS4, but satisfies the extra conditions that avoid order
 *      reduction on Prothero-Robinson-type problems (stiff states driven by
 *      time-varying inputs); order-3 dense output.
 *   3  RODAS5P (default): G. Steinebach, "Improvement of Rosenbrock-Wanner method
 *      RODASP" (2023).  8 stages, order 5(4), no order reduction on
 *      Prothero-Robinson problems, order-4 dense output.
 *   The RODAS4P/RODAS5P tables are those distributed with OrdinaryDiffEq.jl
 *   (Rodas4PTableau, Rodas5PTableau), which use exactly the RODAS conventions
 *   below; their orders are verified by tests/solve/test_integrator.py.
 * Why Rosenbrock: hydraulic models are stiff (oil compressibility, tight rate
 *   limiters, steep friction tanh) but smooth between input samples.  A Rosenbrock
 *   method needs no Newton iteration (one LU per step, s linear solves, s rhs
 *   calls), so a step has a fixed, small cost and no convergence failures; stiff
 *   accuracy and L-stability give clean behaviour on very stiff modes; the embedded
 *   solution gives a reliable error estimate; the dense output lets us produce a
 *   1 kHz output grid without shortening steps.
 * hydrocli compiles RODAS5P (the default) and, for SolverOptions(error_control="scaled")
 *   above rtol 1e-5 (the default of `hydro simulate`), a second library of the same model
 *   with HY_METHOD 2: at the accuracy of scipy BDF on the EHA RODAS4P needs ~25 % fewer
 *   right-hand sides (solve/simulate.py: method_for; docs/solver.md).
 * Why RODAS5P by default (measured on machines/eha_testbench.yaml, `hydro bench
 *   --only eha`, analytic Jacobian): to reach the accuracy of scipy BDF (rtol 1e-6)
 *   RODAS5P needs rtol 1e-7 and ~44k rhs calls / 4.3k steps, RODAS4 ~86k / 10k
 *   steps and RODAS4P ~71k / 8.3k steps (about 1.5-1.9x the time).
 * Formulation (transformed variables, as in RODAS; s = R_S stages):
 *   (I/(h*gam) - J) k_i = f(t + c_i h, x + sum_j a_ij k_j) + sum_j (c_ij/h) k_j + h d_i f_t
 *   the last stages use y_i = y_(i-1) + k_(i-1) (stiff accuracy);
 *   x_new = y_s + k_s;  error estimate = k_s (x_new minus the embedded solution).
 * Non-autonomous term f_t by a forward difference in t (inputs are evaluated on the
 *   segment the step starts in, so a kink of a linearly interpolated table is seen
 *   from the right).
 * Jacobian: analytic if the model defines HY_HAS_JAC and
 *   `static int hy_jac(t, x, p, u, double *jv)` (values in HY_JAC_ROW/COL order);
 *   otherwise forward differences with Curtis-Powell-Reid column grouping
 *   (greedy distance-2 colouring computed once per call from the sparsity pattern;
 *   each group costs one rhs evaluation).  The RODAS methods are not
 *   W-methods, so J is re-evaluated at every accepted step (it is reused after a
 *   rejection).
 * Step size: Gustafsson predictive (PI-type) controller exactly as in RODAS
 *   (exponent 1/R_Q with R_Q = 4 for RODAS4/4P, 5 for RODAS5P; safety 0.9, step
 *   ratio in [1/5, 6], no growth right after a rejection).  Measured and rejected
 *   on the EHA: a classical PI controller (exponents 0.7/q, 0.4/q) halves the
 *   rejections (~25 % -> ~8 %) but takes more accepted steps and more rhs calls at
 *   every tolerance; safety 0.8 or growth limit 3 do not pay off either.
 *   RMS error norm with sk = atol_i + rtol*max(|x_i|,|x_new_i|).  Steps are never
 *   forced onto the output grid (dense output); they are clipped to the last
 *   output time, to hmax, and -- only when some input is zero-order-hold -- to the
 *   next input sample time (a ZOH input is discontinuous there).  Inputs marked
 *   u_hold[j] == 2 are linear like 0, but steps end on their kinks (see
 *   hy_setup_breaks; used by SolverOptions(error_control="scaled") at rtol <= 1e-5).
 * Recoverable failures: a stage that makes the model return a status code, or a
 *   non-finite error estimate, rejects the step and retries with h/5; only when
 *   the step size underflows is the status reported (so the reported time is the
 *   time at which the state actually reaches the model's invalid region).
 * Linear algebra, W = I/(h gam) - J:
 *   - dense LU with partial pivoting for HY_NX <= HY_DENSE_MAX (default 24), or
 *     when the filled pattern is denser than 1/4;
 *   - otherwise sparse LU on the known pattern: minimum-degree ordering of the
 *     symmetrised pattern (ties by index; arrow and block-diagonal patterns give
 *     zero fill), symbolic fill computed once per call, numeric row-wise
 *     (up-looking) factorisation with static diagonal pivoting; if a pivot is
 *     tiny relative to its row (HY_PIVTOL) that step falls back to dense LU with
 *     partial pivoting (dense storage allocated lazily, once).
 *   Cost per step is O(nnz(L+U)) for the solve/factor and O(n * groups) for the
 *   Jacobian.  (A dense ROW in J -- e.g. a supply node fed by all cylinders --
 *   forces as many FD groups as that row has entries; define HY_HAS_JAC to avoid.)
 * Memory: all work arrays are malloc'ed once per call and freed at the end; no
 *   static mutable state, so the function is reentrant (thread-safe).
 *
 * Known limitation: the EHA error is dominated by the transients right after the
 *   square-wave command jumps (t = 5.0x s, 15.0x s) and by stick-slip events in
 *   the steep friction tanh, where the step collapses through several rejections.
 *   Jacobian reuse across steps was measured to be much worse (not W-methods).
 *
 * HY_OUT_NO_INPUTS (set by the code generator when no output reads an input): the dense
 *   output skips the input lookup per output sample (~3 % of the EHA's run at 1 kHz output).
 * Compile-time knobs (define before including): HY_METHOD (3), HY_FORCE_DENSE, HY_FORCE_SPARSE,
 *   HY_DENSE_MAX (24), HY_PIVTOL (1e-8), HY_HAS_JAC, HY_SAFE (0.9), HY_GROW (6).
 *
 * Return codes of hy_simulate: 0 ok; 1 step size underflow; 2 max_steps exceeded;
 *   3 non-finite value (stats[6] = first non-finite state index); 100+k model
 *   status k (stats[5] = time); -1 invalid arguments / out of memory.
 */
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <float.h>
#include <limits.h>

#if !defined(HY_NX) || !defined(HY_NP) || !defined(HY_NU) || !defined(HY_NY) || !defined(HY_NNZ)
#error "hy_integrator.c: the model must define HY_NX, HY_NP, HY_NU, HY_NY and HY_NNZ before including it"
#endif

#if HY_NU > 0
#define HY_NU_A HY_NU
#else
#define HY_NU_A 1
#endif

#ifndef HY_DENSE_MAX
#define HY_DENSE_MAX 24
#endif
#ifndef HY_PIVTOL
#define HY_PIVTOL 1e-8
#endif

#define HY_ABI_VERSION 1

/* full unrolling of the tiny dense kernels (only when the system is small) */
#if HY_NX <= 12 && defined(__GNUC__) && !defined(__clang__)
#define HY_UNROLL _Pragma("GCC unroll 12")
#else
#define HY_UNROLL
#endif
#ifndef HY_GROW
#define HY_GROW 6.0
#endif
#ifndef HY_SAFE
#define HY_SAFE 0.9
#endif

#include "hy_methods.h"

typedef struct {
    /* problem data */
    const double *p;
    int n_tin;
    const double *t_in;
    const double *U;
    const int *u_hold;
    int has_zoh;
    int seg;                 /* cached input interval index */
    double u[HY_NU_A];       /* current input values */
    long nfev;
    double rtol;
    const double *atol;
    /* input breakpoints where some linearly interpolated input has a kink */
    int nbrk, ibrk, *brk;
    /* Jacobian pattern */
    int *rptr, *ridx;        /* row -> entry ids */
    int *cptr, *cidx;        /* col -> entry ids */
    int ngrp, *gptr, *gcol;  /* column groups */
    double *jv;              /* Jacobian values, HY_NNZ */
    double *fdt;             /* df/dt */
    double *xp, *fp;         /* perturbation work */
    /* linear algebra */
    int sparse, use_dense;
    long nfallback;
    double *dA, *ddinv;
    int *dpiv;
    int fnnz;
    int *frp, *fci, *fdiag, *perm, *jpos;
    double *fv, *finv, *fw, *fw2;
} hy_ws;

/* ------------------------------------------------------------------ inputs */

/* interval k with t_in[k] <= tau < t_in[k+1]; -1 before the table, n-1 after.
   Galloping (exponential) search from the cached interval, then bisection inside the
   bracket: O(log d) for a jump of d samples.  Successive calls are close in time but not
   monotone (stage times, then output times back inside the step, then the next step), and
   a step spans tens of samples of a 1 kHz table; a bisection over the whole table made
   this lookup ~10 % of the EHA's run time (perf, issue 16). */
static int hy_seg_find(hy_ws *w, double tau)
{
    const double *ti = w->t_in;
    const int n = w->n_tin;
    int k = w->seg, lo, hi, d;
    if (n <= 0) return -1;
    if (!(tau >= ti[0])) { w->seg = -1; return -1; }
    if (tau >= ti[n - 1]) { w->seg = n - 1; return n - 1; }
    /* here 0 <= answer <= n-2: find lo, hi with ti[lo] <= tau < ti[hi] */
    if (k < 0) k = 0;
    if (k > n - 2) k = n - 2;
    if (ti[k] <= tau) {
        if (tau < ti[k + 1]) { w->seg = k; return k; }
        lo = k + 1; d = 1;
        for (;;) {                                   /* gallop forward */
            hi = lo + d;
            if (hi >= n - 1) { hi = n - 1; break; }
            if (tau < ti[hi]) break;
            lo = hi; d <<= 1;
        }
    } else {
        hi = k; d = 1;
        for (;;) {                                   /* gallop backward */
            lo = hi - d;
            if (lo <= 0) { lo = 0; break; }
            if (ti[lo] <= tau) break;
            hi = lo; d <<= 1;
        }
    }
    while (hi - lo > 1) {
        const int mid = lo + ((hi - lo) >> 1);
        if (ti[mid] <= tau) lo = mid; else hi = mid;
    }
    w->seg = lo;
    return lo;
}

/* inputs at tau; the interval index is capped at kcap (used to evaluate a ZOH
   input left-continuously at the end of a step that stops on a sample time). */
static void hy_eval_u(hy_ws *w, double tau, int kcap, double *u)
{
#if HY_NU > 0
    int j, k = hy_seg_find(w, tau);
    const int n = w->n_tin;
    if (k > kcap) k = kcap;
    if (k < 0) {
        for (j = 0; j < HY_NU; ++j) u[j] = w->U[j];
    } else if (k >= n - 1) {
        const double *un = w->U + (size_t)(n - 1) * HY_NU;
        for (j = 0; j < HY_NU; ++j) u[j] = un[j];
    } else {
        const double *u0 = w->U + (size_t)k * HY_NU, *u1 = u0 + HY_NU;
        const double th = (tau - w->t_in[k]) / (w->t_in[k + 1] - w->t_in[k]);
        for (j = 0; j < HY_NU; ++j)
            u[j] = w->u_hold[j] == 1 ? u0[j] : u0[j] + th * (u1[j] - u0[j]);
    }
#else
    (void)w; (void)tau; (void)kcap; (void)u;
#endif
}

static int hy_f(hy_ws *w, double t, const double *x, int kcap, double *dx)
{
    hy_eval_u(w, t, kcap, w->u);
    w->nfev++;
    return hy_rhs(t, x, w->p, w->u, dx);
}

/* -1 if all finite, else the first non-finite index (cheap test via the sum). */
static int hy_bad_stage(const double *v)
{
    double s = 0.0;
    int i;
    for (i = 0; i < HY_NX; ++i) s += v[i] * 0.0;  /* 0*x is NaN iff x is not finite */
    if (s == 0.0) return -1;
    for (i = 0; i < HY_NX; ++i)
        if (!isfinite(v[i])) return i;
    return -1;
}

static int hy_first_nonfinite(const double *v, int n)
{
    int i;
    for (i = 0; i < n; ++i)
        if (!isfinite(v[i])) return i;
    return -1;
}

/* Input breakpoints (kinks) of the inputs marked u_hold[j] == 2 ("linear, do not
   step blindly across its kinks").  A kink is an interior sample whose deviation from
   the straight line through its neighbours exceeds HY_KINK_TOL times the input's range
   over the table.  Stepping across a kink makes the local error O(h^2) instead of
   O(h^(q+1)): the controller's model breaks down and steps of about one sample interval
   are rejected again and again (measured on the EHA at rtol 1e-7 with 1 kHz tables:
   8410 rejections for 24103 accepted steps).  The driver therefore ends a step ON a
   kink when the step would cross it and either the kink is large (deviation above
   HY_KINK_BIG times the range: a ramp corner of a step command) or the step is shorter
   than HY_KINK_SPAN times t_in[k+1] - t_in[k-1] (4 ms for a 1 kHz table).  Such a step
   would resolve the table nearly sample by sample anyway, and its error estimate
   under-reports a crossed kink: the solution and the embedded solution sample the input
   at the same stage times, so both miss the kink alike (measured on the EHA at rtol 1e-6:
   crossing every kink gives 40x, crossing only from 2 ms on 20x the error of landing).
   Longer steps cross small kinks: over many samples a smooth signal's table is smooth
   to the method.  No restart: the step size and the controller history are kept (a
   clipped step never shrinks the next one).
   Returns 0, or -1 when out of memory. */
#ifndef HY_KINK_TOL
#define HY_KINK_TOL 1e-6
#endif
#ifndef HY_KINK_BIG
#define HY_KINK_BIG 1e-2
#endif
#ifndef HY_KINK_SPAN
#define HY_KINK_SPAN 2.0
#endif
static int hy_setup_breaks(hy_ws *w)
{
#if HY_NU > 0
    const int n = w->n_tin;
    int j, k;
    double range[HY_NU];
    int any = 0;
    w->nbrk = 0; w->ibrk = 0;
    for (j = 0; j < HY_NU; ++j) if (w->u_hold[j] == 2) any = 1;
    if (n < 3 || !any) return 0;
    w->brk = (int *)malloc(sizeof(int) * (size_t)n);
    if (!w->brk) return -1;
    for (j = 0; j < HY_NU; ++j) {
        double lo = w->U[j], hi = w->U[j];
        for (k = 1; k < n; ++k) {
            const double v = w->U[(size_t)k * HY_NU + j];
            if (v < lo) lo = v;
            if (v > hi) hi = v;
        }
        range[j] = hi - lo;
    }
    for (k = 1; k < n - 1; ++k) {
        const double t0 = w->t_in[k - 1], t1 = w->t_in[k], t2 = w->t_in[k + 1];
        const double th = (t1 - t0) / (t2 - t0);
        for (j = 0; j < HY_NU; ++j) {
            const double *u = w->U + (size_t)(k - 1) * HY_NU + j;
            const double dev = u[HY_NU] - (u[0] + th * (u[2 * HY_NU] - u[0]));
            if (w->u_hold[j] == 2 && range[j] > 0.0 && fabs(dev) > HY_KINK_TOL * range[j]) {
                w->brk[w->nbrk++] = fabs(dev) > HY_KINK_BIG * range[j] ? -k : k;
                break;
            }
        }
    }
#else
    (void)w;
#endif
    return 0;
}

#include "hy_linalg.h"

struct hy_sens;              /* forward sensitivities (hy_sens.h, only with HY_HAS_SENS) */
#ifdef HY_HAS_SENS
#include "hy_sens.h"
#include "hy_sens_pipe.h"
#endif

/* --------------------------------------------------------------- Jacobian */

static int hy_setup_pattern(hy_ws *w)
{
    const int n = HY_NX;
    int e, i, j, g;
    int *color = (int *)malloc(sizeof(int) * (size_t)n);
    int *forbid = (int *)malloc(sizeof(int) * (size_t)n);
    int *cnt = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    if (!color || !forbid || !cnt) { free(color); free(forbid); free(cnt); return -1; }
    /* row and column incidence */
    memset(w->rptr, 0, sizeof(int) * (size_t)(n + 1));
    memset(w->cptr, 0, sizeof(int) * (size_t)(n + 1));
    for (e = 0; e < HY_NNZ; ++e) { w->rptr[HY_JAC_ROW[e] + 1]++; w->cptr[HY_JAC_COL[e] + 1]++; }
    for (i = 0; i < n; ++i) { w->rptr[i + 1] += w->rptr[i]; w->cptr[i + 1] += w->cptr[i]; }
    memcpy(cnt, w->rptr, sizeof(int) * (size_t)n);
    for (e = 0; e < HY_NNZ; ++e) w->ridx[cnt[HY_JAC_ROW[e]]++] = e;
    memcpy(cnt, w->cptr, sizeof(int) * (size_t)n);
    for (e = 0; e < HY_NNZ; ++e) w->cidx[cnt[HY_JAC_COL[e]]++] = e;
    /* greedy colouring: columns sharing a row get different colours */
    for (j = 0; j < n; ++j) { color[j] = -1; forbid[j] = -1; }
    w->ngrp = 0;
    for (j = 0; j < n; ++j) {
        int q, c = 0;
        for (q = w->cptr[j]; q < w->cptr[j + 1]; ++q) {
            const int r = HY_JAC_ROW[w->cidx[q]];
            int s;
            for (s = w->rptr[r]; s < w->rptr[r + 1]; ++s) {
                const int k = HY_JAC_COL[w->ridx[s]];
                if (color[k] >= 0) forbid[color[k]] = j;
            }
        }
        while (forbid[c] == j) ++c;
        color[j] = c;
        if (c + 1 > w->ngrp) w->ngrp = c + 1;
    }
    memset(cnt, 0, sizeof(int) * (size_t)(n + 1));
    for (j = 0; j < n; ++j) cnt[color[j] + 1]++;
    for (g = 0; g < w->ngrp; ++g) cnt[g + 1] += cnt[g];
    memcpy(w->gptr, cnt, sizeof(int) * (size_t)(w->ngrp + 1));
    for (j = 0; j < n; ++j) w->gcol[cnt[color[j]]++] = j;
    free(color); free(forbid); free(cnt);
    return 0;
}

/* J (into w->jv) and df/dt (into w->fdt) at (t, x) where f0 = f(t, x). */
static int hy_jacobian(hy_ws *w, double t, const double *x, const double *f0, int kcap)
{
    const int n = HY_NX;
    const double sq = 1.4901161193847656e-08; /* sqrt(DBL_EPSILON) */
    int i, st;
    double dt;
    volatile double tt;
#ifdef HY_HAS_JAC
    hy_eval_u(w, t, kcap, w->u);
    st = hy_jac(t, x, w->p, w->u, w->jv);
    if (st) return st;
#else
    {
        int g, q, r;
        double *xp = w->xp, *fp = w->fp, *del = w->fdt; /* fdt used as scratch */
        for (i = 0; i < n; ++i) xp[i] = x[i];
        for (g = 0; g < w->ngrp; ++g) {
            for (q = w->gptr[g]; q < w->gptr[g + 1]; ++q) {
                const int j = w->gcol[q];
                double sc = fabs(x[j]), a = w->atol[j] / w->rtol;
                volatile double xt;
                if (a > sc) sc = a;
                if (sc < 1e-10) sc = 1e-10;
                xt = x[j] + sq * sc;
                del[j] = xt - x[j];
                xp[j] = xt;
            }
            st = hy_f(w, t, xp, kcap, fp);
            if (st) return st;
            for (q = w->gptr[g]; q < w->gptr[g + 1]; ++q) {
                const int j = w->gcol[q];
                const double id = 1.0 / del[j];
                for (r = w->cptr[j]; r < w->cptr[j + 1]; ++r) {
                    const int e = w->cidx[r];
                    const int row = HY_JAC_ROW[e];
                    w->jv[e] = (fp[row] - f0[row]) * id;
                }
                xp[j] = x[j];
            }
        }
    }
#endif
    tt = t + sq * (fabs(t) > 1.0 ? fabs(t) : 1.0);
    dt = tt - t;
    st = hy_f(w, t + dt, x, kcap, w->fp);
    if (st) return st;
    for (i = 0; i < n; ++i) w->fdt[i] = (w->fp[i] - f0[i]) / dt;
    return 0;
}

/* ---------------------------------------------------------------- driver */

/* Output sample i: the state xo into row i of X_out (unless xo is that row already: the
   dense output interpolates straight into it) and the outputs at it.  The copy is a loop:
   a memcpy of this small constant size compiled to a `rep movs`, ~4 % of the EHA's run
   at 1 kHz output (perf, issue 16). */
static int hy_emit(hy_ws *w, int i, double to, const double *xo, double *X_out, double *Y_out)
{
    double *xr = X_out + (size_t)i * HY_NX;
    int j;
    if (xo != xr)
        for (j = 0; j < HY_NX; ++j) xr[j] = xo[j];
#if HY_NY > 0
#ifndef HY_OUT_NO_INPUTS       /* defined by the generated model when no output reads an input */
    hy_eval_u(w, to, INT_MAX, w->u);
#endif
    return hy_out(to, xr, w->p, w->u, Y_out + (size_t)i * HY_NY);
#else
    (void)w; (void)to; (void)Y_out;
    return 0;
#endif
}

/* Dense output at s = (t_o - t)/h in (0, 1):
   x(t + s h) = (1 - s) x + s (x_new + (1 - s) (K_0 + s (K_1 + s K_2 ...))), K_r = dk + r n.
   The arguments are restrict-qualified (the row of X_out aliases none of them), so the
   states are interpolated two at a time: ~0.08 ms (~3 %) off the EHA's 20 s at 1 kHz output
   (interleaved A/B, issue 16). */
static void hy_dense_row(const double *restrict x, const double *restrict xn, const double *restrict dk,
                         double s, double *restrict xo)
{
    const double s1 = 1.0 - s;
    int i, r;
    for (i = 0; i < HY_NX; ++i) {
        double v = dk[(size_t)(R_NH - 1) * HY_NX + i];
        for (r = R_NH - 2; r >= 0; --r) v = dk[(size_t)r * HY_NX + i] + s * v;
        xo[i] = x[i] * s1 + s * (xn[i] + s1 * v);
    }
}

/* e^(1/R_Q), the step-size controller's root: two square roots for R_Q = 4 (Rodas4, Rodas4P),
   a `pow` otherwise.  The controller takes two per accepted step; `pow` was ~3 % of the EHA's
   run under Rodas4P (perf, issue 16). */
static double hy_root_q(double e)
{
#if R_Q == 4
    return sqrt(sqrt(e));
#else
    return pow(e, 1.0 / R_Q);
#endif
}

static double hy_rms(const double *v, const double *sk, int n)
{
    double s = 0.0;
    int i;
    for (i = 0; i < n; ++i) { double q = v[i] / sk[i]; s += q * q; }
    return sqrt(s / n);
}

int hy_model_info(int *out)
{
    out[0] = HY_NX; out[1] = HY_NP; out[2] = HY_NU; out[3] = HY_NY; out[4] = HY_NNZ;
    out[5] = HY_ABI_VERSION; out[6] = HY_DENSE_MAX;
    return 0;
}

static int hy_integrate(
    const double *p,
    int n_tin, const double *t_in,
    const double *U,
    const int *u_hold,
    double t0, const double *x0,
    int n_out, const double *t_out,
    double rtol, const double *atol,
    double h0, double hmax, long max_steps,
    double *X_out,
    double *Y_out,
    double *stats,
    struct hy_sens *sn)
{
    const int n = HY_NX;
    hy_ws W;
    double *blk = NULL;
    double *x, *xn, *f0, *fn, *fs, *y, *K, *kl, *dk, *sk;
    long nacc = 0, nrej = 0, njac = 0, nlu = 0;
    int ret = 0, iout = 0, i, st;
    int first = 1, reject = 0, jac_ok = 0, worst = -1;
    double t = t0, h, hacc = 0.0, erracc = 1.0, tend, hmin, hlast = 0.0;

    for (i = 0; i < 16; ++i) stats[i] = 0.0;
    stats[5] = t0;
    stats[6] = -1.0;
    if (n_out <= 0) return 0;
    if (!x0 || !t_out || !X_out || !atol || (HY_NY > 0 && !Y_out)) return -1;
#if HY_NU > 0
    if (n_tin < 1 || !t_in || !U || !u_hold) return -1;
#endif
    if (!(rtol >= 100.0 * DBL_EPSILON)) rtol = 100.0 * DBL_EPSILON;
    if (!(hmax > 0.0)) hmax = HUGE_VAL;
    if (max_steps <= 0) max_steps = LONG_MAX;

    memset(&W, 0, sizeof W);
    W.p = p; W.n_tin = n_tin; W.t_in = t_in; W.U = U; W.u_hold = u_hold;
    W.rtol = rtol; W.atol = atol; W.seg = 0;
#if HY_NU > 0
    for (i = 0; i < HY_NU; ++i) if (u_hold[i] == 1) W.has_zoh = 1;
#endif

    /* ---- allocation (once per call) ---- */
    blk = (double *)malloc(sizeof(double) * ((size_t)(11 + R_S + R_NH) * n + (HY_NNZ > 0 ? HY_NNZ : 1)));
    W.rptr = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    W.cptr = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    W.ridx = (int *)malloc(sizeof(int) * (size_t)(HY_NNZ > 0 ? HY_NNZ : 1));
    W.cidx = (int *)malloc(sizeof(int) * (size_t)(HY_NNZ > 0 ? HY_NNZ : 1));
    W.gptr = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    W.gcol = (int *)malloc(sizeof(int) * (size_t)n);
    if (!blk || !W.rptr || !W.cptr || !W.ridx || !W.cidx || !W.gptr || !W.gcol) { ret = -1; goto finish; }
    x = blk; xn = x + n; f0 = xn + n; fn = f0 + n; fs = fn + n; y = fs + n;
    K = y + n;                      /* R_S stage vectors k_0 .. k_(R_S-1) */
    kl = K + (size_t)(R_S - 1) * n; /* last stage = error estimate */
    dk = K + (size_t)R_S * n;       /* R_NH dense-output coefficient vectors */
    sk = dk + (size_t)R_NH * n; W.fdt = sk + n; W.xp = W.fdt + n; W.fp = W.xp + n;
    W.jv = W.fp + n + n;  /* (10 + R_S + R_NH) n used + jv; one spare n */
    if (hy_setup_pattern(&W)) { ret = -1; goto finish; }
    if (hy_setup_breaks(&W)) { ret = -1; goto finish; }
#if defined(HY_FORCE_DENSE)
    W.sparse = 0;
#elif defined(HY_FORCE_SPARSE)
    if (hy_setup_sparse(&W, 1) < 0) { ret = -1; goto finish; }
#else
    if (n > HY_DENSE_MAX) {
        if (hy_setup_sparse(&W, 0) < 0) { ret = -1; goto finish; }
    }
#endif

    memcpy(x, x0, sizeof(double) * (size_t)n);
    if ((i = hy_first_nonfinite(x, n)) >= 0) { ret = 3; worst = i; goto finish; }
    tend = t_out[n_out - 1];
    {
        double a = fabs(t0) > fabs(tend) ? fabs(t0) : fabs(tend);
        hmin = 10.0 * DBL_EPSILON * (a > DBL_MIN ? a : DBL_MIN);
    }

    st = hy_f(&W, t, x, INT_MAX, f0);
    if (st) { ret = 100 + st; goto finish; }
    if ((i = hy_first_nonfinite(f0, n)) >= 0) { ret = 3; worst = i; goto finish; }

    while (iout < n_out && !(t_out[iout] > t)) {
        st = hy_emit(&W, iout, t_out[iout], x, X_out, Y_out);
        if (st) { ret = 100 + st; goto finish; }
        ++iout;
    }
#ifdef HY_HAS_SENS
    if (sn && (st = hy_sens_begin(sn, &W, t_out, iout, n_out, x))) { ret = 100 + st; goto finish; }
#else
    (void)sn;
#endif
    if (iout >= n_out) goto finish;

    /* ---- initial step (Hairer-Norsett-Wanner heuristic) ---- */
    if (h0 > 0.0) {
        h = h0;
    } else {
        double d0, d1, d2 = 0.0, ha, h1;
        for (i = 0; i < n; ++i) sk[i] = atol[i] + rtol * fabs(x[i]);
        d0 = hy_rms(x, sk, n);
        d1 = hy_rms(f0, sk, n);
        ha = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        if (ha > tend - t) ha = tend - t;
        if (ha > hmax) ha = hmax;
        for (i = 0; i < n; ++i) y[i] = x[i] + ha * f0[i];
        st = hy_f(&W, t + ha, y, INT_MAX, fs);
        if (!st) {
            for (i = 0; i < n; ++i) fs[i] -= f0[i];
            d2 = hy_rms(fs, sk, n) / ha;
        }
        if (st || !isfinite(d2)) {
            h = ha * 1e-2;
        } else {
            double dm = d1 > d2 ? d1 : d2;
            h1 = dm <= 1e-15 ? (ha * 1e-3 > 1e-6 ? ha * 1e-3 : 1e-6) : pow(0.01 / dm, 0.25);
            h = 100.0 * ha < h1 ? 100.0 * ha : h1;
        }
    }
    if (!(h > 0.0)) h = 1e-6;

    /* ---- main loop ---- */
    for (;;) {
        int kcap = INT_MAX, clipped = 0, fail = 0;
        double target = tend, hstep, tnext, err, ih;
        if (nacc + nrej >= max_steps) { ret = 2; break; }
        if (W.has_zoh) {
            const int k = hy_seg_find(&W, t);
            kcap = k;
            if (k + 1 < n_tin && t_in[k + 1] < target) target = t_in[k + 1];
        }
        if (W.nbrk) {  /* next kink of an input after t */
            /* a kink less than 1e-4 sample intervals ahead counts as passed (a step that
               ended just short of it by rounding must not be followed by a step of 1e-15) */
            while (W.ibrk < W.nbrk) {
                const int kb = abs(W.brk[W.ibrk]);
                if (t_in[kb] - t > 1e-4 * (t_in[kb + 1] - t_in[kb - 1])) break;
                W.ibrk++;
            }
            if (W.ibrk < W.nbrk) {
                const int kb = abs(W.brk[W.ibrk]);
                const double dts = t_in[kb + 1] - t_in[kb - 1];
                if (t_in[kb] < target && (W.brk[W.ibrk] < 0 || h < HY_KINK_SPAN * dts)) target = t_in[kb];
            }
        }
        hstep = h < hmax ? h : hmax;
        if (t + 1.05 * hstep >= target) {
            hstep = target - t;
            tnext = target;
            clipped = 1;
        } else {
            tnext = t + hstep;
        }
        if (!(hstep >= hmin)) { ret = 1; break; }

        if (!jac_ok) {
            st = hy_jacobian(&W, t, x, f0, kcap);
            njac++;
            if (st) { ret = 100 + st; break; }
            jac_ok = 1;
        }
        st = hy_factor(&W, 1.0 / (R_GAM * hstep));
        nlu++;
        if (st < 0) { ret = -1; break; }
        if (st > 0) {
            nrej++; reject = 1; h = 0.5 * hstep;
            if (h < hmin) { ret = 1; break; }
            continue;
        }
        ih = 1.0 / hstep;

        /* stages: (I/(h gam) - J) k_i = f(t + c_i h, y_i) + h d_i f_t + sum_j (c_ij/h) k_j */
        {
            int is, j;
            for (is = 0; is < R_S; ++is) {
                double *ki = K + (size_t)is * n;
                const double hd = hstep * R_DT[is];
                if (is == 0) {
                    for (i = 0; i < HY_NX; ++i) ki[i] = f0[i] + hd * W.fdt[i];
                } else {
                    if (is < R_NA) {
                        for (i = 0; i < HY_NX; ++i) y[i] = x[i] + R_A[is][0] * K[i];
                        for (j = 1; j < is; ++j) {
                            const double a = R_A[is][j];
                            const double *kj = K + (size_t)j * n;
                            for (i = 0; i < HY_NX; ++i) y[i] += a * kj[i];
                        }
                    } else {
                        /* stiffly accurate tail: y_i = y_(i-1) + k_(i-1) (y still holds y_(i-1)) */
                        const double *kp = ki - n;
                        for (i = 0; i < HY_NX; ++i) y[i] += kp[i];
                    }
                    st = hy_f(&W, t + R_CT[is] * hstep, y, kcap, fs);
                    if (st) { fail = 100 + st; goto stage_fail; }
                    if ((worst = hy_bad_stage(fs)) >= 0) { fail = 3; goto stage_fail; }
                    if (hd != 0.0)
                        for (i = 0; i < HY_NX; ++i) ki[i] = fs[i] + hd * W.fdt[i];
                    else
                        for (i = 0; i < HY_NX; ++i) ki[i] = fs[i];
                    for (j = 0; j < is; ++j) {
                        const double cc = ih * R_C[is][j];
                        const double *kj = K + (size_t)j * n;
                        for (i = 0; i < HY_NX; ++i) ki[i] += cc * kj[i];
                    }
                }
                hy_solve(&W, ki);
            }
            for (i = 0; i < HY_NX; ++i) xn[i] = y[i] + kl[i];
        }

        /* error estimate */
        {
            double s = 0.0, qmax = -1.0;
            for (i = 0; i < HY_NX; ++i) {
                const double ax = fabs(x[i]), an = fabs(xn[i]);
                const double q = kl[i] / (atol[i] + rtol * (ax > an ? ax : an));
                s += q * q;
                if (fabs(q) > qmax) { qmax = fabs(q); worst = i; }
            }
            err = sqrt(s / n);
        }
        if (!isfinite(err)) {
            fail = 3;
            worst = hy_first_nonfinite(xn, n);
            if (worst < 0) worst = hy_first_nonfinite(kl, n);
            goto stage_fail;
        }

        if (err <= 1.0) {
            double fac, hnew;
            st = hy_f(&W, tnext, xn, INT_MAX, fn);
            if (st) { fail = 100 + st; goto stage_fail; }
            if ((i = hy_first_nonfinite(fn, n)) >= 0) { fail = 3; worst = i; goto stage_fail; }
            /* dense output for t_out in (t, tnext] */
            if (iout < n_out && t_out[iout] <= tnext) {
                int r, j;
                for (r = 0; r < R_NH; ++r) {
                    double *dr = dk + (size_t)r * n;
                    for (i = 0; i < HY_NX; ++i) dr[i] = R_H[r][0] * K[i];
                    for (j = 1; j < R_S; ++j) {
                        const double hh = R_H[r][j];
                        const double *kj = K + (size_t)j * n;
                        if (hh != 0.0)
                            for (i = 0; i < HY_NX; ++i) dr[i] += hh * kj[i];
                    }
                }
                while (iout < n_out && t_out[iout] <= tnext) {
                    const double to = t_out[iout];
                    if (to == tnext) {
                        st = hy_emit(&W, iout, to, xn, X_out, Y_out);
                    } else {
                        double s = (to - t) / (tnext - t);
                        double *xo = X_out + (size_t)iout * n;     /* interpolate into the row */
                        if (s < 0.0) s = 0.0;
                        hy_dense_row(x, xn, dk, s, xo);
                        st = hy_emit(&W, iout, to, xo, X_out, Y_out);
                    }
                    if (st) { ret = 100 + st; break; }
                    ++iout;
                }
                if (ret) break;
            }
#ifdef HY_HAS_SENS
            if (sn && (st = hy_sens_step(sn, &W, t, tnext, hstep, x, xn, K, kcap, t_out, n_out))) { ret = 100 + st; break; }
#endif
            /* step size controller (Gustafsson, as in RODAS) */
            fac = hy_root_q(err) / HY_SAFE;
            if (fac > 5.0) fac = 5.0;
            if (fac < 1.0 / HY_GROW) fac = 1.0 / HY_GROW;
            if (!first) {
                double facg = (hacc / hstep) * hy_root_q(err * err / erracc) / HY_SAFE;
                if (facg > 5.0) facg = 5.0;
                if (facg < 1.0 / HY_GROW) facg = 1.0 / HY_GROW;
                if (facg > fac) fac = facg;
            }
            hnew = hstep / fac;
            hacc = hstep;
            erracc = err > 1e-2 ? err : 1e-2;
            if (reject && hnew > hstep) hnew = hstep;
            if (clipped && !reject && hnew < h) hnew = h; /* clipping is not a reason to shrink */
            first = 0; reject = 0; jac_ok = 0;
            nacc++;
            hlast = hstep;
            t = tnext;
            { double *tmp = x; x = xn; xn = tmp; tmp = f0; f0 = fn; fn = tmp; }
            h = hnew;
            worst = -1;
            if (iout >= n_out) break;
        } else {
            double fac = hy_root_q(err) / HY_SAFE;
            if (fac > 5.0) fac = 5.0;
            if (fac < 1.0 / HY_GROW) fac = 1.0 / HY_GROW;
            nrej++;
            h = first ? 0.1 * hstep : hstep / fac;
            reject = 1;
            if (h < hmin) { ret = 1; break; }
        }
        continue;

    stage_fail:
        nrej++;
        reject = 1;
        h = 0.2 * hstep;
        if (h < hmin) { ret = fail; break; }
    }

finish:
#ifdef HY_HAS_SENS
    if (sn) ret = hy_sens_end(sn, ret);      /* joins the column thread of a pipelined run */
#endif
    if (ret != 0) {
        const double nanv = NAN;
        int j;
        for (i = iout; i < n_out; ++i) {
            for (j = 0; j < n; ++j) X_out[(size_t)i * n + j] = nanv;
#if HY_NY > 0
            for (j = 0; j < HY_NY; ++j) Y_out[(size_t)i * HY_NY + j] = nanv;
#endif
        }
    }
    stats[0] = (double)nacc;
    stats[1] = (double)nrej;
    stats[2] = (double)W.nfev;
    stats[3] = (double)njac;
    stats[4] = (double)nlu;
    stats[5] = t;
    stats[6] = (ret == 1 || ret == 3) ? (double)worst : -1.0;
    stats[7] = hlast;
    free(blk);
    free(W.rptr); free(W.cptr); free(W.ridx); free(W.cidx); free(W.gptr); free(W.gcol);
    free(W.dA); free(W.dpiv); free(W.ddinv);
    free(W.perm); free(W.frp); free(W.fci); free(W.fdiag); free(W.jpos);
    free(W.fv); free(W.finv); free(W.fw); free(W.fw2);
    free(W.brk);
    return ret;
}

int hy_simulate(
    const double *p,
    int n_tin, const double *t_in,
    const double *U,
    const int *u_hold,
    double t0, const double *x0,
    int n_out, const double *t_out,
    double rtol, const double *atol,
    double h0, double hmax, long max_steps,
    double *X_out,
    double *Y_out,
    double *stats)
{
    return hy_integrate(p, n_tin, t_in, U, u_hold, t0, x0, n_out, t_out, rtol, atol, h0, hmax, max_steps,
                        X_out, Y_out, stats, NULL);
}
