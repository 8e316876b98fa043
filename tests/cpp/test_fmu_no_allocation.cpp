// The FMU's per-step calls never touch the heap: the FMU binary (soadyn_fmu.so, loaded with dlopen as an
// importer loads it) instantiated on cassini with a frame's outputs and a wrench input, the scan platform's
// input a velocity and the engine gimbal's a position, then 10^4 fmi3DoStep calls with every input set
// before each (torques, the turntable's acceleration, the gimbal's position, the wrench), the scan platform
// locked, prescribed and released through its Boolean inputs, a tunable parameter changed now and then,
// every output read (q, v, qdd, tau, energies, the frame's 16), and the state saved into and restored from
// an existing FMU state; every allocation of the process counted
// (allocation_counter.cpp: the C family too, which the binary's own C++ runtime calls).
#include <dlfcn.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "fmi3Functions.h"
#include "soadyn/fmu/variables.hpp"
#include "soadyn/model/model_file.hpp"
#include "soadyn_scenes/scenes.hpp"

using namespace soadyn_test;

namespace {

template <class F>
F* symbol(void* library, const char* name) {
  return reinterpret_cast<F*>(dlsym(library, name));
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("the allocation counter does not see allocations\n");
    return 1;
  }
  const soadyn::Model model = soadyn::cassini_model<double>();
  const std::filesystem::path resources = std::filesystem::temp_directory_path() / "soadyn_fmu_no_allocation";
  std::filesystem::create_directories(resources);
  std::ofstream(resources / "model.json") << soadyn::model_to_json(model);
  std::ofstream(resources / "soadyn_fmu.txt") << "soadyn-fmu 1\ntoken {test}\nstep 0.001\nsubsteps 1\n"
                                                 "integrator rk4\nframes scan_el\nwrenches scan_el\n"
                                                 "inputs scan_az=velocity gimbal_pitch=position\n";
  void* library = dlopen(SOADYN_FMU_BINARY, RTLD_NOW | RTLD_LOCAL);
  if (!library) {
    std::printf("cannot load %s: %s\n", SOADYN_FMU_BINARY, dlerror());
    return 1;
  }
  auto* instantiate = symbol<fmi3InstantiateCoSimulationTYPE>(library, "fmi3InstantiateCoSimulation");
  auto* enter = symbol<fmi3EnterInitializationModeTYPE>(library, "fmi3EnterInitializationMode");
  auto* leave = symbol<fmi3ExitInitializationModeTYPE>(library, "fmi3ExitInitializationMode");
  auto* do_step = symbol<fmi3DoStepTYPE>(library, "fmi3DoStep");
  auto* set_float = symbol<fmi3SetFloat64TYPE>(library, "fmi3SetFloat64");
  auto* get_float = symbol<fmi3GetFloat64TYPE>(library, "fmi3GetFloat64");
  auto* set_bool = symbol<fmi3SetBooleanTYPE>(library, "fmi3SetBoolean");
  auto* get_state = symbol<fmi3GetFMUStateTYPE>(library, "fmi3GetFMUState");
  auto* set_state = symbol<fmi3SetFMUStateTYPE>(library, "fmi3SetFMUState");
  auto* free_state = symbol<fmi3FreeFMUStateTYPE>(library, "fmi3FreeFMUState");
  auto* free_instance = symbol<fmi3FreeInstanceTYPE>(library, "fmi3FreeInstance");
  fmi3Instance fmu = instantiate("test", "{test}", resources.c_str(), fmi3False, fmi3False, fmi3False, fmi3False,
                                 nullptr, 0, nullptr, nullptr, nullptr);
  if (!fmu || enter(fmu, fmi3False, 0, 0, fmi3False, 0) != fmi3OK || leave(fmu) != fmi3OK) {
    std::printf("cannot instantiate the FMU\n");
    return 1;
  }
  // Value references from the same table the binary serves.
  soadyn::fmu::Settings settings;
  settings.frames = settings.wrenches = {"scan_el"};
  settings.inputs = {{"scan_az", "velocity"}, {"gimbal_pitch", "position"}};
  const std::vector<soadyn::fmu::Variable> variables = soadyn::fmu::variables(model, settings);
  std::vector<fmi3ValueReference> inputs, outputs;
  fmi3ValueReference locked = 0, prescribed = 0, tunable = 0;
  double tunable_start = 0.0;
  for (std::size_t vr = 0; vr < variables.size(); ++vr) {
    const soadyn::fmu::Variable& v = variables[vr];
    const auto ref = static_cast<fmi3ValueReference>(vr);
    if (v.quantity == soadyn::fmu::Quantity::input || v.quantity == soadyn::fmu::Quantity::wrench) inputs.push_back(ref);
    else if (v.name == "locked.scan_az") locked = ref;
    else if (v.name == "prescribed.scan_az") prescribed = ref;
    else if (v.quantity == soadyn::fmu::Quantity::parameter && v.tunable && tunable == 0) tunable = ref;
    else if (v.type == soadyn::fmu::ValueType::float64 && v.quantity != soadyn::fmu::Quantity::parameter)
      outputs.push_back(ref);
  }
  if (tunable == 0 || get_float(fmu, &tunable, 1, &tunable_start, 1) != fmi3OK) return 1;
  std::vector<double> input_values(inputs.size()), output_values(outputs.size());
  fmi3FMUState state = nullptr;
  if (get_state(fmu, &state) != fmi3OK) return 1;  // made before counting; later captures reuse it
  fmi3Boolean event = fmi3False, terminate = fmi3False, early = fmi3False;
  fmi3Float64 last = 0;
  constexpr int kSteps = 10000;
  long failed = 0;
  double t = 0;
  arm_counter();
  for (int k = 0; k < kSteps; ++k) {
    for (std::size_t i = 0; i < inputs.size(); ++i) input_values[i] = 1e-3 * static_cast<double>((k + i) % 5);
    failed += set_float(fmu, inputs.data(), inputs.size(), input_values.data(), inputs.size()) != fmi3OK;
    const fmi3Boolean lock = k % 600 >= 100 && k % 600 < 200, drive = k % 600 >= 300 && k % 600 < 400;
    failed += set_bool(fmu, &locked, 1, &lock, 1) != fmi3OK;
    failed += set_bool(fmu, &prescribed, 1, &drive, 1) != fmi3OK;
    if (k % 250 == 0) {  // a tunable parameter, alternately 10 % above its start value and back
      const double value = tunable_start * (k % 500 == 0 ? 1.1 : 1.0);
      failed += set_float(fmu, &tunable, 1, &value, 1) != fmi3OK;
    }
    failed += do_step(fmu, t, 1e-3, fmi3True, &event, &terminate, &early, &last) != fmi3OK;
    t += 1e-3;
    failed += get_float(fmu, outputs.data(), outputs.size(), output_values.data(), outputs.size()) != fmi3OK;
    if (k % 1000 == 500) failed += get_state(fmu, &state) != fmi3OK;
    if (k % 1000 == 700) {
      failed += set_state(fmu, state) != fmi3OK;
      t -= 0.2;
    }
  }
  const AllocationCounts counts = disarm_counter();
  std::printf("fmu (cassini, frame scan_el): %d DoSteps, %zu outputs read each, %ld allocations, %ld frees, "
              "%ld failed calls\n", kSteps, outputs.size(), counts.allocations(), counts.frees, failed);
  // The counter sees the binary's own allocations (its C++ runtime is linked in): a new FMU state allocates.
  fmi3FMUState fresh = nullptr;
  arm_counter();
  get_state(fmu, &fresh);
  const long seen = disarm_counter().allocations();
  std::printf("a new FMU state inside the binary: %ld allocations seen\n", seen);
  free_state(fmu, &fresh);
  free_state(fmu, &state);
  free_instance(fmu);
  std::filesystem::remove_all(resources);
  if (counts.allocations() != 0 || counts.frees != 0 || failed != 0 || seen == 0) return 1;
  std::printf("test_fmu_no_allocation: PASS\n");
  return 0;
}
