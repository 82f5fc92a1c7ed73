/*
 * hy_sens.h -- forward (direct-decoupled) sensitivities for hy_integrator.c.
 *
 * Included by the integrator only when the generated model defines HY_HAS_SENS, i.e.
 * provides (see hydrocli/model/jacobian.py):
 *   hy_jfp(t, x, p, u, jv, fpv)   df/dx (as hy_jac) and df/dp, values in HY_FP_PTR/HY_FP_ROW
 *                                 (column-compressed over the parameters), in one pass
 *   hy_gjac(t, x, p, u, gxv, gpv) dg/dx (HY_GX_PTR/ROW) and dg/dp (HY_GP_PTR/ROW) of the
 *                                 outputs
 * and the analytic Jacobian hy_jac.
 *
 * METHOD (staggered direct method, as in KPP's tangent-linear Rosenbrock integrators:
 * A. Sandu, D. Daescu, G. Carmichael, "Direct and adjoint sensitivity analysis of chemical
 * kinetic systems with KPP: I", Atmos. Env. 37 (2003) 5083).  The sensitivities
 * S = dx/dtheta (one column per free parameter or free initial state) obey
 *     S' = g(t, x, S) = J(t, x) S + df/dp(t, x),   S(t0) = S0.
 * The Rosenbrock method is applied to the augmented system (x, S), whose Jacobian is
 * block lower-triangular [[J, 0], [M, J]] with M = d(J S + f_p)/dx at (t_n, x_n, S_n).
 * After the integrator accepts a state step (stages k_i, factorised W = I/(h gam) - J),
 * each sensitivity stage solves with the SAME factorisation:
 *     W kS_i = g(t + c_i h, y_i, Sy_i) + sum_j (c_ij/h) kS_j + h d_i g_t + M k_i,
 * Sy_i built from kS_j exactly as y_i from k_j.  M k_i is a directional difference of
 * g in x; g_t a forward difference in t (as f_t).  The sensitivities do not take part in
 * the error control: they inherit the state's steps (the usual staggered choice).
 * Dense output of S uses the integrator's interpolation coefficients; output
 * sensitivities dy/dtheta = dg/dx S + dg/dp are evaluated at every output time.
 *
 * A sensitivity step is split in two (hy_sens_points, hy_sens_columns):
 *   points  -- df/dx and df/dp at the HY_SP points the step needs: (t, x), (t + dt, x) for
 *              g_t, the R_S - 1 stage points y_i and the R_S points x + eps_i k_i of M k_i.
 *              They depend on the states only: about four plain runs' worth per run
 *              (EHA), the same whatever the number of columns;
 *   columns -- everything that touches S: J S + df/dp at those points, the stages and their
 *              block solves with the step's LU, dense output, dy/dtheta.
 * hy_sens_pipe.h runs the two in sequence, or pipelined in two threads (the integrator and
 * the points in the caller's thread, the columns in a second thread a few steps behind).
 * The arithmetic is the same either way: the results are bitwise identical.
 */
#ifndef HY_SENS_H
#define HY_SENS_H
#ifndef HY_HAS_JAC
#error "hy_sens.h: sensitivities need the analytic Jacobian (HY_HAS_JAC)"
#endif

/* Fields are grouped by the thread that writes them during a run, each group on its own
   cache lines (HY_LINE): in a pipelined run a line written by one thread and read by the other
   moves between the two cores' caches at every write ("false sharing"); the work arrays of
   the two threads are separate allocations for the same reason. */
#define HY_LINE 64
struct hy_sens {
    /* set before the run, read by both threads */
    int ns;                  /* sensitivity columns */
    const int *col_p;        /* parameter index of a column, -1 for an initial-state column */
    double *dY;              /* n_out * HY_NY * ns */
    double *dX;              /* n_out * HY_NX * ns, or NULL */
    const double *X_out;
    int pipelined;           /* asked for the two-thread pipeline (hy_sens_pipe.h) */
    struct hy_sstep *ring;   /* step records: HY_RING when pipelined, else one */
    /* written by the integrator's thread (hy_sens_points) */
    _Alignas(HY_LINE) long ngev;   /* evaluations of df/dx, df/dp (the points) */
    double *xe, *ye;         /* HY_NX work each */
    struct hy_pipe *pipe;    /* the running pipeline, or NULL */
    int was_pipelined;       /* the column thread ran */
    /* written by the column thread (hy_sens_columns; the integrator's in a sequential run) */
    _Alignas(HY_LINE) double *S, *Sn, *Sy;   /* HY_NX*ns, state-major (S[j*ns + c]): current, new, stage value */
    double *KS, *DS;         /* R_S and R_NH blocks of HY_NX*ns: stages, dense coefficients */
    double *g0, *g1, *gt;    /* HY_NX*ns work */
    double *gxv, *gpv;
    double *Vb, *col;        /* the block solve's work: HY_NX*ns, HY_NX */
    int iout;                /* outputs whose sensitivities are written */
    _Alignas(HY_LINE) char end;    /* (nothing else on the last line) */
};

/* n bytes rounded up to whole cache lines, from a line boundary (C11; free with free) */
static void *hy_lines(size_t n)
{
    n = (n + HY_LINE - 1) / HY_LINE * HY_LINE;
    return aligned_alloc(HY_LINE, n ? n : HY_LINE);
}

/* points of one step (HY_SP of them): index of (t, x), (t + dt, x), stage i (1 .. R_S-1),
   and x + eps_i k_i (i = 0 .. R_S-1) */
#define HY_SP (2 * R_S + 1)
#define SP_X 0
#define SP_T 1
#define SP_STAGE(i) (1 + (i))
#define SP_M(i) (R_S + 1 + (i))

/* one accepted state step, with everything its sensitivity columns need (hy_sens_points);
   a record and its arrays start on a cache line of their own */
struct hy_sstep {
    _Alignas(HY_LINE) double t, tnext, h, dt;
    double eps[R_S];         /* > 0: the M k_i term of stage i is eps_i-scaled; 0: none */
    int use_dense;
    double *x, *xn, *K;      /* HY_NX, HY_NX, R_S*HY_NX: the step's start, end and stages */
    double *dA, *ddinv;      /* its dense LU of W (when use_dense) */
    int *dpiv;
    double *jv, *fpv;        /* HY_SP blocks of HY_NNZ and HY_FP_NNZ values */
};

/* doubles of a record's arrays, whole cache lines; its pivot ints likewise */
#define HY_SS_DBL (((size_t)(2 + R_S) * HY_NX + (size_t)HY_NX * HY_NX + HY_NX \
                    + (size_t)HY_SP * HY_NNZ + (size_t)HY_SP * HY_FP_NNZ + 2 + 7) / 8 * 8)
#define HY_SS_INT (((size_t)HY_NX + 15) / 16 * 16)

/* storage of count step records in two blocks (*dbl, *ibl; free both) */
static int hy_sstep_alloc(struct hy_sstep *sp, int count, double **dbl, int **ibl)
{
    int c;
    *dbl = (double *)hy_lines(sizeof(double) * HY_SS_DBL * (size_t)count);
    *ibl = (int *)hy_lines(sizeof(int) * HY_SS_INT * (size_t)count);
    if (!*dbl || !*ibl) return -1;
    for (c = 0; c < count; ++c) {
        struct hy_sstep *s = sp + c;
        s->x = *dbl + (size_t)c * HY_SS_DBL; s->xn = s->x + HY_NX; s->K = s->xn + HY_NX;
        s->dA = s->K + (size_t)R_S * HY_NX; s->ddinv = s->dA + (size_t)HY_NX * HY_NX;
        s->jv = s->ddinv + HY_NX; s->fpv = s->jv + (size_t)HY_SP * HY_NNZ + 1;
        s->dpiv = *ibl + (size_t)c * HY_SS_INT;
    }
    return 0;
}

/* df/dx and df/dp at (t, x) into point k of the step record */
static int hy_sens_jfp(struct hy_sens *sn, hy_ws *w, double t, const double *x, int kcap, struct hy_sstep *sp, int k)
{
    hy_eval_u(w, t, kcap, w->u);
    sn->ngev++;
    return hy_jfp(t, x, w->p, w->u, sp->jv + (size_t)k * HY_NNZ, sp->fpv + (size_t)k * HY_FP_NNZ);
}

/* The state-only part of the sensitivity step that follows an accepted state step
   (t, x) -> (tnext, xn) with stages K and factorised W: the step, its LU and df/dx, df/dp at
   its HY_SP points, into sp. */
static int hy_sens_points(struct hy_sens *sn, hy_ws *w, double t, double tnext, double h, const double *x,
                          const double *xn, const double *K, int kcap, struct hy_sstep *sp)
{
    const int n = HY_NX;
    const double sq = 1.4901161193847656e-08;
    double *y = sn->ye;
    volatile double tt;
    int is, i, j, st;

    sp->t = t; sp->tnext = tnext; sp->h = h;
    memcpy(sp->x, x, sizeof(double) * (size_t)n);
    memcpy(sp->xn, xn, sizeof(double) * (size_t)n);
    memcpy(sp->K, K, sizeof(double) * (size_t)R_S * n);
    sp->use_dense = w->use_dense;
    if (w->use_dense) {
        memcpy(sp->dA, w->dA, sizeof(double) * (size_t)n * n);
        memcpy(sp->ddinv, w->ddinv, sizeof(double) * (size_t)n);
        memcpy(sp->dpiv, w->dpiv, sizeof(int) * (size_t)n);
    }
    if ((st = hy_sens_jfp(sn, w, t, x, kcap, sp, SP_X))) return st;
    tt = t + sq * (fabs(t) > 1.0 ? fabs(t) : 1.0);
    sp->dt = tt - t;
    if ((st = hy_sens_jfp(sn, w, t + sp->dt, x, kcap, sp, SP_T))) return st;
    memcpy(y, x, sizeof(double) * (size_t)n);
    for (is = 0; is < R_S; ++is) {
        const double *ki = K + (size_t)is * n;
        double kmax = 0.0;
        if (is > 0) {
            if (is < R_NA) {
                for (i = 0; i < n; ++i) y[i] = x[i] + R_A[is][0] * K[i];
                for (j = 1; j < is; ++j) {
                    const double a = R_A[is][j];
                    const double *kj = K + (size_t)j * n;
                    if (a == 0.0) continue;
                    for (i = 0; i < n; ++i) y[i] += a * kj[i];
                }
            } else {
                const double *kp = ki - n;
                for (i = 0; i < n; ++i) y[i] += kp[i];
            }
            if ((st = hy_sens_jfp(sn, w, t + R_CT[is] * h, y, kcap, sp, SP_STAGE(is)))) return st;
        }
        /* M k_i: a directional difference of g in x along the state stage k_i */
        sp->eps[is] = 0.0;
        for (i = 0; i < n; ++i) {
            const double r = fabs(ki[i]) / (fabs(x[i]) + w->atol[i] / w->rtol);
            if (r > kmax) kmax = r;
        }
#ifndef HY_SENS_NOHESS
        if (kmax > 0.0 && isfinite(kmax)) {
            const double eps = sq / kmax;
            for (i = 0; i < n; ++i) sn->xe[i] = x[i] + eps * ki[i];
            if ((st = hy_sens_jfp(sn, w, t, sn->xe, kcap, sp, SP_M(is)))) return st;
            sp->eps[is] = eps;
        }
#endif
    }
    return 0;
}

/* out = J S + df/dp (parameter columns only) with J, df/dp of point k.  Blocks are
   state-major (S[j * ns + c]: state j, column c), so every update below runs along the
   columns of one state row -- contiguous, vectorised -- instead of gathering one column at
   a time. */
static void hy_sens_g(const struct hy_sens *sn, const struct hy_sstep *sp, int k, const double *S, double *out)
{
    const int ns = sn->ns;
    const double *jv = sp->jv + (size_t)k * HY_NNZ, *fpv = sp->fpv + (size_t)k * HY_FP_NNZ;
    int c, e, q;
    memset(out, 0, sizeof(double) * (size_t)HY_NX * ns);
    for (e = 0; e < HY_NNZ; ++e) {
        const double a = jv[e];
        double *restrict o = out + (size_t)HY_JAC_ROW[e] * ns;
        const double *restrict s = S + (size_t)HY_JAC_COL[e] * ns;
        if (a == 0.0) continue;
        for (c = 0; c < ns; ++c) o[c] += a * s[c];
    }
    for (c = 0; c < ns; ++c) {
        const int p = sn->col_p[c];
        if (p >= 0)
            for (q = HY_FP_PTR[p]; q < HY_FP_PTR[p + 1]; ++q) out[(size_t)HY_FP_ROW[q] * ns + c] += fpv[q];
    }
}

/* Solve W X = B in place for the ns columns of the state-major block B, W the step's: the
   dense LU's substitutions row against row (the same operations, in the same order, as
   hy_solve on each column), the sparse LU (w's, sequential runs only) column by column
   through a gathered copy. */
static void hy_sens_solve(struct hy_sens *sn, const hy_ws *w, const struct hy_sstep *sp, double *B)
{
    const int ns = sn->ns;
    int i, j, c;
    if (!sp->use_dense) {
        double *v = sn->col;
        for (c = 0; c < ns; ++c) {
            for (i = 0; i < HY_NX; ++i) v[i] = B[(size_t)i * ns + c];
            hy_solve(w, v);
            for (i = 0; i < HY_NX; ++i) B[(size_t)i * ns + c] = v[i];
        }
        return;
    }
    {
        const double *restrict a = sp->dA;
        double *restrict V = sn->Vb;
        for (i = 0; i < HY_NX; ++i)                               /* V = P B */
            memcpy(V + (size_t)i * ns, B + (size_t)sp->dpiv[i] * ns, sizeof(double) * (size_t)ns);
        for (j = 0; j < HY_NX - 1; ++j) {
            const double *restrict vj = V + (size_t)j * ns;
            for (i = j + 1; i < HY_NX; ++i) {
                const double l = a[(size_t)i * HY_NX + j];
                double *restrict vi = V + (size_t)i * ns;
                if (l == 0.0) continue;
                for (c = 0; c < ns; ++c) vi[c] -= l * vj[c];
            }
        }
        for (j = HY_NX - 1; j >= 0; --j) {
            double *restrict vj = V + (size_t)j * ns;
            const double d = sp->ddinv[j];
            for (c = 0; c < ns; ++c) vj[c] *= d;
            for (i = 0; i < j; ++i) {
                const double l = a[(size_t)i * HY_NX + j];
                double *restrict vi = V + (size_t)i * ns;
                if (l == 0.0) continue;
                for (c = 0; c < ns; ++c) vi[c] -= l * vj[c];
            }
        }
        memcpy(B, V, sizeof(double) * (size_t)HY_NX * ns);
    }
}

/* dy/dtheta at output i (time to, state x, sensitivities S, state-major); w gives the inputs
   and parameters (its input lookup cache is written). */
static int hy_sens_emit(struct hy_sens *sn, hy_ws *w, int i, double to, const double *x, const double *S)
{
    if (sn->dX)
        memcpy(sn->dX + (size_t)i * HY_NX * sn->ns, S, sizeof(double) * (size_t)HY_NX * sn->ns);
    {
#if HY_NY > 0
    const int ns = sn->ns;
    double *dy = sn->dY + (size_t)i * HY_NY * ns;
    int c, j, q, st;
    hy_eval_u(w, to, INT_MAX, w->u);
    st = hy_gjac(to, x, w->p, w->u, sn->gxv, sn->gpv);
    if (st) return st;
    memset(dy, 0, sizeof(double) * (size_t)HY_NY * ns);
    for (j = 0; j < HY_NX; ++j) {
        const double *restrict s = S + (size_t)j * ns;
        for (q = HY_GX_PTR[j]; q < HY_GX_PTR[j + 1]; ++q) {
            double *restrict d = dy + (size_t)HY_GX_ROW[q] * ns;
            const double a = sn->gxv[q];
            for (c = 0; c < ns; ++c) d[c] += a * s[c];
        }
    }
    for (c = 0; c < ns; ++c) {
        const int k = sn->col_p[c];
        if (k >= 0)
            for (q = HY_GP_PTR[k]; q < HY_GP_PTR[k + 1]; ++q) dy[(size_t)HY_GP_ROW[q] * ns + c] += sn->gpv[q];
    }
#else
    (void)w; (void)to; (void)x; (void)S;
#endif
    }
    return 0;
}

/* The column part of a sensitivity step (the step record sp from hy_sens_points): the
   stages of S, S at tnext, and the output sensitivities in (t, tnext]. */
static int hy_sens_columns(struct hy_sens *sn, hy_ws *w, const struct hy_sstep *sp, const double *t_out, int n_out)
{
    const int n = HY_NX, ns = sn->ns;
    const size_t m = (size_t)n * ns;
    const double h = sp->h, t = sp->t, tnext = sp->tnext, ih = 1.0 / h;
    double *S = sn->S, *Sy = sn->Sy, *g0 = sn->g0, *g1 = sn->g1, *gt = sn->gt;
    size_t q;
    int is, j, st;

    hy_sens_g(sn, sp, SP_X, S, g0);
    hy_sens_g(sn, sp, SP_T, S, gt);
    for (q = 0; q < m; ++q) gt[q] = (gt[q] - g0[q]) / sp->dt;
    memcpy(Sy, S, sizeof(double) * m);
    for (is = 0; is < R_S; ++is) {
        double *ks = sn->KS + (size_t)is * m;
        const double hd = h * R_DT[is];
        if (is == 0) {
            for (q = 0; q < m; ++q) ks[q] = g0[q] + hd * gt[q];
        } else {
            if (is < R_NA) {
                for (q = 0; q < m; ++q) Sy[q] = S[q] + R_A[is][0] * sn->KS[q];
                for (j = 1; j < is; ++j) {
                    const double a = R_A[is][j];
                    const double *ksj = sn->KS + (size_t)j * m;
                    if (a == 0.0) continue;
                    for (q = 0; q < m; ++q) Sy[q] += a * ksj[q];
                }
            } else {
                const double *ksp = ks - m;
                for (q = 0; q < m; ++q) Sy[q] += ksp[q];
            }
            hy_sens_g(sn, sp, SP_STAGE(is), Sy, ks);
            if (hd != 0.0)
                for (q = 0; q < m; ++q) ks[q] += hd * gt[q];
            for (j = 0; j < is; ++j) {
                const double cc = ih * R_C[is][j];
                const double *ksj = sn->KS + (size_t)j * m;
                for (q = 0; q < m; ++q) ks[q] += cc * ksj[q];
            }
        }
        if (sp->eps[is] > 0.0) {                 /* M k_i */
            const double eps = sp->eps[is];
            hy_sens_g(sn, sp, SP_M(is), S, g1);
            for (q = 0; q < m; ++q) ks[q] += (g1[q] - g0[q]) / eps;
        }
        hy_sens_solve(sn, w, sp, ks);
    }
    {
        const double *kl = sn->KS + (size_t)(R_S - 1) * m;
        for (q = 0; q < m; ++q) sn->Sn[q] = Sy[q] + kl[q];
    }
    /* dense output in (t, tnext] */
    if (sn->iout < n_out && t_out[sn->iout] <= tnext) {
        int r;
        for (r = 0; r < R_NH; ++r) {
            double *dr = sn->DS + (size_t)r * m;
            memset(dr, 0, sizeof(double) * m);
            for (j = 0; j < R_S; ++j) {
                const double hh = R_H[r][j];
                const double *ksj = sn->KS + (size_t)j * m;
                if (hh != 0.0)
                    for (q = 0; q < m; ++q) dr[q] += hh * ksj[q];
            }
        }
        while (sn->iout < n_out && t_out[sn->iout] <= tnext) {
            const int io = sn->iout;
            const double to = t_out[io];
            const double *xo = sn->X_out + (size_t)io * n;
            if (to == tnext) {
                st = hy_sens_emit(sn, w, io, to, sp->xn, sn->Sn);
            } else {
                double s = (to - t) / (tnext - t), s1;
                if (s < 0.0) s = 0.0;
                s1 = 1.0 - s;
                for (q = 0; q < m; ++q) {
                    double v = sn->DS[(size_t)(R_NH - 1) * m + q];
                    for (r = R_NH - 2; r >= 0; --r) v = sn->DS[(size_t)r * m + q] + s * v;
                    g1[q] = S[q] * s1 + s * (sn->Sn[q] + s1 * v);
                }
                st = hy_sens_emit(sn, w, io, to, xo, g1);
            }
            if (st) return st;
            sn->iout++;
        }
    }
    { double *tmp = sn->S; sn->S = sn->Sn; sn->Sn = tmp; }
    return 0;
}
#endif
