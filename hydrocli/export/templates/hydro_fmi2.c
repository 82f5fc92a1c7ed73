/*
 * hydro_fmi2.c -- FMI 2.0 model exchange and co-simulation interface of a hydrocli model.
 * Build: cc -O2 -fPIC -shared -I. hydro_fmi2.c -o <modelIdentifier>.so -lm
 * The model, the integrator and the instance logic are in hydro_fmu_core.c.
 * Licence: Apache-2.0 (hydrocli); the FMI headers are BSD-2-Clause (FMI_HEADERS_LICENSE.txt).
 */
#include "hydro_fmu_core.c"
#include "fmi2Functions.h"

#define C_ ((Inst *)comp)

static void emit2(Inst *c, int status, const char *cat, const char *msg)
{
    fmi2CallbackLogger logger = (fmi2CallbackLogger)c->logger;
    if (logger) logger((fmi2ComponentEnvironment)c->env, c->name, (fmi2Status)status, cat, "%s", msg);
}

/* ------------------------------------------------------------ common */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean on, size_t n, const fmi2String cats[])
{
    (void)n; (void)cats;
    if (!comp) return fmi2Error;
    C_->log_on = on ? 1 : 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String location,
                              const fmi2CallbackFunctions *cb, fmi2Boolean visible, fmi2Boolean logging)
{
    (void)location; (void)visible;
    if (!cb || !cb->logger) return NULL;
    if (!guid || strcmp(guid, HY_FMU_GUID) != 0) {
        cb->logger(cb->componentEnvironment, name, fmi2Error, "logStatusError",
                   "fmi2Instantiate: wrong GUID %s (expected %s)", guid ? guid : "(null)", HY_FMU_GUID);
        return NULL;
    }
    return new_instance(name, type == fmi2CoSimulation, logging ? 1 : 0, emit2,
                        cb->componentEnvironment, (void *)cb->logger);
}

void fmi2FreeInstance(fmi2Component comp) { free(comp); }

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean tolDefined, fmi2Real tol,
                               fmi2Real tStart, fmi2Boolean stopDefined, fmi2Real tStop)
{
    (void)stopDefined; (void)tStop;
    if (!allowed(C_, "fmi2SetupExperiment", M_INSTANTIATED)) return fmi2Error;
    if (tolDefined && tol > 0) C_->s.rtol = tol;
    C_->s.t = tStart;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp)
{
    if (!allowed(C_, "fmi2EnterInitializationMode", M_INSTANTIATED)) return fmi2Error;
    C_->s.mode = M_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp)
{
    if (!allowed(C_, "fmi2ExitInitializationMode", M_INIT)) return fmi2Error;
    if (check_initial_state(C_)) return fmi2Error;
    C_->s.mode = C_->is_cs ? M_STEP : M_EVENT;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp)
{
    if (!allowed(C_, "fmi2Terminate", M_EVENT | M_CONT | M_STEP | M_ERROR)) return fmi2Error;
    C_->s.mode = M_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp)
{
    if (!comp) return fmi2Error;
    reset_state(C_);
    return fmi2OK;
}

/* -------------------------------------------------------- get / set */

fmi2Status fmi2GetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, fmi2Real value[])
{
    return (fmi2Status)get_real(C_, vr, n, value);
}

fmi2Status fmi2SetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t n, const fmi2Real value[])
{
    return (fmi2Status)set_real(C_, vr, n, value);
}

#define NO_VARS(fn, T, cnst) \
fmi2Status fn(fmi2Component comp, const fmi2ValueReference vr[], size_t n, cnst T value[]) \
{ \
    (void)vr; (void)value; \
    if (n == 0) return fmi2OK; \
    logf_(C_, ST_ERROR, "logStatusError", #fn ": the model has no variables of this type"); \
    return fmi2Error; \
}
NO_VARS(fmi2GetInteger, fmi2Integer, )
NO_VARS(fmi2GetBoolean, fmi2Boolean, )
NO_VARS(fmi2GetString, fmi2String, )
NO_VARS(fmi2SetInteger, fmi2Integer, const)
NO_VARS(fmi2SetBoolean, fmi2Boolean, const)
NO_VARS(fmi2SetString, fmi2String, const)

/* --------------------------------------------------------- FMU state */

fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *out) { return (fmi2Status)state_get(C_, out); }
fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate in) { return (fmi2Status)state_set(C_, in); }
fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *st) { (void)comp; return (fmi2Status)state_free(st); }

fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate st, size_t *size)
{
    (void)comp; (void)st;
    *size = sizeof(State);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate st, fmi2Byte data[], size_t size)
{
    (void)comp;
    return (fmi2Status)state_serialize(st, (unsigned char *)data, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte data[], size_t size, fmi2FMUstate *st)
{
    return (fmi2Status)state_deserialize(C_, (const unsigned char *)data, size, st);
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference vU[], size_t nU,
                                        const fmi2ValueReference vK[], size_t nK,
                                        const fmi2Real dvK[], fmi2Real dvU[])
{
    return (fmi2Status)directional_derivative(C_, vU, nU, vK, nK, dvK, dvU);
}

/* ----------------------------------------------------- model exchange */

fmi2Status fmi2EnterEventMode(fmi2Component comp)
{
    if (!allowed(C_, "fmi2EnterEventMode", M_EVENT | M_CONT)) return fmi2Error;
    C_->s.mode = M_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *info)
{
    if (!allowed(C_, "fmi2NewDiscreteStates", M_EVENT)) return fmi2Error;
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
    if (!allowed(C_, "fmi2EnterContinuousTimeMode", M_EVENT)) return fmi2Error;
    C_->s.mode = M_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean noSetPrior,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminate)
{
    (void)noSetPrior;
    if (!allowed(C_, "fmi2CompletedIntegratorStep", M_CONT)) return fmi2Error;
    *enterEventMode = fmi2False;
    *terminate = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real t)
{
    if (!allowed(C_, "fmi2SetTime", M_INSTANTIATED | M_INIT | M_EVENT | M_CONT)) return fmi2Error;
    C_->s.t = t;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t nx)
{
    if (!allowed(C_, "fmi2SetContinuousStates", M_EVENT | M_CONT)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    memcpy(C_->s.x, x, sizeof(double) * nx);
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real dx[], size_t nx)
{
    double tmp[NXA];
    int st;
    if (!allowed(C_, "fmi2GetDerivatives", M_INIT | M_EVENT | M_CONT | M_TERMINATED)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    st = hy_rhs(C_->s.t, C_->s.x, C_->s.p, C_->s.u, tmp);
    if (st) return (fmi2Status)model_status(C_, st, "fmi2GetDerivatives");
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
    if (!allowed(C_, "fmi2GetContinuousStates", M_ANY)) return fmi2Error;
    if (nx != (size_t)HY_NX) return fmi2Error;
    memcpy(x, C_->s.x, sizeof(double) * nx);
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
    size_t k;
    if (!allowed(C_, "fmi2SetRealInputDerivatives", M_INIT | M_STEP)) return fmi2Error;
    for (k = 0; k < n; ++k) {
        if (vr[k] < VR_U || vr[k] >= VR_Y || order[k] != 1) {
            logf_(C_, ST_ERROR, "logStatusError",
                  "fmi2SetRealInputDerivatives: only first derivatives of inputs (vr %u)", (unsigned)vr[k]);
            return fmi2Error;
        }
    }
    for (k = 0; k < n; ++k) C_->s.du[vr[k] - VR_U] = value[k];
    C_->s.have_du = 1;
    return fmi2OK;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr; (void)order; (void)value;
    if (n == 0) return fmi2OK;
    logf_(C_, ST_ERROR, "logStatusError", "fmi2GetRealOutputDerivatives: not provided");
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior)
{
    (void)noSetPrior;
    return (fmi2Status)do_step(C_, t, h);
}

fmi2Status fmi2CancelStep(fmi2Component comp) { (void)comp; return fmi2Error; }

fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value)
{
    (void)comp; (void)s; *value = fmi2OK; return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value)
{
    if (comp && s == fmi2LastSuccessfulTime) { *value = C_->s.t; return fmi2OK; }
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
