/*
 * hydro_fmi2.c -- FMI 2.0 model exchange and co-simulation glue for a hydrocli model.
 *
 * One translation unit: the generated model (model.c: HY_NX..., hy_rhs, hy_out, hy_jac),
 * the hydrocli Rosenbrock integrator (hy_integrator.c: hy_simulate) and the export's
 * configuration (hy_fmu_config.h: GUID, start values, nominals, guard messages).
 * Build: cc -O2 -fPIC -shared -I. hydro_fmi2.c -o <modelIdentifier>.so -lm
 *
 * Value references (see hydrocli/export/variables.py): states [0, NX), derivatives
 * [NX, 2NX), parameters, inputs, outputs -- the generated code's array order.
 * Co-simulation: fmi2DoStep integrates [t, t+h] with hy_simulate (variable step, error
 * control, the analytic Jacobian); inputs are held over the step, or ramped when the master
 * gave their first derivatives (canInterpolateInputs). Model exchange: derivatives from
 * hy_rhs; directional derivatives from the analytic Jacobian hy_jac for d(der)/d(states)
 * and a directional difference quotient for the input and output parts.
 * Licence: Apache-2.0 (hydrocli); the FMI headers are BSD-2-Clause (fmi/LICENSE.txt).
 */
#include "model.c"
#include "hy_integrator.c"
#include "hy_fmu_config.h"

#include <stdio.h>
#include <stdarg.h>
#include "fmi2Functions.h"

#define NXA (HY_NX > 0 ? HY_NX : 1)
#define NPA (HY_NP > 0 ? HY_NP : 1)
#define NUA (HY_NU > 0 ? HY_NU : 1)
#define NYA (HY_NY > 0 ? HY_NY : 1)
#define VR_DX (HY_NX)
#define VR_P (2 * HY_NX)
#define VR_U (VR_P + HY_NP)
#define VR_Y (VR_U + HY_NU)
#define VR_END (VR_Y + HY_NY)

typedef enum { M_INSTANTIATED = 1, M_INIT = 2, M_EVENT = 4, M_CONT = 8, M_STEP = 16,
               M_TERMINATED = 32, M_ERROR = 64 } Mode;
#define M_ANY (M_INSTANTIATED | M_INIT | M_EVENT | M_CONT | M_STEP | M_TERMINATED)

typedef struct {             /* everything fmi2GetFMUstate copies */
    Mode mode;
    double t, rtol, h_last;
    double x[NXA], p[NPA], u[NUA], du[NUA];
    int have_du;
} State;

typedef struct {
    fmi2CallbackFunctions cb;
    char name[128];
    int is_cs, log_on;
    State s;
} Inst;

static void logf_(Inst *c, fmi2Status st, const char *cat, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    if (!c || !c->cb.logger) return;
    if (st == fmi2OK && !c->log_on) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    c->cb.logger(c->cb.componentEnvironment, c->name, st, cat, "%s", buf);
}

static int allowed(Inst *c, const char *fn, int modes)
{
    if (!c) return 0;
    if (c->s.mode & modes) return 1;
    logf_(c, fmi2Error, "logStatusError", "%s: not allowed in the current state (%d)", fn, (int)c->s.mode);
    c->s.mode = M_ERROR;
    return 0;
}

static fmi2Status model_status(Inst *c, int st, const char *what)
{
    if (st == 0) return fmi2OK;
    if (st > 0 && st <= HY_FMU_NGUARD)
        logf_(c, fmi2Error, "logStatusError", "%s at t = %g s: %s", what, c->s.t, HY_FMU_GUARDS[st - 1]);
    else
        logf_(c, fmi2Error, "logStatusError", "%s at t = %g s: model status %d", what, c->s.t, st);
    return fmi2Error;
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

/* ------------------------------------------------------------ common */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean on, size_t n, const fmi2String cats[])
{
    Inst *c = (Inst *)comp;
    (void)n; (void)cats;
    if (!c) return fmi2Error;
    c->log_on = on ? 1 : 0;
    return fmi2OK;
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

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String location,
                              const fmi2CallbackFunctions *cb, fmi2Boolean visible, fmi2Boolean logging)
{
    Inst *c;
    (void)location; (void)visible;
    if (!cb || !cb->logger) return NULL;
    if (!guid || strcmp(guid, HY_FMU_GUID) != 0) {
        cb->logger(cb->componentEnvironment, name, fmi2Error, "logStatusError",
                   "fmi2Instantiate: wrong GUID %s (expected %s)", guid ? guid : "(null)", HY_FMU_GUID);
        return NULL;
    }
    c = (Inst *)calloc(1, sizeof(Inst));
    if (!c) return NULL;
    c->cb = *cb;
    snprintf(c->name, sizeof c->name, "%s", name ? name : "hydrocli");
    c->is_cs = (type == fmi2CoSimulation);
    c->log_on = logging ? 1 : 0;
    reset_state(c);
    return c;
}

void fmi2FreeInstance(fmi2Component comp) { free(comp); }

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean tolDefined, fmi2Real tol,
                               fmi2Real tStart, fmi2Boolean stopDefined, fmi2Real tStop)
{
    Inst *c = (Inst *)comp;
    (void)stopDefined; (void)tStop;
    if (!allowed(c, "fmi2SetupExperiment", M_INSTANTIATED)) return fmi2Error;
    if (tolDefined && tol > 0) c->s.rtol = tol;
    c->s.t = tStart;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2EnterInitializationMode", M_INSTANTIATED)) return fmi2Error;
    c->s.mode = M_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    double dx[NXA];
    int st;
    if (!allowed(c, "fmi2ExitInitializationMode", M_INIT)) return fmi2Error;
    st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, dx);
    if (st) { c->s.mode = M_ERROR; return model_status(c, st, "initial state"); }
    c->s.mode = c->is_cs ? M_STEP : M_EVENT;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2Terminate", M_EVENT | M_CONT | M_STEP | M_ERROR)) return fmi2Error;
    c->s.mode = M_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    if (!c) return fmi2Error;
    reset_state(c);
    return fmi2OK;
}

/* -------------------------------------------------------- get / set */

fmi2Status fmi2GetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, fmi2Real value[])
{
    Inst *c = (Inst *)comp;
    double dx[NXA], y[NYA];
    int have_dx = 0, have_y = 0, st;
    size_t k;
    if (!allowed(c, "fmi2GetReal", M_ANY)) return fmi2Error;
    for (k = 0; k < n; ++k) {
        const fmi2ValueReference r = vr[k];
        if (r < VR_DX) value[k] = c->s.x[r];
        else if (r < VR_P) {
            if (!have_dx) {
                st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, dx);
                if (st) return model_status(c, st, "fmi2GetReal (derivatives)");
                have_dx = 1;
            }
            value[k] = dx[r - VR_DX];
        } else if (r < VR_U) value[k] = c->s.p[r - VR_P];
        else if (r < VR_Y) value[k] = c->s.u[r - VR_U];
        else if (r < VR_END) {
            if (!have_y) {
                st = hy_out(c->s.t, c->s.x, c->s.p, c->s.u, y);
                if (st) return model_status(c, st, "fmi2GetReal (outputs)");
                have_y = 1;
            }
            value[k] = y[r - VR_Y];
        } else {
            logf_(c, fmi2Error, "logStatusError", "fmi2GetReal: unknown value reference %u", (unsigned)r);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, const fmi2Real value[])
{
    Inst *c = (Inst *)comp;
    size_t k;
    if (!allowed(c, "fmi2SetReal", M_INSTANTIATED | M_INIT | M_EVENT | M_CONT | M_STEP)) return fmi2Error;
    for (k = 0; k < n; ++k) {
        const fmi2ValueReference r = vr[k];
        if (r < VR_DX && (c->s.mode & (M_INSTANTIATED | M_INIT))) c->s.x[r] = value[k];
        else if (r >= VR_P && r < VR_U) c->s.p[r - VR_P] = value[k];
        else if (r >= VR_U && r < VR_Y) { c->s.u[r - VR_U] = value[k]; c->s.have_du = 0; }
        else {
            logf_(c, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u cannot be set now",
                  (unsigned)r);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

#define NO_VARS(fn, T, cnst) \
fmi2Status fn(fmi2Component comp, const fmi2ValueReference vr[], size_t n, cnst T value[]) \
{ \
    (void)vr; (void)value; \
    if (n == 0) return fmi2OK; \
    logf_((Inst *)comp, fmi2Error, "logStatusError", #fn ": the model has no variables of this type"); \
    return fmi2Error; \
}
NO_VARS(fmi2GetInteger, fmi2Integer, )
NO_VARS(fmi2GetBoolean, fmi2Boolean, )
NO_VARS(fmi2GetString, fmi2String, )
NO_VARS(fmi2SetInteger, fmi2Integer, const)
NO_VARS(fmi2SetBoolean, fmi2Boolean, const)
NO_VARS(fmi2SetString, fmi2String, const)

/* --------------------------------------------------------- FMU state */

fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *out)
{
    Inst *c = (Inst *)comp;
    State *s;
    if (!c || !out) return fmi2Error;
    s = (State *)(*out ? *out : malloc(sizeof(State)));
    if (!s) return fmi2Error;
    *s = c->s;
    *out = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate in)
{
    Inst *c = (Inst *)comp;
    if (!c || !in) return fmi2Error;
    c->s = *(State *)in;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *st)
{
    (void)comp;
    if (st) { free(*st); *st = NULL; }
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate st, size_t *size)
{
    (void)comp; (void)st;
    *size = sizeof(State);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate st, fmi2Byte data[], size_t size)
{
    (void)comp;
    if (!st || size < sizeof(State)) return fmi2Error;
    memcpy(data, st, sizeof(State));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte data[], size_t size, fmi2FMUstate *st)
{
    if (size != sizeof(State)) {
        logf_((Inst *)comp, fmi2Error, "logStatusError", "fmi2DeSerializeFMUstate: wrong size");
        return fmi2Error;
    }
    if (!*st) *st = malloc(sizeof(State));
    if (!*st) return fmi2Error;
    memcpy(*st, data, sizeof(State));
    return fmi2OK;
}

/* ----------------------------------------------- directional derivatives */

/* d(unknowns) = d(unknowns)/d(knowns) * dvKnown; knowns are states and inputs, unknowns are
   derivatives and outputs.  der/states: analytic Jacobian (hy_jac) when the model has one;
   everything else: one directional difference quotient. */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference vU[], size_t nU,
                                        const fmi2ValueReference vK[], size_t nK,
                                        const fmi2Real dvK[], fmi2Real dvU[])
{
    Inst *c = (Inst *)comp;
    double vx[NXA], vu[NUA], x1[NXA], u1[NUA], f0[NXA], f1[NXA], y0[NYA], y1[NYA];
    double eps;
    int i, st, fd_x;
    size_t k;
    if (!allowed(c, "fmi2GetDirectionalDerivative", M_INIT | M_EVENT | M_CONT | M_STEP)) return fmi2Error;
    memset(vx, 0, sizeof vx); memset(vu, 0, sizeof vu);
    for (k = 0; k < nK; ++k) {
        const fmi2ValueReference r = vK[k];
        if (r < VR_DX) vx[r] = dvK[k];
        else if (r >= VR_U && r < VR_Y) vu[r - VR_U] = dvK[k];
        else {
            logf_(c, fmi2Error, "logStatusError",
                  "fmi2GetDirectionalDerivative: known %u is not a state or an input", (unsigned)r);
            return fmi2Error;
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
    if (eps == 0.0) return fmi2OK;

    st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, f0);
    if (!st) st = hy_out(c->s.t, c->s.x, c->s.p, c->s.u, y0);
    if (!st) st = hy_rhs(c->s.t, fd_x ? x1 : c->s.x, c->s.p, u1, f1);  /* input part (and states without hy_jac) */
    if (!st) st = hy_out(c->s.t, x1, c->s.p, u1, y1);
    if (st) return model_status(c, st, "fmi2GetDirectionalDerivative");
#ifdef HY_HAS_JAC
    {
        double jv[HY_NNZ > 0 ? HY_NNZ : 1], jx[NXA];
        int e;
        st = hy_jac(c->s.t, c->s.x, c->s.p, c->s.u, jv);
        if (st) return model_status(c, st, "fmi2GetDirectionalDerivative");
        memset(jx, 0, sizeof jx);
        for (e = 0; e < HY_NNZ; ++e) jx[HY_JAC_ROW[e]] += jv[e] * vx[HY_JAC_COL[e]];
        for (i = 0; i < HY_NX; ++i) f1[i] = f0[i] + eps * jx[i] + (f1[i] - f0[i]);
    }
#endif
    for (k = 0; k < nU; ++k) {
        const fmi2ValueReference r = vU[k];
        if (r >= VR_DX && r < VR_P) dvU[k] = (f1[r - VR_DX] - f0[r - VR_DX]) / eps;
        else if (r >= VR_Y && r < VR_END) dvU[k] = (y1[r - VR_Y] - y0[r - VR_Y]) / eps;
        else {
            logf_(c, fmi2Error, "logStatusError",
                  "fmi2GetDirectionalDerivative: unknown %u is not a derivative or an output", (unsigned)r);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

/* ----------------------------------------------------- model exchange */

fmi2Status fmi2EnterEventMode(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2EnterEventMode", M_EVENT | M_CONT)) return fmi2Error;
    c->s.mode = M_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *info)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2NewDiscreteStates", M_EVENT)) return fmi2Error;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component comp)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2EnterContinuousTimeMode", M_EVENT)) return fmi2Error;
    c->s.mode = M_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean noSetPrior,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminate)
{
    Inst *c = (Inst *)comp;
    (void)noSetPrior;
    if (!allowed(c, "fmi2CompletedIntegratorStep", M_CONT)) return fmi2Error;
    *enterEventMode = fmi2False;
    *terminate = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real t)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2SetTime", M_INSTANTIATED | M_INIT | M_EVENT | M_CONT)) return fmi2Error;
    c->s.t = t;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t nx)
{
    Inst *c = (Inst *)comp;
    size_t i;
    if (!allowed(c, "fmi2SetContinuousStates", M_EVENT | M_CONT)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    for (i = 0; i < nx; ++i) c->s.x[i] = x[i];
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real dx[], size_t nx)
{
    Inst *c = (Inst *)comp;
    double tmp[NXA];
    int st;
    if (!allowed(c, "fmi2GetDerivatives", M_INIT | M_EVENT | M_CONT | M_TERMINATED)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    st = hy_rhs(c->s.t, c->s.x, c->s.p, c->s.u, tmp);
    if (st) return model_status(c, st, "fmi2GetDerivatives");
    memcpy(dx, tmp, sizeof(double) * nx);
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component comp, fmi2Real ind[], size_t ni)
{
    (void)ind;
    return (comp && ni == 0) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component comp, fmi2Real x[], size_t nx)
{
    Inst *c = (Inst *)comp;
    if (!allowed(c, "fmi2GetContinuousStates", M_ANY)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    memcpy(x, c->s.x, sizeof(double) * nx);
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component comp, fmi2Real nom[], size_t nx)
{
    size_t i;
    if (!comp || nx != (size_t)HY_NX) return fmi2Error;
    for (i = 0; i < nx; ++i) nom[i] = HY_FMU_NOMINAL[i];
    return fmi2OK;
}

/* ------------------------------------------------------- co-simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    Inst *c = (Inst *)comp;
    size_t k;
    if (!allowed(c, "fmi2SetRealInputDerivatives", M_INIT | M_STEP)) return fmi2Error;
    for (k = 0; k < n; ++k) {
        if (vr[k] < VR_U || vr[k] >= VR_Y || order[k] != 1) {
            logf_(c, fmi2Error, "logStatusError",
                  "fmi2SetRealInputDerivatives: only first derivatives of inputs (vr %u)", (unsigned)vr[k]);
            return fmi2Error;
        }
    }
    for (k = 0; k < n; ++k) c->s.du[vr[k] - VR_U] = value[k];
    c->s.have_du = 1;
    return fmi2OK;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr; (void)order; (void)value;
    if (n == 0) return fmi2OK;
    logf_((Inst *)comp, fmi2Error, "logStatusError", "fmi2GetRealOutputDerivatives: not provided");
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior)
{
    Inst *c = (Inst *)comp;
    double t_in[2], U[2 * NUA], atol[NXA], X[NXA], Y[NYA], stats[16], tout = t + h;
    int hold[NUA], i, n_tin = 1, st;
    (void)noSetPrior;
    if (!allowed(c, "fmi2DoStep", M_STEP)) return fmi2Error;
    if (h < 0.0) {
        logf_(c, fmi2Error, "logStatusError", "fmi2DoStep: negative step size %g", h);
        return fmi2Error;
    }
    if (fabs(t - c->s.t) > 1e-9 * (1.0 + fabs(t)))
        logf_(c, fmi2Warning, "logStatusWarning", "fmi2DoStep: communication point %g differs from the FMU time %g",
              t, c->s.t);
    t_in[0] = t; t_in[1] = tout;
    for (i = 0; i < HY_NU; ++i) {
        U[i] = c->s.u[i];
        U[HY_NU + i] = c->s.have_du ? c->s.u[i] + h * c->s.du[i] : c->s.u[i];
        hold[i] = 0;
    }
    if (!(h > 0.0)) { c->s.t = t; return fmi2OK; }
    n_tin = (HY_NU > 0) ? 2 : 0;
    for (i = 0; i < HY_NX; ++i) atol[i] = HY_FMU_ATOL_FACTOR * c->s.rtol * HY_FMU_NOMINAL[i];
    st = hy_simulate(c->s.p, n_tin, t_in, U, hold, t, c->s.x, 1, &tout, c->s.rtol, atol,
                     c->s.h_last, HUGE_VAL, HY_FMU_MAX_STEPS, X, Y, stats);
    if (st != 0) {
        c->s.t = stats[5];
        c->s.mode = M_ERROR;
        if (st >= 100) return model_status(c, st - 100, "fmi2DoStep");
        logf_(c, fmi2Error, "logStatusError", "fmi2DoStep from t = %g s: %s (integrator status %d)",
              t, integrator_message(st), st);
        return fmi2Error;
    }
    memcpy(c->s.x, X, sizeof(double) * HY_NX);
    for (i = 0; i < HY_NU; ++i) c->s.u[i] = U[HY_NU + i];
    c->s.t = tout;
    if (stats[7] > 0.0) c->s.h_last = stats[7];
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component comp) { (void)comp; return fmi2Error; }

fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value)
{
    (void)comp; (void)s; *value = fmi2OK; return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value)
{
    Inst *c = (Inst *)comp;
    if (c && s == fmi2LastSuccessfulTime) { *value = c->s.t; return fmi2OK; }
    return fmi2Discard;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)comp; (void)s; (void)value; return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)comp; (void)s; *value = fmi2False; return fmi2Discard;
}

fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value)
{
    (void)comp; (void)s; (void)value; return fmi2Discard;
}
