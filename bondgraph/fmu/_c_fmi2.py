"""C text of the FMI 2.0 function layer, ``fmi2Functions.c`` (private; see :mod:`._c_core`)."""

from __future__ import annotations

__all__ = ["FMI2_LAYER"]

FMI2_LAYER = r"""/* fmi2Functions.c -- FMI 2.0 layer of a bondgraph FMU (Model Exchange and Co-Simulation);
 * do not edit.  Compile with the generated model source, for example
 *     cc -std=c99 -shared -fPIC -fvisibility=hidden -I. fmi2Functions.c MODEL.c -lm
 * Define FMI2_FUNCTION_PREFIX (MODELIDENTIFIER_) to link it statically. */
#include "fmi2Functions.h"
#include "bg_fmu_core.h"

#define C_ ((bg_instance *)c)
#define STATUS(s) ((s) == BG_OK ? fmi2OK : fmi2Error)

static void bg2_log(bg_instance *c, int error, const char *message)
{
    const fmi2CallbackFunctions *f = (const fmi2CallbackFunctions *)c->callbacks;
    char safe[4096];
    size_t i, k = 0;
    if (!f || !f->logger || (!error && !c->logging)) return;
    /* the message is the logger's format: a '%' (from a model's name) is doubled */
    for (i = 0; message[i] != '\0' && k + 2 < sizeof safe; ++i) {
        if (message[i] == '%') safe[k++] = '%';
        safe[k++] = message[i];
    }
    safe[k] = '\0';
    f->logger(f->componentEnvironment, c->name, error ? fmi2Error : fmi2OK,
              error ? "logStatusError" : "logAll", safe);
}

#define NONE(n, type) STATUS(bg_none(C_, n, type))
#define UNSUPPORTED(what) STATUS(bg_unsupported(C_, what))

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    (void)nCategories; (void)categories;
    C_->logging = loggingOn ? 1 : 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    bg_instance *c;
    int cosim = fmuType == fmi2CoSimulation;
    (void)fmuResourceLocation; (void)visible;
    c = bg_new(instanceName, cosim);
    if (!c) return NULL;
    c->callbacks = functions;
    c->logging = loggingOn ? 1 : 0;
    c->log = bg2_log;
    return bg_admit(c, fmuGUID, "GUID");
}

void fmi2FreeInstance(fmi2Component c) { bg_free(C_); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined; (void)tolerance;
    bg_set_time(C_, startTime);
    bg_set_horizon(C_, stopTimeDefined, startTime, stopTime);
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { C_->mode = BG_INIT; return fmi2OK; }

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    C_->mode = C_->cosim ? BG_STEPPING : BG_EVENT;
    return STATUS(bg_event_start(C_));
}

fmi2Status fmi2Terminate(fmi2Component c) { C_->mode = BG_TERMINATED; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { bg_reset(C_); return fmi2OK; }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    size_t i;
    for (i = 0; i < nvr; ++i)
        if (bg_get(C_, vr[i], &value[i]) != BG_OK) return fmi2Error;
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    size_t i;
    for (i = 0; i < nvr; ++i)
        if (bg_set(C_, vr[i], value[i]) != BG_OK) return fmi2Error;
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{ (void)vr; (void)value; return NONE(nvr, "Integer"); }
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{ (void)vr; (void)value; return NONE(nvr, "Boolean"); }
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{ (void)vr; (void)value; return NONE(nvr, "String"); }
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{ (void)vr; (void)value; return NONE(nvr, "Integer"); }
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{ (void)vr; (void)value; return NONE(nvr, "Boolean"); }
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{ (void)vr; (void)value; return NONE(nvr, "String"); }

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{ return STATUS(bg_get_state(C_, FMUstate)); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{ return STATUS(bg_set_state(C_, FMUstate)); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{ (void)c; bg_free_state(FMUstate); return fmi2OK; }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{ (void)c; (void)FMUstate; *size = bg_serial_size(); return fmi2OK; }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{ return STATUS(bg_serialize(C_, FMUstate, (unsigned char *)serializedState, size)); }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{ return STATUS(bg_deserialize(C_, (const unsigned char *)serializedState, size, FMUstate)); }

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                        size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                        size_t nKnown, const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    return UNSUPPORTED("fmi2GetDirectionalDerivative");
}

/* Model Exchange */
fmi2Status fmi2EnterEventMode(fmi2Component c) { C_->mode = BG_EVENT; return fmi2OK; }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo)
{
    int changed = 0, status = bg_event_update(C_, &changed);
    eventInfo->newDiscreteStatesNeeded = fmi2False;
    eventInfo->terminateSimulation = fmi2False;
    eventInfo->nominalsOfContinuousStatesChanged = fmi2False;
    eventInfo->valuesOfContinuousStatesChanged = changed ? fmi2True : fmi2False;
    eventInfo->nextEventTimeDefined = fmi2False;
    eventInfo->nextEventTime = 0.0;
    return STATUS(status);
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { C_->mode = BG_CONTINUOUS; return fmi2OK; }

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    (void)c; (void)noSetFMUStatePriorToCurrentPoint;
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) { bg_set_time(C_, time); return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{ return STATUS(bg_set_states(C_, x, nx)); }
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{ return STATUS(bg_get_derivatives(C_, derivatives, nx)); }
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{ return STATUS(bg_event_indicators(C_, eventIndicators, ni)); }
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{ return STATUS(bg_get_states(C_, x, nx)); }
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{ return STATUS(bg_nominals(C_, x_nominal, nx)); }

/* Co-Simulation */
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr; (void)nvr; (void)order; (void)value;
    return UNSUPPORTED("fmi2SetRealInputDerivatives (inputs are held over a step)");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr; (void)nvr; (void)order; (void)value;
    return UNSUPPORTED("fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    return STATUS(bg_do_step(C_, currentCommunicationPoint, communicationStepSize));
}

fmi2Status fmi2CancelStep(fmi2Component c) { return UNSUPPORTED("fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{ (void)c; (void)s; (void)value; return fmi2Discard; }
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    if (s != fmi2LastSuccessfulTime) return fmi2Discard;
    *value = C_->d.time;
    return fmi2OK;
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{ (void)c; (void)s; (void)value; return fmi2Discard; }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{ (void)c; (void)s; (void)value; return fmi2Discard; }
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{ (void)c; (void)s; (void)value; return fmi2Discard; }
"""
