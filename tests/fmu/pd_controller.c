/* A PD controller as an FMI 2.0 co-simulation FMU, written against the standard's headers alone: the
 * controller side of the co-simulation test (test_fmu_cosimulation.py compiles it with the system's C
 * compiler and packs it with its modelDescription.xml). Value references: 0 setpoint (parameter),
 * 1 kp, 2 kd (parameters), 3 position, 4 velocity (inputs), 5 torque (output):
 * torque = kp (setpoint - position) - kd velocity, computed at each communication point. */
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

typedef struct {
  fmi2Real values[6];
} Controller;

static void update(Controller* c) { c->values[5] = c->values[1] * (c->values[0] - c->values[3]) - c->values[2] * c->values[4]; }

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String categories[]) {
  (void)c, (void)on, (void)n, (void)categories;
  return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions* functions, fmi2Boolean visible, fmi2Boolean logging) {
  (void)name, (void)guid, (void)resources, (void)functions, (void)visible, (void)logging;
  if (type != fmi2CoSimulation) return NULL;
  Controller* c = calloc(1, sizeof(Controller));
  return c;
}

void fmi2FreeInstance(fmi2Component c) { free(c); }
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean td, fmi2Real tol, fmi2Real start, fmi2Boolean sd,
                               fmi2Real stop) {
  (void)c, (void)td, (void)tol, (void)start, (void)sd, (void)stop;
  return fmi2OK;
}
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return c ? fmi2OK : fmi2Error; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  update(c);
  return fmi2OK;
}
fmi2Status fmi2Terminate(fmi2Component c) { return c ? fmi2OK : fmi2Error; }
fmi2Status fmi2Reset(fmi2Component c) {
  memset(c, 0, sizeof(Controller));
  return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
  for (size_t k = 0; k < n; ++k) {
    if (vr[k] > 5) return fmi2Error;
    value[k] = ((Controller*)c)->values[vr[k]];
  }
  return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
  for (size_t k = 0; k < n; ++k) {
    if (vr[k] > 4) return fmi2Error;
    ((Controller*)c)->values[vr[k]] = value[k];
  }
  update(c);
  return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_prior) {
  (void)t, (void)h, (void)no_prior;
  update(c);
  return fmi2OK;
}

/* What a controller without these needs to declare for an importer that binds every function. */
#define UNSUPPORTED(name, ...) \
  fmi2Status name(fmi2Component c, __VA_ARGS__) { (void)c; return fmi2Error; }
UNSUPPORTED(fmi2GetInteger, const fmi2ValueReference vr[], size_t n, fmi2Integer v[])
UNSUPPORTED(fmi2GetBoolean, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[])
UNSUPPORTED(fmi2GetString, const fmi2ValueReference vr[], size_t n, fmi2String v[])
UNSUPPORTED(fmi2SetInteger, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[])
UNSUPPORTED(fmi2SetBoolean, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[])
UNSUPPORTED(fmi2SetString, const fmi2ValueReference vr[], size_t n, const fmi2String v[])
UNSUPPORTED(fmi2GetFMUstate, fmi2FMUstate* s)
UNSUPPORTED(fmi2SetFMUstate, fmi2FMUstate s)
UNSUPPORTED(fmi2FreeFMUstate, fmi2FMUstate* s)
UNSUPPORTED(fmi2SerializedFMUstateSize, fmi2FMUstate s, size_t* n)
UNSUPPORTED(fmi2SerializeFMUstate, fmi2FMUstate s, fmi2Byte b[], size_t n)
UNSUPPORTED(fmi2DeSerializeFMUstate, const fmi2Byte b[], size_t n, fmi2FMUstate* s)
UNSUPPORTED(fmi2GetDirectionalDerivative, const fmi2ValueReference a[], size_t na, const fmi2ValueReference b[],
            size_t nb, const fmi2Real dv[], fmi2Real du[])
UNSUPPORTED(fmi2SetRealInputDerivatives, const fmi2ValueReference vr[], size_t n, const fmi2Integer o[],
            const fmi2Real v[])
UNSUPPORTED(fmi2GetRealOutputDerivatives, const fmi2ValueReference vr[], size_t n, const fmi2Integer o[],
            fmi2Real v[])
UNSUPPORTED(fmi2GetStatus, const fmi2StatusKind k, fmi2Status* s)
UNSUPPORTED(fmi2GetRealStatus, const fmi2StatusKind k, fmi2Real* v)
UNSUPPORTED(fmi2GetIntegerStatus, const fmi2StatusKind k, fmi2Integer* v)
UNSUPPORTED(fmi2GetBooleanStatus, const fmi2StatusKind k, fmi2Boolean* v)
UNSUPPORTED(fmi2GetStringStatus, const fmi2StatusKind k, fmi2String* v)
fmi2Status fmi2CancelStep(fmi2Component c) {
  (void)c;
  return fmi2Error;
}
