// The FMI 3.0 co-simulation entry points of the soadyn FMU: argument and status translation around
// fmu::Instance. Model exchange and scheduled execution are not offered (their instantiation returns NULL
// with the reason logged); the functions that belong to them, to clocks, event mode and derivatives
// return fmi3Error naming themselves. No exception leaves an entry point.
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "fmi3Functions.h"
#include "soadyn/fmu/instance.hpp"
#include "soadyn/fmu/saved_states.hpp"

namespace {

struct Component {
  std::string name;
  fmi3InstanceEnvironment environment = nullptr;
  fmi3LogMessageCallback log_message = nullptr;
  bool logging = false;
  std::unique_ptr<soadyn::fmu::Instance> instance;

  void log(bool error, const char* category, const std::string& message) const {
    if (log_message && (error || logging)) log_message(environment, error ? fmi3Error : fmi3OK, category, message.c_str());
  }
};

Component* component(fmi3Instance instance) { return static_cast<Component*>(instance); }

fmi3Status status(bool ok) { return ok ? fmi3OK : fmi3Error; }

fmi3Status unsupported(fmi3Instance instance, const char* function) {
  if (instance) component(instance)->log(true, "logError", std::string(function) + " is not supported by this FMU "
                                                                                   "(co-simulation without event mode)");
  return fmi3Error;
}

// Runs `body`, turning an escaping exception (none is expected) into fmi3Error with its message logged.
template <class Body>
fmi3Status guarded(fmi3Instance instance, const char* function, Body&& body) {
  if (instance == nullptr) return fmi3Error;
  try {
    return body(*component(instance));
  } catch (const std::exception& e) {
    component(instance)->log(true, "logError", std::string(function) + ": " + e.what());
  } catch (...) {
    component(instance)->log(true, "logError", std::string(function) + ": unknown error");
  }
  return fmi3Error;
}

template <class Get, class T>
fmi3Status for_each_value(fmi3Instance instance, const char* function, const fmi3ValueReference vrs[], size_t n, T values[],
                      size_t n_values, Get&& get) {
  return guarded(instance, function, [&](Component& c) {
    if (n != n_values) {
      c.log(true, "logError", std::string(function) + ": " + std::to_string(n) + " value references but " +
                                  std::to_string(n_values) + " values");
      return fmi3Error;
    }
    for (size_t k = 0; k < n; ++k)
      if (!get(*c.instance, vrs[k], values[k])) return fmi3Error;
    return fmi3OK;
  });
}

// The Int32 and Int64 calls: the integer parameters (Instance::get_integer, set_integer).
template <class Integer>
fmi3Status get_integers(fmi3Instance instance, const char* call, const fmi3ValueReference vrs[], size_t n,
                        Integer values[], size_t nValues, soadyn::fmu::ValueType type) {
  return for_each_value(instance, call, vrs, n, values, nValues,
                        [type](soadyn::fmu::Instance& i, fmi3ValueReference vr, Integer& x) {
                          long long value = 0;
                          const bool ok = i.get_integer(vr, value, type);
                          x = static_cast<Integer>(value);
                          return ok;
                        });
}

template <class Integer>
fmi3Status set_integers(fmi3Instance instance, const char* call, const fmi3ValueReference vrs[], size_t n,
                        const Integer values[], size_t nValues, soadyn::fmu::ValueType type) {
  return for_each_value(instance, call, vrs, n, values, nValues,
                        [type](soadyn::fmu::Instance& i, fmi3ValueReference vr, const Integer& x) {
                          return i.set_integer(vr, static_cast<long long>(x), type);
                        });
}

}  // namespace

#define SOADYN_FMI3_UNSUPPORTED(function, ...) \
  fmi3Status function(fmi3Instance instance, __VA_ARGS__) { return unsupported(instance, #function); }
#define SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(function) \
  fmi3Status function(fmi3Instance instance) { return unsupported(instance, #function); }

extern "C" {

const char* fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t, const fmi3String[]) {
  if (!instance) return fmi3Error;
  component(instance)->logging = loggingOn;
  return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean, const fmi3ValueReference[], size_t,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback) {
  auto c = std::make_unique<Component>();
  c->name = instanceName ? instanceName : "";
  c->environment = instanceEnvironment;
  c->log_message = logMessage;
  c->logging = loggingOn;
  if (eventModeUsed) {
    c->log(true, "logError", "event mode is not supported by this FMU");
    return nullptr;
  }
  if (resourcePath == nullptr) {
    c->log(true, "logError", "no resource path given: the FMU reads its model from resources/model.json");
    return nullptr;
  }
  try {
    std::string resources = resourcePath;
    while (resources.size() > 1 && resources.back() == '/') resources.pop_back();
    const Component* raw = c.get();
    c->instance = std::make_unique<soadyn::fmu::Instance>(
        resources, [raw](bool error, const char* category, const std::string& m) { raw->log(error, category, m); });
    if (!instantiationToken || c->instance->settings().token != instantiationToken) {
      c->log(true, "logError", std::string("the instantiation token '") + (instantiationToken ? instantiationToken : "") +
                                   "' is not this FMU's ('" + c->instance->settings().token + "')");
      return nullptr;
    }
  } catch (const std::exception& e) {
    c->log(true, "logError", std::string("cannot instantiate: ") + e.what());
    return nullptr;
  }
  return c.release();
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                                          fmi3InstanceEnvironment environment, fmi3LogMessageCallback log) {
  if (log) log(environment, fmi3Error, "logError", "this FMU is for co-simulation only (no model exchange)");
  return nullptr;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                                               fmi3InstanceEnvironment environment, fmi3LogMessageCallback log,
                                               fmi3ClockUpdateCallback, fmi3LockPreemptionCallback,
                                               fmi3UnlockPreemptionCallback) {
  if (log) log(environment, fmi3Error, "logError", "this FMU is for co-simulation only (no scheduled execution)");
  return nullptr;
}

void fmi3FreeInstance(fmi3Instance instance) { delete component(instance); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean, fmi3Float64, fmi3Float64 startTime,
                                       fmi3Boolean, fmi3Float64) {
  return guarded(instance, "fmi3EnterInitializationMode",
                 [&](Component& c) { return status(c.instance->enter_initialization(startTime)); });
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
  return guarded(instance, "fmi3ExitInitializationMode",
                 [&](Component& c) { return status(c.instance->exit_initialization()); });
}

fmi3Status fmi3Terminate(fmi3Instance instance) { return instance ? fmi3OK : fmi3Error; }

fmi3Status fmi3Reset(fmi3Instance instance) {
  return guarded(instance, "fmi3Reset", [&](Component& c) { return status(c.instance->reset()); });
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Float64 values[],
                          size_t nValues) {
  return for_each_value(instance, "fmi3GetFloat64", vrs, n, values, nValues,
                    [](soadyn::fmu::Instance& i, fmi3ValueReference vr, fmi3Float64& x) { return i.get_float64(vr, x); });
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const fmi3Float64 values[],
                          size_t nValues) {
  return for_each_value(instance, "fmi3SetFloat64", vrs, n, values, nValues,
                    [](soadyn::fmu::Instance& i, fmi3ValueReference vr, const fmi3Float64& x) {
                      return i.set_float64(vr, x);
                    });
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Boolean values[],
                          size_t nValues) {
  return for_each_value(instance, "fmi3GetBoolean", vrs, n, values, nValues,
                    [](soadyn::fmu::Instance& i, fmi3ValueReference vr, fmi3Boolean& x) { return i.get_boolean(vr, x); });
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const fmi3Boolean values[],
                          size_t nValues) {
  return for_each_value(instance, "fmi3SetBoolean", vrs, n, values, nValues,
                    [](soadyn::fmu::Instance& i, fmi3ValueReference vr, const fmi3Boolean& x) {
                      return i.set_boolean(vr, x);
                    });
}

// Int32: the substeps parameter; Int64: the integrator (an Enumeration, which FMI 3 reads and writes as Int64).
fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Int32 values[],
                        size_t nValues) {
  return get_integers(instance, "fmi3GetInt32", vrs, n, values, nValues, soadyn::fmu::ValueType::int32);
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const fmi3Int32 values[],
                        size_t nValues) {
  return set_integers(instance, "fmi3SetInt32", vrs, n, values, nValues, soadyn::fmu::ValueType::int32);
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, fmi3Int64 values[],
                        size_t nValues) {
  return get_integers(instance, "fmi3GetInt64", vrs, n, values, nValues, soadyn::fmu::ValueType::enumeration);
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vrs[], size_t n, const fmi3Int64 values[],
                        size_t nValues) {
  return set_integers(instance, "fmi3SetInt64", vrs, n, values, nValues, soadyn::fmu::ValueType::enumeration);
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean, fmi3Boolean* eventHandlingNeeded, fmi3Boolean* terminateSimulation,
                      fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime) {
  return guarded(instance, "fmi3DoStep", [&](Component& c) {
    const bool ok = c.instance->do_step(currentCommunicationPoint, communicationStepSize);
    if (eventHandlingNeeded) *eventHandlingNeeded = false;
    if (terminateSimulation) *terminateSimulation = !ok;
    if (earlyReturn) *earlyReturn = false;
    double time = 0.0;
    c.instance->get_float64(0, time);
    if (lastSuccessfulTime) *lastSuccessfulTime = time;
    return status(ok);
  });
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) { return instance ? fmi3OK : fmi3Error; }

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* state) {
  return guarded(instance, "fmi3GetFMUState", [&](Component& c) {
    if (!state) return fmi3Error;
    *state = soadyn::fmu::capture_state(*c.instance, *state);
    return fmi3OK;
  });
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
  return guarded(instance, "fmi3SetFMUState",
                 [&](Component& c) { return status(soadyn::fmu::restore_state(*c.instance, state)); });
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* state) {
  if (!instance || !state) return fmi3Error;
  soadyn::fmu::free_state(*state);
  *state = nullptr;
  return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t* size) {
  if (!instance || !state || !size) return fmi3Error;
  *size = soadyn::fmu::serialized_size(state);
  return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte serialized[], size_t size) {
  if (!instance || !state) return fmi3Error;
  return soadyn::fmu::serialize_state(state, serialized, size) ? fmi3OK : unsupported(instance, "a short buffer");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serialized[], size_t size,
                                   fmi3FMUState* state) {
  return guarded(instance, "fmi3DeserializeFMUState", [&](Component& c) {
    if (!state) return fmi3Error;
    std::string why;
    soadyn::fmu::SavedState* saved = soadyn::fmu::deserialize_state(*c.instance, serialized, size, *state, why);
    if (!saved) {
      c.log(true, "logError", "fmi3DeserializeFMUState: " + why);
      return fmi3Error;
    }
    *state = saved;
    return fmi3OK;
  });
}

SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(fmi3EnterEventMode)
SOADYN_FMI3_UNSUPPORTED(fmi3GetFloat32, const fmi3ValueReference[], size_t, fmi3Float32[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetInt8, const fmi3ValueReference[], size_t, fmi3Int8[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetUInt8, const fmi3ValueReference[], size_t, fmi3UInt8[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetInt16, const fmi3ValueReference[], size_t, fmi3Int16[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetUInt16, const fmi3ValueReference[], size_t, fmi3UInt16[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetUInt32, const fmi3ValueReference[], size_t, fmi3UInt32[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetUInt64, const fmi3ValueReference[], size_t, fmi3UInt64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetString, const fmi3ValueReference[], size_t, fmi3String[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetBinary, const fmi3ValueReference[], size_t, size_t[], fmi3Binary[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetClock, const fmi3ValueReference[], size_t, fmi3Clock[])
SOADYN_FMI3_UNSUPPORTED(fmi3SetFloat32, const fmi3ValueReference[], size_t, const fmi3Float32[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetInt8, const fmi3ValueReference[], size_t, const fmi3Int8[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetUInt8, const fmi3ValueReference[], size_t, const fmi3UInt8[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetInt16, const fmi3ValueReference[], size_t, const fmi3Int16[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetUInt16, const fmi3ValueReference[], size_t, const fmi3UInt16[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetUInt32, const fmi3ValueReference[], size_t, const fmi3UInt32[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetUInt64, const fmi3ValueReference[], size_t, const fmi3UInt64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetString, const fmi3ValueReference[], size_t, const fmi3String[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetBinary, const fmi3ValueReference[], size_t, const size_t[], const fmi3Binary[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3SetClock, const fmi3ValueReference[], size_t, const fmi3Clock[])
SOADYN_FMI3_UNSUPPORTED(fmi3GetNumberOfVariableDependencies, fmi3ValueReference, size_t*)
SOADYN_FMI3_UNSUPPORTED(fmi3GetVariableDependencies, fmi3ValueReference, size_t[], fmi3ValueReference[], size_t[],
                        fmi3DependencyKind[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetDirectionalDerivative, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                        size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetAdjointDerivative, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                        size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(fmi3EnterConfigurationMode)
SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(fmi3ExitConfigurationMode)
SOADYN_FMI3_UNSUPPORTED(fmi3GetIntervalDecimal, const fmi3ValueReference[], size_t, fmi3Float64[],
                        fmi3IntervalQualifier[])
SOADYN_FMI3_UNSUPPORTED(fmi3GetIntervalFraction, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[],
                        fmi3IntervalQualifier[])
SOADYN_FMI3_UNSUPPORTED(fmi3GetShiftDecimal, const fmi3ValueReference[], size_t, fmi3Float64[])
SOADYN_FMI3_UNSUPPORTED(fmi3GetShiftFraction, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[])
SOADYN_FMI3_UNSUPPORTED(fmi3SetIntervalDecimal, const fmi3ValueReference[], size_t, const fmi3Float64[])
SOADYN_FMI3_UNSUPPORTED(fmi3SetIntervalFraction, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                        const fmi3UInt64[])
SOADYN_FMI3_UNSUPPORTED(fmi3SetShiftDecimal, const fmi3ValueReference[], size_t, const fmi3Float64[])
SOADYN_FMI3_UNSUPPORTED(fmi3SetShiftFraction, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                        const fmi3UInt64[])
SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(fmi3EvaluateDiscreteStates)
SOADYN_FMI3_UNSUPPORTED(fmi3UpdateDiscreteStates, fmi3Boolean*, fmi3Boolean*, fmi3Boolean*, fmi3Boolean*,
                        fmi3Boolean*, fmi3Float64*)
SOADYN_FMI3_UNSUPPORTED_NO_ARGUMENTS(fmi3EnterContinuousTimeMode)
SOADYN_FMI3_UNSUPPORTED(fmi3CompletedIntegratorStep, fmi3Boolean, fmi3Boolean*, fmi3Boolean*)
SOADYN_FMI3_UNSUPPORTED(fmi3SetTime, fmi3Float64)
SOADYN_FMI3_UNSUPPORTED(fmi3SetContinuousStates, const fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetContinuousStateDerivatives, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetEventIndicators, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetContinuousStates, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetNominalsOfContinuousStates, fmi3Float64[], size_t)
SOADYN_FMI3_UNSUPPORTED(fmi3GetNumberOfEventIndicators, size_t*)
SOADYN_FMI3_UNSUPPORTED(fmi3GetNumberOfContinuousStates, size_t*)
// Scheduled execution's one function, declared by the FMI 3.0 header of the standard's release (not by the
// header here, of a later revision); importers that bind it look for the symbol.
FMI3_Export SOADYN_FMI3_UNSUPPORTED(fmi3ActivateModelPartition, fmi3ValueReference, fmi3Float64)
SOADYN_FMI3_UNSUPPORTED(fmi3GetOutputDerivatives, const fmi3ValueReference[], size_t, const fmi3Int32[],
                        fmi3Float64[], size_t)

}  // extern "C"
