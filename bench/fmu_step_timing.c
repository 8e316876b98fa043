/* Per-step time of an exported FMU's fmi3DoStep against the C API's soadyn_sim_step on the same model, in
 * C (no foreign-function layer between the loop and the calls): bench_fmu.py compiles and runs it.
 *   fmu_step_timing BINARY RESOURCES TOKEN MODEL_JSON DT CALLS REPETITIONS
 * Each repetition times, in turn: CALLS steps of the C API one step per call, CALLS steps in one call
 * (the step alone), and CALLS DoSteps of one step; it prints one line per repetition, in microseconds. */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fmi3Functions.h"
#include "soadyn/embed/c_api.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static char* read_file(const char* path) {
  FILE* f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  const long size = ftell(f);
  fseek(f, 0, SEEK_SET);
  char* text = malloc((size_t)size + 1);
  const size_t got = fread(text, 1, (size_t)size, f);
  text[got] = '\0';
  fclose(f);
  return text;
}

int main(int argc, char** argv) {
  if (argc != 8) {
    fprintf(stderr, "usage: %s BINARY RESOURCES TOKEN MODEL_JSON DT CALLS REPETITIONS\n", argv[0]);
    return 2;
  }
  const double dt = atof(argv[5]);
  const int calls = atoi(argv[6]), repetitions = atoi(argv[7]);
  void* library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!library) return fprintf(stderr, "%s\n", dlerror()), 1;
  fmi3InstantiateCoSimulationTYPE* instantiate =
      (fmi3InstantiateCoSimulationTYPE*)dlsym(library, "fmi3InstantiateCoSimulation");
  fmi3EnterInitializationModeTYPE* enter =
      (fmi3EnterInitializationModeTYPE*)dlsym(library, "fmi3EnterInitializationMode");
  fmi3ExitInitializationModeTYPE* leave = (fmi3ExitInitializationModeTYPE*)dlsym(library, "fmi3ExitInitializationMode");
  fmi3DoStepTYPE* do_step = (fmi3DoStepTYPE*)dlsym(library, "fmi3DoStep");
  fmi3FreeInstanceTYPE* free_instance = (fmi3FreeInstanceTYPE*)dlsym(library, "fmi3FreeInstance");
  fmi3Instance fmu = instantiate("bench", argv[3], argv[2], fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0, NULL,
                                 NULL, NULL);
  if (!fmu || enter(fmu, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK || leave(fmu) != fmi3OK)
    return fprintf(stderr, "cannot instantiate the FMU\n"), 1;
  char* text = read_file(argv[4]);
  soadyn_model* model = text ? soadyn_model_from_json(text) : NULL;
  soadyn_sim* sim = model ? soadyn_sim_create(model, dt, "rk4") : NULL;
  if (!sim) return fprintf(stderr, "cannot create the C API simulator: %s\n", soadyn_last_error()), 1;
  double t = 0.0;
  fmi3Boolean event = fmi3False, terminate = fmi3False, early = fmi3False;
  fmi3Float64 last = 0.0;
  for (int r = 0; r < repetitions; ++r) {
    double start = now();
    for (int k = 0; k < calls; ++k) soadyn_sim_step(sim, 1);
    const double one_per_call = (now() - start) / calls * 1e6;
    start = now();
    soadyn_sim_step(sim, calls);
    const double batched = (now() - start) / calls * 1e6;
    start = now();
    for (int k = 0; k < calls; ++k) {
      if (do_step(fmu, t, dt, fmi3True, &event, &terminate, &early, &last) != fmi3OK) return 1;
      t += dt;
    }
    const double fmu_step = (now() - start) / calls * 1e6;
    printf("c_api_one %.4f c_api_batched %.4f fmu %.4f\n", one_per_call, batched, fmu_step);
  }
  free_instance(fmu);
  soadyn_sim_free(sim);
  soadyn_model_free(model);
  free(text);
  return 0;
}
