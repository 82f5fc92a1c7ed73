/* Linear algebra of the hydrocli integrator (included by hy_integrator.c after the
   workspace type): W = I/(h*gamma) - J factorised densely (partial pivoting) for small
   systems, sparsely on the fixed Jacobian pattern (minimum degree, static pivoting with a
   dense fallback) for large ones. */
#ifndef HY_LINALG_H
#define HY_LINALG_H
/* the dense LU and the assembly of W are unrolled like the solve (HY_UNROLL, set by
   hy_integrator.c for HY_NX <= 12): the compile-time bounds then drop the loop control and the
   stores of W go to fixed offsets; together ~7 % off the EHA's 20 s (issue 16, A/B, the same
   arithmetic and results) */
#if HY_NX <= 12 && HY_NNZ <= 64 && defined(__GNUC__) && !defined(__clang__)
#define HY_UNROLL_NNZ _Pragma("GCC unroll 64")
#else
#define HY_UNROLL_NNZ
#endif

/* ------------------------------------------------------------- dense LU */

/* Row-major, partial pivoting (whole rows swapped, so P A = L U); the size is the
   compile-time HY_NX so that small systems are fully unrolled.  The diagonal of U is stored
   inverted in dinv; piv[i] is the original row that ends in row i (P as a gather list). */
static int hy_lu_dense(double *restrict a, int *restrict piv, double *restrict dinv)
{
    int i, j, k;
    for (i = 0; i < HY_NX; ++i) piv[i] = i;
    HY_UNROLL
    for (k = 0; k < HY_NX; ++k) {
        int pr = k;
        double amax = fabs(a[(size_t)k * HY_NX + k]);
        HY_UNROLL
        for (i = k + 1; i < HY_NX; ++i) {
            double v = fabs(a[(size_t)i * HY_NX + k]);
            if (v > amax) { amax = v; pr = i; }
        }
        if (!(amax > 0.0) || !isfinite(amax)) return 1;
        if (pr != k) {
            double *r1 = a + (size_t)k * HY_NX, *r2 = a + (size_t)pr * HY_NX;
            const int tp = piv[k];
            for (j = 0; j < HY_NX; ++j) { double tmp = r1[j]; r1[j] = r2[j]; r2[j] = tmp; }
            piv[k] = piv[pr];
            piv[pr] = tp;
        }
        {
            const double *rk = a + (size_t)k * HY_NX;
            const double inv = 1.0 / rk[k];
            dinv[k] = inv;
            HY_UNROLL
            for (i = k + 1; i < HY_NX; ++i) {
                double *ri = a + (size_t)i * HY_NX;
                const double l = ri[k] * inv;
                ri[k] = l;
                if (l != 0.0) {
                    HY_UNROLL
                    for (j = k + 1; j < HY_NX; ++j) ri[j] -= l * rk[j];
                }
            }
        }
    }
    return 0;
}

/* Solve L U x = P b in place.  The right-hand side is worked on in a local copy so that,
   with the size a compile-time constant and the loops unrolled, it lives in registers: through
   the pointer b every store would force the compiler to reload (b may alias a), which made
   this solve the largest single cost of a step on the EHA (perf, issue 16). */
static void hy_lu_dense_solve(const double *restrict a, const int *restrict piv, const double *restrict dinv,
                              double *restrict b)
{
    double v[HY_NX];
    int i, j;
    HY_UNROLL
    for (i = 0; i < HY_NX; ++i) v[i] = b[piv[i]];      /* v = P b */
    /* column-oriented substitutions: independent updates, no long FP chain */
    HY_UNROLL
    for (j = 0; j < HY_NX - 1; ++j) {
        const double bj = v[j];
        HY_UNROLL
        for (i = j + 1; i < HY_NX; ++i) v[i] -= a[(size_t)i * HY_NX + j] * bj;
    }
    HY_UNROLL
    for (j = HY_NX - 1; j >= 0; --j) {
        const double bj = v[j] * dinv[j];
        v[j] = bj;
        HY_UNROLL
        for (i = 0; i < j; ++i) v[i] -= a[(size_t)i * HY_NX + j] * bj;
    }
    HY_UNROLL
    for (i = 0; i < HY_NX; ++i) b[i] = v[i];
}

/* ------------------------------------------------------------ sparse LU */

/* Minimum-degree ordering + symbolic fill.  Returns 1 if the sparse path was set
   up, 0 if dense should be used, -1 on allocation failure. */
static int hy_setup_sparse(hy_ws *w, int force)
{
    const int n = HY_NX;
    unsigned char *adj = (unsigned char *)calloc((size_t)n * n, 1);
    int *deg = (int *)malloc(sizeof(int) * (size_t)n);
    int *nb = (int *)malloc(sizeof(int) * (size_t)n);
    unsigned char *el = (unsigned char *)calloc((size_t)n, 1);
    int *iperm = (int *)malloc(sizeof(int) * (size_t)n);
    int e, i, k, ret = -1;
    long fnnz;
    if (!adj || !deg || !nb || !el || !iperm) goto done;
    w->perm = (int *)malloc(sizeof(int) * (size_t)n);
    if (!w->perm) goto done;
    for (e = 0; e < HY_NNZ; ++e) {
        int r = HY_JAC_ROW[e], c = HY_JAC_COL[e];
        if (r != c) { adj[(size_t)r * n + c] = 1; adj[(size_t)c * n + r] = 1; }
    }
    for (i = 0; i < n; ++i) {
        int d = 0, j;
        const unsigned char *ar = adj + (size_t)i * n;
        for (j = 0; j < n; ++j) d += ar[j];
        deg[i] = d;
    }
    for (k = 0; k < n; ++k) {
        int v = -1, dmin = INT_MAX, m = 0, a, b, u;
        unsigned char *av;
        for (i = 0; i < n; ++i)
            if (!el[i] && deg[i] < dmin) { dmin = deg[i]; v = i; }
        w->perm[k] = v;
        iperm[v] = k;
        el[v] = 1;
        av = adj + (size_t)v * n;
        for (u = 0; u < n; ++u)
            if (av[u] && !el[u]) nb[m++] = u;
        for (a = 0; a < m; ++a) deg[nb[a]]--;
        for (a = 0; a < m; ++a) {
            unsigned char *ra = adj + (size_t)nb[a] * n;
            for (b = 0; b < m; ++b) {
                if (b != a && !ra[nb[b]]) { ra[nb[b]] = 1; deg[nb[a]]++; }
            }
        }
    }
    fnnz = n;
    for (i = 0; i < (long)n * n; ++i) fnnz += adj[i];
    if (!force && fnnz > (long)n * n / 4) { ret = 0; goto done; }
    w->fnnz = (int)fnnz;
    w->frp = (int *)malloc(sizeof(int) * (size_t)(n + 1));
    w->fci = (int *)malloc(sizeof(int) * (size_t)fnnz);
    w->fdiag = (int *)malloc(sizeof(int) * (size_t)n);
    w->jpos = (int *)malloc(sizeof(int) * (size_t)(HY_NNZ > 0 ? HY_NNZ : 1));
    w->fv = (double *)malloc(sizeof(double) * (size_t)fnnz);
    w->finv = (double *)malloc(sizeof(double) * (size_t)n);
    w->fw = (double *)calloc((size_t)n, sizeof(double));
    w->fw2 = (double *)malloc(sizeof(double) * (size_t)n);
    if (!w->frp || !w->fci || !w->fdiag || !w->jpos || !w->fv || !w->finv || !w->fw || !w->fw2)
        goto done;
    {
        int pos = 0, c;
        for (k = 0; k < n; ++k) {
            const int v = w->perm[k];
            const unsigned char *av = adj + (size_t)v * n;
            w->frp[k] = pos;
            for (c = 0; c < n; ++c) {
                const int u = w->perm[c];
                if (u == v || av[u]) {
                    if (c == k) w->fdiag[k] = pos;
                    w->fci[pos++] = c;
                }
            }
        }
        w->frp[n] = pos;
    }
    for (e = 0; e < HY_NNZ; ++e) {
        const int r = iperm[HY_JAC_ROW[e]], c = iperm[HY_JAC_COL[e]];
        int lo = w->frp[r], hi = w->frp[r + 1] - 1;
        while (lo < hi) {
            int mid = (lo + hi) >> 1;
            if (w->fci[mid] < c) lo = mid + 1; else hi = mid;
        }
        w->jpos[e] = lo;
    }
    w->sparse = 1;
    ret = 1;
done:
    free(adj); free(deg); free(nb); free(el); free(iperm);
    return ret;
}

static int hy_lu_sparse(hy_ws *w)
{
    const int n = HY_NX;
    double *v = w->fv, *x = w->fw;
    const int *rp = w->frp, *ci = w->fci, *dg = w->fdiag;
    int i, p, q;
    for (i = 0; i < n; ++i) {
        const int p0 = rp[i], p1 = rp[i + 1], pd = dg[i];
        double rmax = 0.0, d;
        for (p = p0; p < p1; ++p) {
            double a = fabs(v[p]);
            x[ci[p]] = v[p];
            if (a > rmax) rmax = a;
        }
        for (p = p0; p < pd; ++p) {
            const int k = ci[p];
            const double l = x[k] * w->finv[k];
            x[k] = l;
            if (l != 0.0) {
                const int q1 = rp[k + 1];
                for (q = dg[k] + 1; q < q1; ++q) x[ci[q]] -= l * v[q];
            }
        }
        for (p = p0; p < p1; ++p) { const int c = ci[p]; v[p] = x[c]; x[c] = 0.0; }
        d = v[pd];
        if (!(fabs(d) > HY_PIVTOL * rmax) || !isfinite(d)) return 1;
        w->finv[i] = 1.0 / d;
    }
    return 0;
}

static void hy_lu_sparse_solve(const hy_ws *w, double *b)
{
    const int n = HY_NX;
    const double *v = w->fv;
    const int *rp = w->frp, *ci = w->fci, *dg = w->fdiag, *pm = w->perm;
    double *y = w->fw2;
    int i, p;
    for (i = 0; i < n; ++i) y[i] = b[pm[i]];
    for (i = 0; i < n; ++i) {
        double s = y[i];
        for (p = rp[i]; p < dg[i]; ++p) s -= v[p] * y[ci[p]];
        y[i] = s;
    }
    for (i = n - 1; i >= 0; --i) {
        double s = y[i];
        const int p1 = rp[i + 1];
        for (p = dg[i] + 1; p < p1; ++p) s -= v[p] * y[ci[p]];
        y[i] = s * w->finv[i];
    }
    for (i = 0; i < n; ++i) b[pm[i]] = y[i];
}

/* factor W = fac*I - J.  0 ok, 1 singular, -1 out of memory */
static int hy_factor(hy_ws *w, double fac)
{
    const int n = HY_NX;
    int e, i;
    if (w->sparse) {
        memset(w->fv, 0, sizeof(double) * (size_t)w->fnnz);
        for (e = 0; e < HY_NNZ; ++e) w->fv[w->jpos[e]] -= w->jv[e];
        for (i = 0; i < n; ++i) w->fv[w->fdiag[i]] += fac;
        if (hy_lu_sparse(w) == 0) { w->use_dense = 0; return 0; }
        w->nfallback++;
    }
    if (!w->dA) {
        w->dA = (double *)malloc(sizeof(double) * (size_t)n * n);
        w->dpiv = (int *)malloc(sizeof(int) * (size_t)n);
        w->ddinv = (double *)malloc(sizeof(double) * (size_t)n);
        if (!w->dA || !w->dpiv || !w->ddinv) return -1;
    }
    memset(w->dA, 0, sizeof(double) * (size_t)n * n);
    HY_UNROLL_NNZ
    for (e = 0; e < HY_NNZ; ++e)
        w->dA[(size_t)HY_JAC_ROW[e] * n + HY_JAC_COL[e]] -= w->jv[e];
    HY_UNROLL
    for (i = 0; i < n; ++i) w->dA[(size_t)i * n + i] += fac;
    w->use_dense = 1;
    return hy_lu_dense(w->dA, w->dpiv, w->ddinv);
}

static void hy_solve(const hy_ws *w, double *b)
{
    if (w->use_dense) hy_lu_dense_solve(w->dA, w->dpiv, w->ddinv, b);
    else hy_lu_sparse_solve(w, b);
}

#endif
