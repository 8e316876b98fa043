// The FMI 2.0 co-simulation entry points of the soadyn FMU: argument and status translation around
// fmu::Instance, as fmi3_functions.cpp does for FMI 3.0. Model exchange is not offered; its functions,
// directional derivatives and input derivatives return fmi2Error naming themselves.
#include <exception>
#include <memory>
#include <string>

#include "fmi2Functions.h"
#include "soadyn/fmu/instance.hpp"
#include "soadyn/fmu/saved_states.hpp"

namespace {

struct Component {
  std::string name;
  fmi2CallbackFunctions callbacks{};
  bool logging = false;
  double start_time = 0.0;
  std::unique_ptr<soadyn::fmu::Instance> instance;

  // The message is FMI 2's format string (no arguments): '%' doubled, so that loggers that format and loggers
  // that do not both show it as written.
  void log(bool error, const char* category, const std::string& message) const {
    if (!callbacks.logger || !(error || logging)) return;
    std::string format;
    for (const char c : message) format += c == '%' ? std::string("%%") : std::string(1, c);
    callbacks.logger(callbacks.componentEnvironment, name.c_str(), error ? fmi2Error : fmi2OK, category,
                     format.c_str());
  }
};

Component* component(fmi2Component c) { return static_cast<Component*>(c); }

fmi2Status status(bool ok) { return ok ? fmi2OK : fmi2Error; }

fmi2Status unsupported(fmi2Component c, const char* function) {
  if (c) component(c)->log(true, "logError", std::string(function) + " is not supported by this FMU (co-simulation)");
  return fmi2Error;
}

template <class Body>
fmi2Status guarded(fmi2Component c, const char* function, Body&& body) {
  if (c == nullptr) return fmi2Error;
  try {
    return body(*component(c));
  } catch (const std::exception& e) {
    component(c)->log(true, "logError", std::string(function) + ": " + e.what());
  } catch (...) {
    component(c)->log(true, "logError", std::string(function) + ": unknown error");
  }
  return fmi2Error;
}

template <class T, class Each>
fmi2Status for_each_value(fmi2Component c, const char* function, const fmi2ValueReference vrs[], size_t n, T values[],
                          Each&& each) {
  return guarded(c, function, [&](Component& comp) {
    if (n > 0 && (!vrs || !values)) return fmi2Error;
    for (size_t k = 0; k < n; ++k)
      if (!each(*comp.instance, vrs[k], values[k])) return fmi2Error;
    return fmi2OK;
  });
}

}  // namespace

#define SOADYN_FMI2_UNSUPPORTED(function, ...) \
  fmi2Status function(fmi2Component c, __VA_ARGS__) { return unsupported(c, #function); }

extern "C" {

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  if (!c) return fmi2Error;
  component(c)->logging = loggingOn;
  return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions, fmi2Boolean,
                              fmi2Boolean loggingOn) {
  auto c = std::make_unique<Component>();
  c->name = instanceName ? instanceName : "";
  if (functions) c->callbacks = *functions;
  c->logging = loggingOn;
  if (fmuType != fmi2CoSimulation) {
    c->log(true, "logError", "this FMU is for co-simulation only (no model exchange)");
    return nullptr;
  }
  try {
    if (!fmuResourceLocation) throw std::invalid_argument("no resource location given");
    const Component* raw = c.get();
    c->instance = std::make_unique<soadyn::fmu::Instance>(
        soadyn::fmu::path_of_file_uri(fmuResourceLocation),
        [raw](bool error, const char* category, const std::string& m) { raw->log(error, category, m); });
    if (!fmuGUID || c->instance->settings().token != fmuGUID) {
      c->log(true, "logError", std::string("the GUID '") + (fmuGUID ? fmuGUID : "") + "' is not this FMU's ('" +
                                   c->instance->settings().token + "')");
      return nullptr;
    }
  } catch (const std::exception& e) {
    c->log(true, "logError", std::string("cannot instantiate: ") + e.what());
    return nullptr;
  }
  return c.release();
}

void fmi2FreeInstance(fmi2Component c) { delete component(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real, fmi2Real startTime, fmi2Boolean, fmi2Real) {
  if (!c) return fmi2Error;
  component(c)->start_time = startTime;
  return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return guarded(c, "fmi2EnterInitializationMode",
                 [&](Component& comp) { return status(comp.instance->enter_initialization(comp.start_time)); });
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return guarded(c, "fmi2ExitInitializationMode",
                 [&](Component& comp) { return status(comp.instance->exit_initialization()); });
}

fmi2Status fmi2Terminate(fmi2Component c) { return c ? fmi2OK : fmi2Error; }

fmi2Status fmi2Reset(fmi2Component c) {
  return guarded(c, "fmi2Reset", [&](Component& comp) { return status(comp.instance->reset()); });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return for_each_value(c, "fmi2GetReal", vr, nvr, value, [](soadyn::fmu::Instance& i, fmi2ValueReference r,
                                                             fmi2Real& x) { return i.get_float64(r, x); });
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  return for_each_value(c, "fmi2SetReal", vr, nvr, value, [](soadyn::fmu::Instance& i, fmi2ValueReference r,
                                                             const fmi2Real& x) { return i.set_float64(r, x); });
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
  return for_each_value(c, "fmi2GetBoolean", vr, nvr, value,
                        [](soadyn::fmu::Instance& i, fmi2ValueReference r, fmi2Boolean& x) {
                          bool b = false;
                          const bool ok = i.get_boolean(r, b);
                          x = b ? fmi2True : fmi2False;
                          return ok;
                        });
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
  return for_each_value(c, "fmi2SetBoolean", vr, nvr, value,
                        [](soadyn::fmu::Instance& i, fmi2ValueReference r, const fmi2Boolean& x) {
                          return i.set_boolean(r, x != fmi2False);
                        });
}

// Integer: the substeps (Integer) and integrator (Enumeration) parameters.
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
  return for_each_value(c, "fmi2GetInteger", vr, nvr, value,
                        [](soadyn::fmu::Instance& i, fmi2ValueReference r, fmi2Integer& x) {
                          long long v = 0;
                          const bool ok = i.get_integer(r, v, std::nullopt);
                          x = static_cast<fmi2Integer>(v);
                          return ok;
                        });
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
  return for_each_value(c, "fmi2SetInteger", vr, nvr, value,
                        [](soadyn::fmu::Instance& i, fmi2ValueReference r, const fmi2Integer& x) {
                          return i.set_integer(r, x, std::nullopt);
                        });
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean) {
  return guarded(c, "fmi2DoStep", [&](Component& comp) {
    return status(comp.instance->do_step(currentCommunicationPoint, communicationStepSize));
  });
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status* value) {
  if (!c || !value) return fmi2Error;
  *value = component(c)->instance->failed() ? fmi2Error : fmi2OK;
  return fmi2OK;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean* value) {
  if (!c || !value || kind != fmi2Terminated) return unsupported(c, "fmi2GetBooleanStatus of this kind");
  *value = component(c)->instance->failed() ? fmi2True : fmi2False;
  return fmi2OK;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real* value) {
  if (!c || !value || kind != fmi2LastSuccessfulTime) return unsupported(c, "fmi2GetRealStatus of this kind");
  return status(component(c)->instance->get_float64(0, *value));
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) {
  return guarded(c, "fmi2GetFMUstate", [&](Component& comp) {
    if (!state) return fmi2Error;
    *state = soadyn::fmu::capture_state(*comp.instance, *state);
    return fmi2OK;
  });
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
  return guarded(c, "fmi2SetFMUstate",
                 [&](Component& comp) { return status(soadyn::fmu::restore_state(*comp.instance, state)); });
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* state) {
  if (!c || !state) return fmi2Error;
  soadyn::fmu::free_state(*state);
  *state = nullptr;
  return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t* size) {
  if (!c || !state || !size) return fmi2Error;
  *size = soadyn::fmu::serialized_size(state);
  return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte serialized[], size_t size) {
  if (!c || !state) return fmi2Error;
  return soadyn::fmu::serialize_state(state, reinterpret_cast<unsigned char*>(serialized), size)
             ? fmi2OK
             : unsupported(c, "fmi2SerializeFMUstate into a short buffer");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serialized[], size_t size, fmi2FMUstate* state) {
  return guarded(c, "fmi2DeSerializeFMUstate", [&](Component& comp) {
    if (!state) return fmi2Error;
    std::string why;
    soadyn::fmu::SavedState* saved = soadyn::fmu::deserialize_state(
        *comp.instance, reinterpret_cast<const unsigned char*>(serialized), size, *state, why);
    if (!saved) {
      comp.log(true, "logError", "fmi2DeSerializeFMUstate: " + why);
      return fmi2Error;
    }
    *state = saved;
    return fmi2OK;
  });
}

SOADYN_FMI2_UNSUPPORTED(fmi2GetString, const fmi2ValueReference[], size_t, fmi2String[])
SOADYN_FMI2_UNSUPPORTED(fmi2SetString, const fmi2ValueReference[], size_t, const fmi2String[])
SOADYN_FMI2_UNSUPPORTED(fmi2GetIntegerStatus, const fmi2StatusKind, fmi2Integer*)
SOADYN_FMI2_UNSUPPORTED(fmi2GetStringStatus, const fmi2StatusKind, fmi2String*)
SOADYN_FMI2_UNSUPPORTED(fmi2GetDirectionalDerivative, const fmi2ValueReference[], size_t, const fmi2ValueReference[],
                        size_t, const fmi2Real[], fmi2Real[])
SOADYN_FMI2_UNSUPPORTED(fmi2SetRealInputDerivatives, const fmi2ValueReference[], size_t, const fmi2Integer[],
                        const fmi2Real[])
SOADYN_FMI2_UNSUPPORTED(fmi2GetRealOutputDerivatives, const fmi2ValueReference[], size_t, const fmi2Integer[],
                        fmi2Real[])
SOADYN_FMI2_UNSUPPORTED(fmi2NewDiscreteStates, fmi2EventInfo*)
SOADYN_FMI2_UNSUPPORTED(fmi2CompletedIntegratorStep, fmi2Boolean, fmi2Boolean*, fmi2Boolean*)
SOADYN_FMI2_UNSUPPORTED(fmi2SetTime, fmi2Real)
SOADYN_FMI2_UNSUPPORTED(fmi2SetContinuousStates, const fmi2Real[], size_t)
SOADYN_FMI2_UNSUPPORTED(fmi2GetDerivatives, fmi2Real[], size_t)
SOADYN_FMI2_UNSUPPORTED(fmi2GetEventIndicators, fmi2Real[], size_t)
SOADYN_FMI2_UNSUPPORTED(fmi2GetContinuousStates, fmi2Real[], size_t)
SOADYN_FMI2_UNSUPPORTED(fmi2GetNominalsOfContinuousStates, fmi2Real[], size_t)
fmi2Status fmi2EnterEventMode(fmi2Component c) { return unsupported(c, "fmi2EnterEventMode"); }
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return unsupported(c, "fmi2EnterContinuousTimeMode"); }

}  // extern "C"
