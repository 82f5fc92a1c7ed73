/*
 * hy_sens_pipe.h -- the driver of the forward sensitivities (hy_sens.h): each accepted
 * state step's sensitivity step, run in sequence or pipelined in two threads; and
 * hy_simulate_sens.
 *
 * Why a pipeline: a sensitivity step has a state-only part (hy_sens_points: df/dx and
 * df/dp at 2 R_S + 1 points) and a part that grows with the columns (hy_sens_columns).
 * On the EHA's 30 s at 1 kHz (medians of 8, one process): a plain run 36 ms, a sensitivity
 * run with 1 column 157 ms, with 15 columns 320 ms.  Splitting the columns between two
 * runs in two threads (265 ms) repeats the state-only part in each thread.  Pipelined, the
 * caller's thread integrates the states and evaluates the points of step n + 1 while a
 * second thread does the columns of step n; each part is done once.
 *
 * Measured (EHA 30 s at 1 kHz, 15 columns, 2 idle cores, one process, interleaved): 163-170 ms
 * in sequence, 89-94 ms pipelined.  On this VM both fall into slower stretches when the host
 * is busy; the pipelined run, which needs both cores, then loses most of its gain.
 *
 * Hand-over: a ring of HY_RING step records (single producer, single consumer; C11
 * atomics, sequentially consistent).  A thread with nothing to do spins HY_SPIN polls,
 * then sleeps on a condition variable (the other thread wakes it only when it sleeps),
 * so a pipelined run on a busy machine does not burn a core waiting (spinning 0, 200 or
 * 4000 polls measured the same on an idle machine).  The column thread
 * gets its own copy of the workspace for the input lookup of the outputs (hy_eval_u
 * writes a cache); it reads the rows of X_out the integrator has written before it
 * published the step.  An error in either thread stops both; the first one is reported.
 * The pipeline needs the dense LU (the sparse LU's factors live in the integrator's
 * workspace and are overwritten by the next step): a sparse model runs in sequence.
 */
#ifndef HY_SENS_PIPE_H
#define HY_SENS_PIPE_H
#include <pthread.h>
#include <stdatomic.h>

#ifndef HY_RING
#define HY_RING 64
#endif
#ifndef HY_SPIN
#define HY_SPIN 500
#endif

/* each group on its own cache lines (see struct hy_sens) */
struct hy_pipe {
    _Alignas(HY_LINE) atomic_long head;    /* steps published by the integrator */
    _Alignas(HY_LINE) atomic_long tail;    /* steps whose columns are done */
    _Alignas(HY_LINE) atomic_int done, abort, err, sleepers;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_t th;
    struct hy_sens *sn;
    const double *t_out;
    int n_out;
    _Alignas(HY_LINE) hy_ws wb;            /* the column thread's workspace copy (inputs, parameters) */
    _Alignas(HY_LINE) char end;
};

static void hy_cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

static int hy_pipe_has_work(struct hy_pipe *pp)
{
    return atomic_load(&pp->head) > atomic_load(&pp->tail) || atomic_load(&pp->done) || atomic_load(&pp->abort);
}

static int hy_pipe_has_room(struct hy_pipe *pp)
{
    return atomic_load(&pp->head) - atomic_load(&pp->tail) < HY_RING || atomic_load(&pp->err);
}

/* wait until ready(pp): spin, then sleep on the condition variable */
static void hy_pipe_wait(struct hy_pipe *pp, int (*ready)(struct hy_pipe *))
{
    int i;
    for (i = 0; i < HY_SPIN; ++i) {
        if (ready(pp)) return;
        hy_cpu_relax();
    }
    pthread_mutex_lock(&pp->mu);
    atomic_fetch_add(&pp->sleepers, 1);
    while (!ready(pp)) pthread_cond_wait(&pp->cv, &pp->mu);
    atomic_fetch_sub(&pp->sleepers, 1);
    pthread_mutex_unlock(&pp->mu);
}

/* after a change of head, tail or a flag: wake the other thread if it sleeps */
static void hy_pipe_wake(struct hy_pipe *pp, int always)
{
    if (always || atomic_load(&pp->sleepers) > 0) {
        pthread_mutex_lock(&pp->mu);
        pthread_cond_broadcast(&pp->cv);
        pthread_mutex_unlock(&pp->mu);
    }
}

/* the column thread: the published steps' columns, in order */
static void *hy_pipe_columns(void *arg)
{
    struct hy_pipe *pp = (struct hy_pipe *)arg;
    for (;;) {
        const long k = atomic_load(&pp->tail);
        int st;
        hy_pipe_wait(pp, hy_pipe_has_work);
        if (atomic_load(&pp->abort) || atomic_load(&pp->head) == k) break;   /* aborted, or done and drained */
        st = hy_sens_columns(pp->sn, &pp->wb, &pp->sn->ring[k % HY_RING], pp->t_out, pp->n_out);
        if (st) {
            atomic_store(&pp->err, st);
            hy_pipe_wake(pp, 0);
            break;
        }
        atomic_store(&pp->tail, k + 1);
        hy_pipe_wake(pp, 0);
    }
    return NULL;
}

/* outputs at the initial time (already emitted by the integrator up to iout); then, when a
   pipeline was asked for and the LU is dense, the column thread starts. */
static int hy_sens_begin(struct hy_sens *sn, hy_ws *w, const double *t_out, int iout, int n_out, const double *x)
{
    struct hy_pipe *pp;
    int i, st;
    for (i = 0; i < iout; ++i)
        if ((st = hy_sens_emit(sn, w, i, t_out[i], x, sn->S))) return st;
    sn->iout = iout;
    if (!sn->pipelined || w->sparse) return 0;
    pp = (struct hy_pipe *)hy_lines(sizeof *pp);
    if (!pp) return 0;                                   /* run in sequence */
    memset(pp, 0, sizeof *pp);
    atomic_init(&pp->head, 0); atomic_init(&pp->tail, 0);
    atomic_init(&pp->done, 0); atomic_init(&pp->abort, 0); atomic_init(&pp->err, 0); atomic_init(&pp->sleepers, 0);
    pp->wb = *w; pp->sn = sn; pp->t_out = t_out; pp->n_out = n_out;
    if (pthread_mutex_init(&pp->mu, NULL)) { free(pp); return 0; }
    if (pthread_cond_init(&pp->cv, NULL)) { pthread_mutex_destroy(&pp->mu); free(pp); return 0; }
    if (pthread_create(&pp->th, NULL, hy_pipe_columns, pp)) {
        pthread_cond_destroy(&pp->cv); pthread_mutex_destroy(&pp->mu); free(pp);
        return 0;
    }
    sn->pipe = pp;
    sn->was_pipelined = 1;
    return 0;
}

/* the sensitivity step that follows an accepted state step (t, x) -> (tnext, xn) with
   stages K and factorised W: in sequence, or its points published to the column thread */
static int hy_sens_step(struct hy_sens *sn, hy_ws *w, double t, double tnext, double h, const double *x, const double *xn,
                        const double *K, int kcap, const double *t_out, int n_out)
{
    struct hy_pipe *pp = sn->pipe;
    long k;
    int st;
    if (!pp) {
        if ((st = hy_sens_points(sn, w, t, tnext, h, x, xn, K, kcap, sn->ring))) return st;
        return hy_sens_columns(sn, w, sn->ring, t_out, n_out);
    }
    hy_pipe_wait(pp, hy_pipe_has_room);
    if ((st = atomic_load(&pp->err))) return st;
    k = atomic_load(&pp->head);
    if ((st = hy_sens_points(sn, w, t, tnext, h, x, xn, K, kcap, &sn->ring[k % HY_RING]))) return st;
    atomic_store(&pp->head, k + 1);
    hy_pipe_wake(pp, 0);
    return 0;
}

/* the integration ended with ret: let the column thread finish (or stop it after an
   error) and join it; returns ret, or 100 + the column thread's model status */
static int hy_sens_end(struct hy_sens *sn, int ret)
{
    struct hy_pipe *pp = sn->pipe;
    int st;
    if (!pp) return ret;
    if (ret) atomic_store(&pp->abort, 1);
    atomic_store(&pp->done, 1);
    hy_pipe_wake(pp, 1);
    pthread_join(pp->th, NULL);
    st = atomic_load(&pp->err);
    if (!ret && st) ret = 100 + st;
    pthread_cond_destroy(&pp->cv);
    pthread_mutex_destroy(&pp->mu);
    free(pp);
    sn->pipe = NULL;
    return ret;
}

static int hy_integrate(const double *p, int n_tin, const double *t_in, const double *U, const int *u_hold,
                        double t0, const double *x0, int n_out, const double *t_out, double rtol,
                        const double *atol, double h0, double hmax, long max_steps, double *X_out,
                        double *Y_out, double *stats, struct hy_sens *sn);

/* hy_simulate plus sensitivities: ns columns, col_p[c] the parameter index of column c
   (-1: an initial-state column, whose S0 column is given), S0 HY_NX*ns state-major
   (S0[j*ns + c], a C-ordered nx x ns array),
   dY_out n_out*HY_NY*ns (row-major: output sample, output, column), dX_out (NULL or
   n_out*HY_NX*ns) the state sensitivities; pipelined != 0: the columns in a second thread
   (results bitwise the same).  stats[8] = number of df/dx, df/dp evaluations, stats[9] = 1
   when the run was pipelined. */
int hy_simulate_sens(
    const double *p, int n_tin, const double *t_in, const double *U, const int *u_hold,
    double t0, const double *x0, int n_out, const double *t_out, double rtol, const double *atol,
    double h0, double hmax, long max_steps, double *X_out, double *Y_out, double *stats,
    int ns, const int *col_p, const double *S0, double *dY_out, double *dX_out, int pipelined)
{
    struct hy_sens *sn;
    struct hy_sstep *ring;
    const size_t m = (size_t)HY_NX * (ns > 0 ? ns : 1);
    const int nring = pipelined ? HY_RING : 1;
    double *blk, *wa, *rd = NULL;
    int *ri = NULL;
    int ret;
    if (ns < 1 || !col_p || !S0 || (HY_NY > 0 && !dY_out)) return -1;
    sn = (struct hy_sens *)hy_lines(sizeof *sn);
    blk = (double *)hy_lines(sizeof(double) * ((7 + R_S + R_NH) * m + HY_GX_NNZ + HY_GP_NNZ + HY_NX + 2));
    wa = (double *)hy_lines(sizeof(double) * 2 * HY_NX);        /* the integrator thread's work */
    ring = (struct hy_sstep *)hy_lines(sizeof *ring * (size_t)nring);
    if (!sn || !blk || !wa || !ring || hy_sstep_alloc(ring, nring, &rd, &ri)) {
        free(sn); free(blk); free(wa); free(ring); free(rd); free(ri);
        return -1;
    }
    memset(sn, 0, sizeof *sn);
    sn->ns = ns; sn->col_p = col_p; sn->dY = dY_out; sn->dX = dX_out; sn->X_out = X_out;
    sn->pipelined = pipelined != 0; sn->ring = ring;
    sn->xe = wa; sn->ye = wa + HY_NX;
    sn->S = blk; sn->Sn = sn->S + m; sn->Sy = sn->Sn + m; sn->g0 = sn->Sy + m; sn->g1 = sn->g0 + m; sn->gt = sn->g1 + m;
    sn->KS = sn->gt + m; sn->DS = sn->KS + (size_t)R_S * m; sn->gxv = sn->DS + (size_t)R_NH * m;
    sn->gpv = sn->gxv + HY_GX_NNZ + 1; sn->col = sn->gpv + HY_GP_NNZ + 1; sn->Vb = sn->col + HY_NX;
    memcpy(sn->S, S0, sizeof(double) * m);
    ret = hy_integrate(p, n_tin, t_in, U, u_hold, t0, x0, n_out, t_out, rtol, atol, h0, hmax, max_steps,
                       X_out, Y_out, stats, sn);
    stats[8] = (double)sn->ngev;
    stats[9] = (double)sn->was_pipelined;
    free(sn); free(blk); free(wa); free(ring); free(rd); free(ri);
    return ret;
}
#endif
