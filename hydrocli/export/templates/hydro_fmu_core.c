/*
 * hydro_fmu_core.c -- the FMI-version-independent part of a hydrocli FMU, included by
 * hydro_fmi2.c and hydro_fmi3.c (one translation unit with the generated model).
 *
 * Contents: the generated model (model.c: HY_NX..., hy_rhs, hy_out, hy_jac), the hydrocli
 * Rosenbrock integrator (hy_integrator.c: hy_simulate), the export's configuration
 * (hy_fmu_config.h: token, start values, nominals, guard messages), and the instance with
 * its get/set, step and directional-derivative logic. Status codes are ints with the values
 * FMI 2 and FMI 3 share (0 OK, 1 Warning, 2 Discard, 3 Error).
 *
 * Value references (hydrocli/export/variables.py): states [0, NX), derivatives [NX, 2NX),
 * parameters, inputs, outputs -- the generated code's array order.
 * Co-simulation: a step integrates [t, t+h] with hy_simulate (variable step, error control,
 * the analytic Jacobian); inputs are held over the step, or ramped when the master gave their
 * first derivatives. Directional derivatives: the analytic Jacobian hy_jac for
 * d(der)/d(states), a directional difference quotient for the input and output parts.
 * Licence: Apache-2.0 (hydrocli); the FMI headers are BSD-2-Clause (FMI_HEADERS_LICENSE.txt).
 */
#include "model.c"
#include "hy_integrator.c"
#include "hy_fmu_config.h"

#include <stdio.h>
#include <stdarg.h>

#define NXA (HY_NX > 0 ? HY_NX : 1)
#define NPA (HY_NP > 0 ? HY_NP : 1)
#define NUA (HY_NU > 0 ? HY_NU : 1)
#define NYA (HY_NY > 0 ? HY_NY : 1)
#define VR_DX (HY_NX)
#define VR_P (2 * HY_NX)
#define VR_U (VR_P + HY_NP)
#define VR_Y (VR_U + HY_NU)
#define VR_END (VR_Y + HY_NY)

enum { ST_OK = 0, ST_WARNING = 1, ST_DISCARD = 2, ST_ERROR = 3 };

typedef enum { M_INSTANTIATED = 1, M_INIT = 2, M_EVENT = 4, M_CONT = 8, M_STEP = 16,
               M_TERMINATED = 32, M_ERROR = 64 } Mode;
#define M_ANY (M_INSTANTIATED | M_INIT | M_EVENT | M_CONT | M_STEP | M_TERMINATED)

typedef struct {             /* everything GetFMUstate copies */
    Mode mode;
    double t, rtol, h_last;
    double x[NXA], p[NPA], u[NUA], du[NUA];
    int have_du;
} State;

typedef struct Inst Inst;
typedef void (*EmitFn)(Inst *c, int status, const char *category, const char *message);

struct Inst {
    EmitFn emit;             /* the FMI version's logger call */
    void *env;               /* componentEnvironment / instanceEnvironment */
    void *logger;            /* fmi2CallbackLogger / fmi3LogMessageCallback */
    char name[128];
    int is_cs, log_on;
    State s;
};

static void logf_(Inst *c, int st, const char *cat, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    if (!c || !c->emit) return;
    if (st == ST_OK && !c->log_on) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    c->emit(c, st, cat, buf);
}

static int allowed(Inst *c, const char *fn, int modes)
{
    if (!c) return 0;
    if (c->s.mode & modes) return 1;
    logf_(c, ST_ERROR, "logStatusError", "%s: not allowed in the current state (%d)", fn, (int)c->s.mode);
    c->s.mode = M_ERROR;
    return 0;
}

static int model_status(Inst *c, int st, const char *what)
{
    if (st == 0) return ST_OK;
    if (st > 0 && st <= HY_FMU_NGUARD)
        logf_(c, ST_ERROR, "logStatusError", "%s at t = %g s: %s", what, c->s.t, HY_FMU_GUARDS[st - 1]);
    else
        logf_(c, ST_ERROR, "logStatusError", "%s at t = %g s: model status %d", what, c->s.t, st);
    return ST_ERROR;
}

static const char *integrator_message(int st)
{
    switch (st) {
    case 1: return "step size underflow (stiffness blow-up or a discontinuity)";
    case 2: return "maximum number of steps exceeded";
    case 3: return "a state became NaN or infinite";
    default: return "invalid arguments or out of memory in the integrator";
    }
}

static void reset_state(Inst *c)
{
    int i;
    memset(&c->s, 0, sizeof c->s);
    c->s.mode = M_INSTANTIATED;
    c->s.rtol = HY_FMU_RTOL;
    for (i = 0; i < HY_NX; ++i) c->s.x[i] = HY_FMU_X0[i];
    for (i = 0; i < HY_NP; ++i) c->s.p[i] = HY_FMU_P0[i];
    for (i = 0; i < HY_NU; ++i) c->s.u[i] = 0.0;
}

static Inst *new_instance(const char *name, int is_cs, int log_on, EmitFn emit, void *env, void *logger)
{
    Inst *c = (Inst *)calloc(1, sizeof(Inst));
    if (!c) return NULL;
    c->emit = emit; c->env = env; c->logger = logger;
    snprintf(c->name, sizeof c->name, "%s", name ? name : "hydrocli");
    c->is_cs = is_cs;
    c->log_on = log_on;
    reset_state(c);
    return c;
}

static int check_initial_state(Inst *c)
{
    double dx[NXA];
    const int st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, dx);
    if (st) { c->s.mode = M_ERROR; return model_status(c, st, "initial state"); }
    return ST_OK;
}

static int get_real(Inst *c, const unsigned int vr[], size_t n, double value[])
{
    double dx[NXA], y[NYA];
    int have_dx = 0, have_y = 0, st;
    size_t k;
    if (!allowed(c, "GetReal", M_ANY)) return ST_ERROR;
    for (k = 0; k < n; ++k) {
        const unsigned int r = vr[k];
        if (r < VR_DX) value[k] = c->s.x[r];
        else if (r < VR_P) {
            if (!have_dx) {
                st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, dx);
                if (st) return model_status(c, st, "GetReal (derivatives)");
                have_dx = 1;
            }
            value[k] = dx[r - VR_DX];
        } else if (r < VR_U) value[k] = c->s.p[r - VR_P];
        else if (r < VR_Y) value[k] = c->s.u[r - VR_U];
        else if (r < VR_END) {
            if (!have_y) {
                st = hy_out(c->s.t, c->s.x, c->s.p, c->s.u, y);
                if (st) return model_status(c, st, "GetReal (outputs)");
                have_y = 1;
            }
            value[k] = y[r - VR_Y];
        } else {
            logf_(c, ST_ERROR, "logStatusError", "GetReal: unknown value reference %u", (unsigned)r);
            return ST_ERROR;
        }
    }
    return ST_OK;
}

static int set_real(Inst *c, const unsigned int vr[], size_t n, const double value[])
{
    size_t k;
    if (!allowed(c, "SetReal", M_INSTANTIATED | M_INIT | M_EVENT | M_CONT | M_STEP)) return ST_ERROR;
    for (k = 0; k < n; ++k) {
        const unsigned int r = vr[k];
        if (r < VR_DX && (c->s.mode & (M_INSTANTIATED | M_INIT))) c->s.x[r] = value[k];
        else if (r >= VR_P && r < VR_U) c->s.p[r - VR_P] = value[k];
        else if (r >= VR_U && r < VR_Y) { c->s.u[r - VR_U] = value[k]; c->s.have_du = 0; }
        else {
            logf_(c, ST_ERROR, "logStatusError", "SetReal: value reference %u cannot be set now",
                  (unsigned)r);
            return ST_ERROR;
        }
    }
    return ST_OK;
}

/* d(unknowns) = d(unknowns)/d(knowns) * dvKnown; knowns are states and inputs, unknowns are
   derivatives and outputs.  der/states: analytic Jacobian (hy_jac) when the model has one;
   everything else: one directional difference quotient. */
static int directional_derivative(Inst *c, const unsigned int vU[], size_t nU,
                                        const unsigned int vK[], size_t nK,
                                        const double dvK[], double dvU[])
{
    double vx[NXA], vu[NUA], x1[NXA], u1[NUA], f0[NXA], f1[NXA], y0[NYA], y1[NYA];
    double eps;
    int i, st, fd_x;
    size_t k;
    if (!allowed(c, "GetDirectionalDerivative", M_INIT | M_EVENT | M_CONT | M_STEP)) return ST_ERROR;
    memset(vx, 0, sizeof vx); memset(vu, 0, sizeof vu);
    for (k = 0; k < nK; ++k) {
        const unsigned int r = vK[k];
        if (r < VR_DX) vx[r] = dvK[k];
        else if (r >= VR_U && r < VR_Y) vu[r - VR_U] = dvK[k];
        else {
            logf_(c, ST_ERROR, "logStatusError",
                  "GetDirectionalDerivative: known %u is not a state or an input", (unsigned)r);
            return ST_ERROR;
        }
    }
#ifdef HY_HAS_JAC
    fd_x = 0;
#else
    fd_x = 1;
#endif
    /* step along the direction: each perturbed component moves by about sqrt(eps) of its size */
    eps = HUGE_VAL;
    for (i = 0; i < HY_NX; ++i) {
        const double a = fabs(c->s.x[i]) > HY_FMU_NOMINAL[i] ? fabs(c->s.x[i]) : HY_FMU_NOMINAL[i];
        if (vx[i] != 0.0 && a / fabs(vx[i]) < eps) eps = a / fabs(vx[i]);
    }
    for (i = 0; i < HY_NU; ++i) {
        const double a = fabs(c->s.u[i]) > 1.0 ? fabs(c->s.u[i]) : 1.0;
        if (vu[i] != 0.0 && a / fabs(vu[i]) < eps) eps = a / fabs(vu[i]);
    }
    eps = isfinite(eps) ? 1.4901161193847656e-08 * eps : 0.0;
    for (i = 0; i < HY_NX; ++i) x1[i] = c->s.x[i] + eps * vx[i];
    for (i = 0; i < HY_NU; ++i) u1[i] = c->s.u[i] + eps * vu[i];
    for (k = 0; k < nU; ++k) dvU[k] = 0.0;
    if (eps == 0.0) return ST_OK;

    st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, f0);
    if (!st) st = hy_out(c->s.t, c->s.x, c->s.p, c->s.u, y0);
    if (!st) st = hy_rhs(c->s.t, fd_x ? x1 : c->s.x, c->s.p, u1, f1);  /* input part (and states without hy_jac) */
    if (!st) st = hy_out(c->s.t, x1, c->s.p, u1, y1);
    if (st) return model_status(c, st, "GetDirectionalDerivative");
#ifdef HY_HAS_JAC
    {
        double jv[HY_NNZ > 0 ? HY_NNZ : 1], jx[NXA];
        int e;
        st = hy_jac(c->s.t, c->s.x, c->s.p, c->s.u, jv);
        if (st) return model_status(c, st, "GetDirectionalDerivative");
        memset(jx, 0, sizeof jx);
        for (e = 0; e < HY_NNZ; ++e) jx[HY_JAC_ROW[e]] += jv[e] * vx[HY_JAC_COL[e]];
        for (i = 0; i < HY_NX; ++i) f1[i] = f0[i] + eps * jx[i] + (f1[i] - f0[i]);
    }
#endif
    for (k = 0; k < nU; ++k) {
        const unsigned int r = vU[k];
        if (r >= VR_DX && r < VR_P) dvU[k] = (f1[r - VR_DX] - f0[r - VR_DX]) / eps;
        else if (r >= VR_Y && r < VR_END) dvU[k] = (y1[r - VR_Y] - y0[r - VR_Y]) / eps;
        else {
            logf_(c, ST_ERROR, "logStatusError",
                  "GetDirectionalDerivative: unknown %u is not a derivative or an output", (unsigned)r);
            return ST_ERROR;
        }
    }
    return ST_OK;
}

static int do_step(Inst *c, double t, double h)
{
    double t_in[2], U[2 * NUA], atol[NXA], X[NXA], Y[NYA], stats[16], tout = t + h;
    int hold[NUA], i, n_tin = 1, st;
    if (!allowed(c, "DoStep", M_STEP)) return ST_ERROR;
    if (h < 0.0) {
        logf_(c, ST_ERROR, "logStatusError", "DoStep: negative step size %g", h);
        return ST_ERROR;
    }
    if (fabs(t - c->s.t) > 1e-9 * (1.0 + fabs(t)))
        logf_(c, ST_WARNING, "logStatusWarning", "DoStep: communication point %g differs from the FMU time %g",
              t, c->s.t);
    t_in[0] = t; t_in[1] = tout;
    for (i = 0; i < HY_NU; ++i) {
        U[i] = c->s.u[i];
        U[HY_NU + i] = c->s.have_du ? c->s.u[i] + h * c->s.du[i] : c->s.u[i];
        hold[i] = 0;
    }
    if (!(h > 0.0)) { c->s.t = t; return ST_OK; }
    n_tin = (HY_NU > 0) ? 2 : 0;
    for (i = 0; i < HY_NX; ++i) atol[i] = HY_FMU_ATOL_FACTOR * c->s.rtol * HY_FMU_NOMINAL[i];
    st = hy_simulate(c->s.p, n_tin, t_in, U, hold, t, c->s.x, 1, &tout, c->s.rtol, atol,
                     c->s.h_last, HUGE_VAL, HY_FMU_MAX_STEPS, X, Y, stats);
    if (st != 0) {
        c->s.t = stats[5];
        c->s.mode = M_ERROR;
        if (st >= 100) return model_status(c, st - 100, "DoStep");
        logf_(c, ST_ERROR, "logStatusError", "DoStep from t = %g s: %s (integrator status %d)",
              t, integrator_message(st), st);
        return ST_ERROR;
    }
    memcpy(c->s.x, X, sizeof(double) * HY_NX);
    for (i = 0; i < HY_NU; ++i) c->s.u[i] = U[HY_NU + i];
    c->s.t = tout;
    if (stats[7] > 0.0) c->s.h_last = stats[7];
    return ST_OK;
}

/* ---- FMU state: a copy of State (plain data, so serialisation is a memcpy) ---- */

static int state_get(Inst *c, void **out)
{
    State *s;
    if (!c || !out) return ST_ERROR;
    s = (State *)(*out ? *out : malloc(sizeof(State)));
    if (!s) return ST_ERROR;
    *s = c->s;
    *out = s;
    return ST_OK;
}

static int state_set(Inst *c, const void *in)
{
    if (!c || !in) return ST_ERROR;
    c->s = *(const State *)in;
    return ST_OK;
}

static int state_free(void **st)
{
    if (st) { free(*st); *st = NULL; }
    return ST_OK;
}

static int state_serialize(const void *st, unsigned char *data, size_t size)
{
    if (!st || size < sizeof(State)) return ST_ERROR;
    memcpy(data, st, sizeof(State));
    return ST_OK;
}

static int state_deserialize(Inst *c, const unsigned char *data, size_t size, void **st)
{
    if (size != sizeof(State)) {
        logf_(c, ST_ERROR, "logStatusError", "DeserializeFMUState: %zu bytes, expected %zu", size, sizeof(State));
        return ST_ERROR;
    }
    if (!*st) *st = malloc(sizeof(State));
    if (!*st) return ST_ERROR;
    memcpy(*st, data, sizeof(State));
    return ST_OK;
}
