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
 */
#ifndef HY_SENS_H
#define HY_SENS_H
#ifndef HY_HAS_JAC
#error "hy_sens.h: sensitivities need the analytic Jacobian (HY_HAS_JAC)"
#endif

struct hy_sens {
    int ns;                  /* sensitivity columns */
    const int *col_p;        /* parameter index of a column, -1 for an initial-state column */
    double *S, *Sn, *Sy;     /* HY_NX*ns, state-major (S[j*ns + c]): current, new, stage value */
    double *KS, *DS;         /* R_S and R_NH blocks of HY_NX*ns: stages, dense coefficients */
    double *g0, *g1, *gt;    /* HY_NX*ns work */
    double *jv, *fpv, *gxv, *gpv, *xe, *ye;
    double *Vb, *col;        /* the block solve's work: HY_NX*ns, HY_NX */
    double *dY;              /* n_out * HY_NY * ns */
    double *dX;              /* n_out * HY_NX * ns, or NULL */
    const double *X_out;
    int iout;                /* outputs whose sensitivities are written */
    long ngev;               /* evaluations of g */
};

/* out = J(t, x) S + df/dp(t, x) (parameter columns only).  Blocks are state-major
   (S[j * ns + c]: state j, column c), so every update below runs along the columns of one
   state row -- contiguous, vectorised -- instead of gathering one column at a time. */
static int hy_sens_g(struct hy_sens *sn, hy_ws *w, double t, const double *x, const double *S, int kcap,
                     double *out)
{
    const int ns = sn->ns;
    int c, e, q, st;
    hy_eval_u(w, t, kcap, w->u);
    st = hy_jfp(t, x, w->p, w->u, sn->jv, sn->fpv);
    if (st) return st;
    sn->ngev++;
    memset(out, 0, sizeof(double) * (size_t)HY_NX * ns);
    for (e = 0; e < HY_NNZ; ++e) {
        const double a = sn->jv[e];
        double *restrict o = out + (size_t)HY_JAC_ROW[e] * ns;
        const double *restrict s = S + (size_t)HY_JAC_COL[e] * ns;
        if (a == 0.0) continue;
        for (c = 0; c < ns; ++c) o[c] += a * s[c];
    }
    for (c = 0; c < ns; ++c) {
        const int k = sn->col_p[c];
        if (k >= 0)
            for (q = HY_FP_PTR[k]; q < HY_FP_PTR[k + 1]; ++q) out[(size_t)HY_FP_ROW[q] * ns + c] += sn->fpv[q];
    }
    return 0;
}

/* Solve W X = B in place for the ns columns of the state-major block B: the dense LU's
   substitutions row against row (the same operations, in the same order, as hy_solve on each
   column), the sparse LU column by column through a gathered copy. */
static void hy_sens_solve(struct hy_sens *sn, const hy_ws *w, double *B)
{
    const int ns = sn->ns;
    int i, j, c;
    if (!w->use_dense) {
        double *v = sn->col;
        for (c = 0; c < ns; ++c) {
            for (i = 0; i < HY_NX; ++i) v[i] = B[(size_t)i * ns + c];
            hy_solve(w, v);
            for (i = 0; i < HY_NX; ++i) B[(size_t)i * ns + c] = v[i];
        }
        return;
    }
    {
        const double *restrict a = w->dA;
        double *restrict V = sn->Vb;
        for (i = 0; i < HY_NX; ++i)                               /* V = P B */
            memcpy(V + (size_t)i * ns, B + (size_t)w->dpiv[i] * ns, sizeof(double) * (size_t)ns);
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
            const double d = w->ddinv[j];
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

/* dy/dtheta at output i (time to, state x, sensitivities S, state-major). */
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

/* outputs at the initial time (already emitted by the integrator up to iout). */
static int hy_sens_begin(struct hy_sens *sn, hy_ws *w, const double *t_out, int iout, const double *x)
{
    int i, st;
    for (i = 0; i < iout; ++i)
        if ((st = hy_sens_emit(sn, w, i, t_out[i], x, sn->S))) return st;
    sn->iout = iout;
    return 0;
}

/* the sensitivity step that follows an accepted state step (t, x) -> (t + h, xn) with
   stages K and factorised W; writes the output sensitivities in (t, t + h]. */
static int hy_sens_step(struct hy_sens *sn, hy_ws *w, double t, double tnext, double h, const double *x, const double *xn,
                        const double *K, int kcap, const double *t_out, int n_out)
{
    const int n = HY_NX, ns = sn->ns;
    const size_t m = (size_t)n * ns;
    const double sq = 1.4901161193847656e-08, ih = 1.0 / h;
    double *S = sn->S, *Sy = sn->Sy, *g0 = sn->g0, *g1 = sn->g1, *gt = sn->gt, *y = sn->ye;
    size_t q;
    int is, j, i, st;
    volatile double tt;
    double dt;

    if ((st = hy_sens_g(sn, w, t, x, S, kcap, g0))) return st;
    tt = t + sq * (fabs(t) > 1.0 ? fabs(t) : 1.0);
    dt = tt - t;
    if ((st = hy_sens_g(sn, w, t + dt, x, S, kcap, gt))) return st;
    for (q = 0; q < m; ++q) gt[q] = (gt[q] - g0[q]) / dt;
    memcpy(Sy, S, sizeof(double) * m);
    memcpy(y, x, sizeof(double) * (size_t)n);
    for (is = 0; is < R_S; ++is) {
        double *ks = sn->KS + (size_t)is * m;
        const double *ki = K + (size_t)is * n;
        const double hd = h * R_DT[is];
        double kmax = 0.0;
        if (is == 0) {
            for (q = 0; q < m; ++q) ks[q] = g0[q] + hd * gt[q];
        } else {
            if (is < R_NA) {
                for (i = 0; i < n; ++i) y[i] = x[i] + R_A[is][0] * K[i];
                for (q = 0; q < m; ++q) Sy[q] = S[q] + R_A[is][0] * sn->KS[q];
                for (j = 1; j < is; ++j) {
                    const double a = R_A[is][j];
                    const double *kj = K + (size_t)j * n, *ksj = sn->KS + (size_t)j * m;
                    if (a == 0.0) continue;
                    for (i = 0; i < n; ++i) y[i] += a * kj[i];
                    for (q = 0; q < m; ++q) Sy[q] += a * ksj[q];
                }
            } else {
                const double *kp = ki - n, *ksp = ks - m;
                for (i = 0; i < n; ++i) y[i] += kp[i];
                for (q = 0; q < m; ++q) Sy[q] += ksp[q];
            }
            if ((st = hy_sens_g(sn, w, t + R_CT[is] * h, y, Sy, kcap, ks))) return st;
            if (hd != 0.0)
                for (q = 0; q < m; ++q) ks[q] += hd * gt[q];
            for (j = 0; j < is; ++j) {
                const double cc = ih * R_C[is][j];
                const double *ksj = sn->KS + (size_t)j * m;
                for (q = 0; q < m; ++q) ks[q] += cc * ksj[q];
            }
        }
        /* M k_i: directional difference of g in x along the state stage k_i */
        for (i = 0; i < n; ++i) {
            const double r = fabs(ki[i]) / (fabs(x[i]) + w->atol[i] / w->rtol);
            if (r > kmax) kmax = r;
        }
#ifndef HY_SENS_NOHESS
        if (kmax > 0.0 && isfinite(kmax)) {
            const double eps = sq / kmax;
            for (i = 0; i < n; ++i) sn->xe[i] = x[i] + eps * ki[i];
            if ((st = hy_sens_g(sn, w, t, sn->xe, S, kcap, g1))) return st;
            for (q = 0; q < m; ++q) ks[q] += (g1[q] - g0[q]) / eps;
        }
#endif
        hy_sens_solve(sn, w, ks);
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
                st = hy_sens_emit(sn, w, io, to, xn, sn->Sn);
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

static int hy_integrate(const double *p, int n_tin, const double *t_in, const double *U, const int *u_hold,
                        double t0, const double *x0, int n_out, const double *t_out, double rtol,
                        const double *atol, double h0, double hmax, long max_steps, double *X_out,
                        double *Y_out, double *stats, struct hy_sens *sn);

/* hy_simulate plus sensitivities: ns columns, col_p[c] the parameter index of column c
   (-1: an initial-state column, whose S0 column is given), S0 HY_NX*ns state-major
   (S0[j*ns + c], a C-ordered nx x ns array),
   dY_out n_out*HY_NY*ns (row-major: output sample, output, column), dX_out (NULL or
   n_out*HY_NX*ns) the state sensitivities.  stats[8] = number
   of sensitivity right-hand-side evaluations. */
int hy_simulate_sens(
    const double *p, int n_tin, const double *t_in, const double *U, const int *u_hold,
    double t0, const double *x0, int n_out, const double *t_out, double rtol, const double *atol,
    double h0, double hmax, long max_steps, double *X_out, double *Y_out, double *stats,
    int ns, const int *col_p, const double *S0, double *dY_out, double *dX_out)
{
    struct hy_sens sn;
    const size_t m = (size_t)HY_NX * (ns > 0 ? ns : 1);
    double *blk;
    int ret;
    memset(&sn, 0, sizeof sn);
    if (ns < 1 || !col_p || !S0 || (HY_NY > 0 && !dY_out)) return -1;
    blk = (double *)malloc(sizeof(double) * ((7 + R_S + R_NH) * m + HY_NNZ + HY_FP_NNZ + HY_GX_NNZ
                                             + HY_GP_NNZ + 3 * HY_NX + 4));
    if (!blk) return -1;
    sn.ns = ns; sn.col_p = col_p; sn.dY = dY_out; sn.dX = dX_out; sn.X_out = X_out;
    sn.S = blk; sn.Sn = sn.S + m; sn.Sy = sn.Sn + m; sn.g0 = sn.Sy + m; sn.g1 = sn.g0 + m; sn.gt = sn.g1 + m;
    sn.KS = sn.gt + m; sn.DS = sn.KS + (size_t)R_S * m; sn.jv = sn.DS + (size_t)R_NH * m;
    sn.fpv = sn.jv + HY_NNZ + 1; sn.gxv = sn.fpv + HY_FP_NNZ + 1; sn.gpv = sn.gxv + HY_GX_NNZ + 1;
    sn.xe = sn.gpv + HY_GP_NNZ + 1; sn.ye = sn.xe + HY_NX; sn.col = sn.ye + HY_NX; sn.Vb = sn.col + HY_NX;
    memcpy(sn.S, S0, sizeof(double) * m);
    ret = hy_integrate(p, n_tin, t_in, U, u_hold, t0, x0, n_out, t_out, rtol, atol, h0, hmax, max_steps,
                       X_out, Y_out, stats, &sn);
    stats[8] = (double)sn.ngev;
    free(blk);
    return ret;
}
#endif
