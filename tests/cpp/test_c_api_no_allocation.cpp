// The C API's per-step calls never touch the heap: cassini (free flight, flexible booms, its turntable and
// engine gimbal following their input acceleration and position) driven through soadyn/embed/c_api.h for
// 10^4 steps: every DOF's input and a wrench on the scan platform set each step, a hinge locked, released and
// prescribed (with a velocity input) in turn, the state read (q, v, qdd and tau), saved and loaded back, with every allocation of the process counted
// (allocation_counter.cpp). The model and the state buffer are made before counting.
#include <cstdio>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "soadyn/embed/c_api.h"
#include "soadyn/model/model_file.hpp"
#include "soadyn_scenes/scenes.hpp"

using namespace soadyn_test;

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("the allocation counter does not see allocations\n");
    return 1;
  }
  const std::string text = soadyn::model_to_json(soadyn::cassini_model<double>());
  soadyn_model* model = soadyn_model_from_json(text.c_str());
  soadyn_sim* sim = model ? soadyn_sim_create(model, 1e-3, "rk4") : nullptr;
  if (!sim) {
    std::printf("cannot create the simulator: %s\n", soadyn_last_error());
    return 1;
  }
  const int nq = soadyn_model_nq(model), nv = soadyn_model_nv(model);
  const int hinge = soadyn_model_dof_index(model, "scan_az");
  const int wrench = soadyn_sim_add_wrench_input(sim, "scan_el");
  if (wrench < 0 || soadyn_sim_set_input_kind(sim, hinge, "velocity") != SOADYN_OK ||
      soadyn_sim_set_input_kind(sim, soadyn_model_dof_index(model, "gimbal_pitch"), "position") != SOADYN_OK) {
    std::printf("cannot set the inputs up: %s\n", soadyn_last_error());
    return 1;
  }
  double wrench_values[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  std::vector<double> q(static_cast<std::size_t>(nq)), v(static_cast<std::size_t>(nv)),
      qdd(static_cast<std::size_t>(nv)), tau(static_cast<std::size_t>(nv));
  std::vector<unsigned char> state(soadyn_sim_state_size(sim));
  constexpr int kSteps = 10000;
  long failed = 0;
  arm_counter();
  for (int k = 0; k < kSteps; ++k) {
    for (int dof = 0; dof < nv; ++dof) failed += soadyn_sim_set_input(sim, dof, 1e-3 * ((k + dof) % 7)) != SOADYN_OK;
    wrench_values[k % 6] = 1e-2 * (k % 3);
    failed += soadyn_sim_set_wrench(sim, wrench, wrench_values) != SOADYN_OK;
    if (k % 500 == 100) failed += soadyn_sim_lock(sim, hinge) != SOADYN_OK;
    if (k % 500 == 200) failed += soadyn_sim_prescribe(sim, hinge) != SOADYN_OK;
    if (k % 500 == 300) failed += soadyn_sim_release(sim, hinge) != SOADYN_OK;
    if (k % 1000 == 400) failed += soadyn_sim_save_state(sim, state.data(), state.size()) != SOADYN_OK;
    if (k % 1000 == 450) failed += soadyn_sim_load_state(sim, state.data(), state.size()) != SOADYN_OK;
    failed += soadyn_sim_step(sim, 1) != SOADYN_OK;
    failed += soadyn_sim_get_q(sim, q.data(), nq) != SOADYN_OK;
    failed += soadyn_sim_get_v(sim, v.data(), nv) != SOADYN_OK;
    failed += soadyn_sim_get_qdd_tau(sim, qdd.data(), tau.data(), nv) != SOADYN_OK;
  }
  const AllocationCounts counts = disarm_counter();
  std::printf("c api (cassini): %d steps, %ld allocations, %ld frees, %ld failed calls\n", kSteps,
              counts.allocations(), counts.frees, failed);
  soadyn_sim_free(sim);
  soadyn_model_free(model);
  if (counts.allocations() != 0 || counts.frees != 0 || failed != 0) return 1;
  std::printf("test_c_api_no_allocation: PASS\n");
  return 0;
}
