"""C text of the FMI 3.0 function layer, ``fmi3Functions.c`` (private; see :mod:`._c_core`)."""

from __future__ import annotations

__all__ = ["FMI3_LAYER"]

FMI3_LAYER = r"""/* fmi3Functions.c -- FMI 3.0 layer of a bondgraph FMU (Model Exchange and Co-Simulation);
 * do not edit.  Compile with the generated model source, for example
 *     cc -std=c99 -shared -fPIC -fvisibility=hidden -I. fmi3Functions.c MODEL.c -lm
 * Define FMI3_FUNCTION_PREFIX (MODELIDENTIFIER_) to link it statically. */
#include "fmi3Functions.h"
#include "bg_fmu_core.h"

#define C_ ((bg_instance *)instance)
#define STATUS(s) ((s) == BG_OK ? fmi3OK : fmi3Error)
#define VRS const fmi3ValueReference valueReferences[], size_t nValueReferences

static void bg3_log(bg_instance *c, int error, const char *message)
{
    fmi3LogMessageCallback log = (fmi3LogMessageCallback)c->log_message;
    if (!log || (!error && !c->logging)) return;
    log(c->env, error ? fmi3Error : fmi3OK, error ? "logStatusError" : "logAll", message);
}

#define NONE(n, type) STATUS(bg_none(C_, n, type))
#define UNSUPPORTED(what) STATUS(bg_unsupported(C_, what))

static fmi3Instance bg3_new(fmi3String instanceName, fmi3String token, int cosim, fmi3Boolean loggingOn,
                            fmi3InstanceEnvironment env, fmi3LogMessageCallback logMessage)
{
    bg_instance *c = bg_new(instanceName, cosim);
    if (!c) return NULL;
    c->env = env;
    c->log_message = (void (*)(void))logMessage;
    c->logging = loggingOn ? 1 : 0;
    c->log = bg3_log;
    return bg_admit(c, token, "instantiation token");
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    (void)nCategories; (void)categories;
    C_->logging = loggingOn ? 1 : 0;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)resourcePath; (void)visible;
    return bg3_new(instanceName, instantiationToken, 0, loggingOn, instanceEnvironment, logMessage);
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
    return bg3_new(instanceName, instantiationToken, 1, loggingOn, instanceEnvironment, logMessage);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible,
                                               fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "this FMU does not provide Scheduled Execution");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) { bg_free(C_); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)toleranceDefined; (void)tolerance;
    bg_set_time(C_, startTime);
    bg_set_horizon(C_, stopTimeDefined, startTime, stopTime);
    C_->mode = BG_INIT;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    C_->mode = C_->cosim ? BG_STEPPING : BG_EVENT;
    return STATUS(bg_event_start(C_));
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) { C_->mode = BG_EVENT; return fmi3OK; }
fmi3Status fmi3Terminate(fmi3Instance instance) { C_->mode = BG_TERMINATED; return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance instance) { bg_reset(C_); return fmi3OK; }

fmi3Status fmi3GetFloat64(fmi3Instance instance, VRS, fmi3Float64 values[], size_t nValues)
{
    size_t i;
    if (bg_count(C_, nValues, nValueReferences, "fmi3GetFloat64 (scalar variables)") != BG_OK) return fmi3Error;
    for (i = 0; i < nValueReferences; ++i)
        if (bg_get(C_, valueReferences[i], &values[i]) != BG_OK) return fmi3Error;
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, VRS, const fmi3Float64 values[], size_t nValues)
{
    size_t i;
    if (bg_count(C_, nValues, nValueReferences, "fmi3SetFloat64 (scalar variables)") != BG_OK) return fmi3Error;
    for (i = 0; i < nValueReferences; ++i)
        if (bg_set(C_, valueReferences[i], values[i]) != BG_OK) return fmi3Error;
    return fmi3OK;
}

/* the other types: this FMU has no variables of them */
#define BG3_NONE(NAME, TYPE, CONST) \
    fmi3Status NAME(fmi3Instance instance, VRS, CONST TYPE values[], size_t nValues) \
    { (void)valueReferences; (void)values; (void)nValues; return NONE(nValueReferences, #TYPE); }
BG3_NONE(fmi3GetFloat32, fmi3Float32, )
BG3_NONE(fmi3GetInt8, fmi3Int8, )
BG3_NONE(fmi3GetUInt8, fmi3UInt8, )
BG3_NONE(fmi3GetInt16, fmi3Int16, )
BG3_NONE(fmi3GetUInt16, fmi3UInt16, )
BG3_NONE(fmi3GetInt32, fmi3Int32, )
BG3_NONE(fmi3GetUInt32, fmi3UInt32, )
BG3_NONE(fmi3GetInt64, fmi3Int64, )
BG3_NONE(fmi3GetUInt64, fmi3UInt64, )
BG3_NONE(fmi3GetBoolean, fmi3Boolean, )
BG3_NONE(fmi3GetString, fmi3String, )
BG3_NONE(fmi3SetFloat32, fmi3Float32, const)
BG3_NONE(fmi3SetInt8, fmi3Int8, const)
BG3_NONE(fmi3SetUInt8, fmi3UInt8, const)
BG3_NONE(fmi3SetInt16, fmi3Int16, const)
BG3_NONE(fmi3SetUInt16, fmi3UInt16, const)
BG3_NONE(fmi3SetInt32, fmi3Int32, const)
BG3_NONE(fmi3SetUInt32, fmi3UInt32, const)
BG3_NONE(fmi3SetInt64, fmi3Int64, const)
BG3_NONE(fmi3SetUInt64, fmi3UInt64, const)
BG3_NONE(fmi3SetBoolean, fmi3Boolean, const)
BG3_NONE(fmi3SetString, fmi3String, const)

fmi3Status fmi3GetBinary(fmi3Instance instance, VRS, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{ (void)valueReferences; (void)valueSizes; (void)values; (void)nValues; return NONE(nValueReferences, "Binary"); }
fmi3Status fmi3SetBinary(fmi3Instance instance, VRS, const size_t valueSizes[], const fmi3Binary values[],
                         size_t nValues)
{ (void)valueReferences; (void)valueSizes; (void)values; (void)nValues; return NONE(nValueReferences, "Binary"); }
fmi3Status fmi3GetClock(fmi3Instance instance, VRS, fmi3Clock values[])
{ (void)valueReferences; (void)values; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3SetClock(fmi3Instance instance, VRS, const fmi3Clock values[])
{ (void)valueReferences; (void)values; return NONE(nValueReferences, "Clock"); }

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference; (void)nDependencies;
    return UNSUPPORTED("fmi3GetNumberOfVariableDependencies (see the ModelStructure)");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return UNSUPPORTED("fmi3GetVariableDependencies (see the ModelStructure)");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{ return STATUS(bg_get_state(C_, FMUState)); }
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{ return STATUS(bg_set_state(C_, FMUState)); }
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{ (void)instance; bg_free_state(FMUState); return fmi3OK; }
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{ (void)instance; (void)FMUState; *size = bg_serial_size(); return fmi3OK; }
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size)
{ return STATUS(bg_serialize(C_, FMUState, serializedState, size)); }
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{ return STATUS(bg_deserialize(C_, serializedState, size, FMUState)); }

#define BG3_DERIVATIVE_ARGS const fmi3ValueReference unknowns[], size_t nUnknowns, \
    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, \
    fmi3Float64 sensitivity[], size_t nSensitivity
#define BG3_DERIVATIVE_UNUSED (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; \
    (void)nSeed; (void)sensitivity; (void)nSensitivity
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, BG3_DERIVATIVE_ARGS)
{ BG3_DERIVATIVE_UNUSED; return UNSUPPORTED("fmi3GetDirectionalDerivative"); }
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, BG3_DERIVATIVE_ARGS)
{ BG3_DERIVATIVE_UNUSED; return UNSUPPORTED("fmi3GetAdjointDerivative"); }

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{ return UNSUPPORTED("fmi3EnterConfigurationMode (no structural parameters)"); }
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{ return UNSUPPORTED("fmi3ExitConfigurationMode (no structural parameters)"); }

/* clocks: this FMU has none */
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, VRS, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[])
{ (void)valueReferences; (void)intervals; (void)qualifiers; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, VRS, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{ (void)valueReferences; (void)counters; (void)resolutions; (void)qualifiers; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, VRS, fmi3Float64 shifts[])
{ (void)valueReferences; (void)shifts; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, VRS, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{ (void)valueReferences; (void)counters; (void)resolutions; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, VRS, const fmi3Float64 intervals[])
{ (void)valueReferences; (void)intervals; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, VRS, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{ (void)valueReferences; (void)counters; (void)resolutions; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, VRS, const fmi3Float64 shifts[])
{ (void)valueReferences; (void)shifts; return NONE(nValueReferences, "Clock"); }
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, VRS, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[])
{ (void)valueReferences; (void)counters; (void)resolutions; return NONE(nValueReferences, "Clock"); }

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) { (void)instance; return fmi3OK; }

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime)
{
    int changed = 0, status = bg_event_update(C_, &changed);
    *discreteStatesNeedUpdate = fmi3False;
    *terminateSimulation = fmi3False;
    *nominalsOfContinuousStatesChanged = fmi3False;
    *valuesOfContinuousStatesChanged = changed ? fmi3True : fmi3False;
    *nextEventTimeDefined = fmi3False;
    *nextEventTime = 0.0;
    return STATUS(status);
}

/* Model Exchange */
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) { C_->mode = BG_CONTINUOUS; return fmi3OK; }

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    (void)instance; (void)noSetFMUStatePriorToCurrentPoint;
    *enterEventMode = fmi3False;
    *terminateSimulation = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) { bg_set_time(C_, time); return fmi3OK; }
fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{ return STATUS(bg_set_states(C_, continuousStates, nContinuousStates)); }
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{ return STATUS(bg_get_derivatives(C_, derivatives, nContinuousStates)); }
fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{ return STATUS(bg_event_indicators(C_, eventIndicators, nEventIndicators)); }
fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{ return STATUS(bg_get_states(C_, continuousStates, nContinuousStates)); }
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates)
{ return STATUS(bg_nominals(C_, nominals, nContinuousStates)); }
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{ (void)instance; *nEventIndicators = BG_NZ; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{ (void)instance; *nContinuousStates = BG_NX; return fmi3OK; }

/* Co-Simulation */
fmi3Status fmi3EnterStepMode(fmi3Instance instance) { C_->mode = BG_STEPPING; return fmi3OK; }

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, VRS, const fmi3Int32 orders[],
                                    fmi3Float64 values[], size_t nValues)
{
    (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
    return UNSUPPORTED("fmi3GetOutputDerivatives");
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    int status;
    (void)noSetFMUStatePriorToCurrentPoint;
    status = bg_do_step(C_, currentCommunicationPoint, communicationStepSize);
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    *lastSuccessfulTime = C_->d.time;
    return STATUS(status);
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return UNSUPPORTED("fmi3ActivateModelPartition (no Scheduled Execution)");
}
"""
