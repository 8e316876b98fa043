// Force elements allocate nothing per call: a random 20-body tree with every
// joint kind (free root), a spring-damper on every DOF with a scalar
// coordinate and point springs (one with a force-law table) between bodies
// and to the world, 10^4 calls each of inverse_dynamics, bias_forces,
// forward_dynamics, hybrid_dynamics (a mixed mask), potential_energy (and
// mechanical_energy's, equal to it bit for bit) and
// force_element_dissipation, then 10^4 RK4 steps of the Simulator, counted by
// the allocation counter (allocation_counter.cpp). Each call is checked
// (forward dynamics of inverse dynamics' torques gives back qdd; hybrid
// dynamics agrees with both), so the calls do their work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/model/add_force_element.hxx"  // joint_has_scalar_coordinates
#include "soadyn/soadyn.hpp"

using namespace soadyn_test;

namespace {

constexpr int kCalls = 10000;
constexpr int kStates = 16;
constexpr double kTolerance = 1e-9;

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1.0);
}

soadyn::Model sprung_model() {
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  int springs = 0;
  for (int k = 0; k < model.nv; ++k) {
    const int body = model.dof_body[static_cast<std::size_t>(k)];
    if (!soadyn::joint_has_scalar_coordinates(model.joints[static_cast<std::size_t>(body)])) continue;
    model.add_joint_spring("joint_spring_" + std::to_string(k), k, 2.0 + k, 0.1 * (k % 3), 0.05 * k);
    ++springs;
  }
  const double rest = 0.4;
  for (int b = 1; b < model.nbodies(); b += 4)
    model.add_point_spring("point_spring_" + std::to_string(b), model.body_names[static_cast<std::size_t>(b)],
                           b % 8 == 1 ? "world" : model.body_names[static_cast<std::size_t>(b - 1)],
                           soadyn::Vec3<double>(0.05, 0.02, -0.1), soadyn::Vec3<double>(0.1, 0.0, 0.03), 30.0, 0.5,
                           b % 8 == 1 ? &rest : nullptr);
  model.add_point_spring("jounce_stop", model.body_names[5], "world", soadyn::Vec3<double>::Zero(),
                         soadyn::Vec3<double>(0.2, 0.1, 0.0), 0.0, 1.0, nullptr, {0.1, 0.4, 0.6, 0.8},
                         {-20.0, 0.0, 0.0, 200.0});
  std::printf("force elements: %d joint springs, %zu point springs\n", springs, model.force_elements.point_springs.size());
  return model;
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_force_elements_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = sprung_model();
  soadyn::Data data(model);
  const Eigen::Index nv = model.nv;
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 900 + k));
  Eigen::VectorXd tau(nv), qdd(nv), u(nv), h(nv);
  long failed = 0;
  double worst = 0.0, energy = 0.0;

  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    bool ok = soadyn::inverse_dynamics<double>(model, data, s.q, s.v, s.u, s.f_ext.data()).ok();
    tau = data.tau;
    ok = ok && soadyn::forward_dynamics<double>(model, data, s.q, s.v, tau, s.f_ext.data()).ok();
    worst = std::max(worst, relative(data.qdd, s.u));
    ok = ok && soadyn::bias_forces<double>(model, data, s.q, s.v).ok();
    h = data.tau;
    model.set_prescribed(1, call % 2 == 0);  // a flag flip needs no rebuild
    model.set_prescribed(3, true);
    for (Eigen::Index k = 0; k < nv; ++k) u[k] = model.is_prescribed(static_cast<int>(k)) ? s.u[k] : tau[k];
    ok = ok && soadyn::hybrid_dynamics<double>(model, data, s.q, s.v, u, s.f_ext.data()).ok();
    worst = std::max(worst, relative(data.qdd, s.u));
    worst = std::max(worst, relative(data.tau, tau));
    model.set_prescribed(1, false);
    model.set_prescribed(3, false);
    const double potential = soadyn::potential_energy<double>(model, data, s.q);
    double kinetic_together = 0, potential_together = 0;  // the springs' potential from one sweep, bit for bit
    soadyn::mechanical_energy<double>(model, data, s.q, s.v, kinetic_together, potential_together);
    energy += potential + soadyn::force_element_dissipation<double>(model, data, s.q, s.v);
    if (!ok || !h.allFinite() || potential_together != potential) ++failed;
  }
  const AllocationCounts counts = disarm_counter();
  std::printf("calls: %d of each; failed statuses: %ld\n", kCalls, failed);
  std::printf("identities: max relative error %.3g (tolerance %.0e)\n", worst, kTolerance);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);

  soadyn::Simulator sim(model, 1e-3);
  sim.set_state(states[0].q, Eigen::VectorXd::Zero(nv));
  long failed_steps = 0;
  arm_counter();
  for (int step = 0; step < kCalls; ++step)
    if (!sim.step().ok()) ++failed_steps;
  const AllocationCounts sim_counts = disarm_counter();
  std::printf("simulator: %d rk4 steps, %ld allocations, %ld frees, %ld failed statuses\n", kCalls,
              sim_counts.allocations(), sim_counts.frees, failed_steps);

  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0 && worst <= kTolerance &&
                    std::isfinite(energy) && sim_counts.allocations() == 0 && sim_counts.frees == 0 &&
                    failed_steps == 0;
  std::printf("test_force_elements_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
