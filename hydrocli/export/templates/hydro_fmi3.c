/*
 * hydro_fmi3.c -- FMI 3.0 co-simulation interface of a hydrocli model.
 * Build: cc -O2 -fPIC -shared -I. hydro_fmi3.c -o <modelIdentifier>.so -lm
 * The model, the integrator and the instance logic are in hydro_fmu_core.c; value
 * reference VR_END is the independent variable (time). Model exchange, scheduled execution,
 * event mode, clocks and directional derivatives are not provided (stubs at the end).
 * Licence: Apache-2.0 (hydrocli); the FMI headers are BSD-2-Clause (FMI_HEADERS_LICENSE.txt).
 */
#include "hydro_fmu_core.c"
#include "fmi3Functions.h"

#define C_ ((Inst *)instance)
#define VR_TIME (VR_END)

static void emit3(Inst *c, int status, const char *cat, const char *msg)
{
    fmi3LogMessageCallback logger = (fmi3LogMessageCallback)c->logger;
    if (logger) logger((fmi3InstanceEnvironment)c->env, (fmi3Status)status, cat, msg);
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    (void)nCategories; (void)categories;
    if (!instance) return fmi3Error;
    C_->log_on = loggingOn ? 1 : 0;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)resourcePath; (void)visible; (void)eventModeUsed; (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables; (void)nRequiredIntermediateVariables; (void)intermediateUpdate;
    if (!instantiationToken || strcmp(instantiationToken, HY_FMU_GUID) != 0) {
        if (logMessage)
            logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                       "fmi3InstantiateCoSimulation: wrong instantiationToken");
        return NULL;
    }
    return new_instance(instanceName, 1, loggingOn ? 1 : 0, emit3, instanceEnvironment, (void *)logMessage);
}

void fmi3FreeInstance(fmi3Instance instance) { free(instance); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)stopTimeDefined; (void)stopTime;
    if (!allowed(C_, "fmi3EnterInitializationMode", M_INSTANTIATED)) return fmi3Error;
    if (toleranceDefined && tolerance > 0) C_->s.rtol = tolerance;
    C_->s.t = startTime;
    C_->s.mode = M_INIT;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    if (!allowed(C_, "fmi3ExitInitializationMode", M_INIT)) return fmi3Error;
    if (check_initial_state(C_)) return fmi3Error;
    C_->s.mode = M_STEP;
    return fmi3OK;
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    return allowed(C_, "fmi3EnterStepMode", M_STEP) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    if (!allowed(C_, "fmi3Terminate", M_STEP | M_ERROR)) return fmi3Error;
    C_->s.mode = M_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    if (!instance) return fmi3Error;
    reset_state(C_);
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    size_t k;
    if (nValues != nValueReferences) return fmi3Error;       /* no arrays */
    for (k = 0; k < nValueReferences; ++k)
        if (valueReferences[k] == VR_TIME) break;
    if (k == nValueReferences) return (fmi3Status)get_real(C_, valueReferences, nValueReferences, values);
    for (k = 0; k < nValueReferences; ++k) {                 /* time among them: one by one */
        if (valueReferences[k] == VR_TIME) values[k] = C_->s.t;
        else if (get_real(C_, valueReferences + k, 1, values + k)) return fmi3Error;
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    if (nValues != nValueReferences) return fmi3Error;
    return (fmi3Status)set_real(C_, valueReferences, nValueReferences, values);
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    return (fmi3Status)state_get(C_, FMUState);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    return (fmi3Status)state_set(C_, FMUState);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    (void)instance;
    return (fmi3Status)state_free(FMUState);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    (void)instance; (void)FMUState;
    *size = sizeof(State);
    return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size)
{
    (void)instance;
    return (fmi3Status)state_serialize(FMUState, (unsigned char *)serializedState, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    return (fmi3Status)state_deserialize(C_, (const unsigned char *)serializedState, size, FMUState);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    (void)instance;
    *nContinuousStates = (size_t)HY_NX;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    (void)instance;
    *nEventIndicators = 0;
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    int st;
    (void)noSetFMUStatePriorToCurrentPoint;
    st = do_step(C_, currentCommunicationPoint, communicationStepSize);
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    *lastSuccessfulTime = C_->s.t;
    return (fmi3Status)st;
}

/* ------------------------------------------- not provided by this FMU (generated stubs) */

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage)
{
    return NULL;  /* not supported: co-simulation only */
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate, fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption)
{
    return NULL;  /* not supported: co-simulation only */
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3EnterEventMode: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetFloat32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int8 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetInt8: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt8 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetUInt8: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int16 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetInt16: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt16 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetUInt16: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetInt32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetUInt32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int64 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetInt64: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetUInt64: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetBoolean: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3String values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetString: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetBinary: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Clock values[])
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetClock: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetFloat32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int8 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetInt8: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt8 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetUInt8: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int16 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetInt16: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt16 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetUInt16: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetInt32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt32 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetUInt32: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int64 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetInt64: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetUInt64: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetBoolean: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3String values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetString: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetBinary: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Clock values[])
{
    if (nValueReferences == 0) return fmi3OK;
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetClock: the model has no variables of this type");
    return fmi3Error;
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference, size_t* nDependencies)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetNumberOfVariableDependencies: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent, size_t elementIndicesOfDependent[], fmi3ValueReference independents[], size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetVariableDependencies: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetDirectionalDerivative: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetAdjointDerivative: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3EnterConfigurationMode: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3ExitConfigurationMode: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetIntervalDecimal: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetIntervalFraction: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 shifts[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetShiftDecimal: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetShiftFraction: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 intervals[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetIntervalDecimal: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetIntervalFraction: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 shifts[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetShiftDecimal: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetShiftFraction: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3EvaluateDiscreteStates: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate, fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged, fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3UpdateDiscreteStates: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3EnterContinuousTimeMode: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3CompletedIntegratorStep: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetTime: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3SetContinuousStates: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nContinuousStates)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetContinuousStateDerivatives: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetEventIndicators: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetContinuousStates: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetNominalsOfContinuousStates: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3GetOutputDerivatives: not supported by this co-simulation FMU");
    return fmi3Error;
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference, fmi3Float64 activationTime)
{
    logf_((Inst *)instance, ST_ERROR, "logStatusError", "fmi3ActivateModelPartition: not supported by this co-simulation FMU");
    return fmi3Error;
}
