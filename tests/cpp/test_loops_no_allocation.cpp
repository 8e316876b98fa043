// constrained_dynamics (with and without joint wrenches), loop_joint_wrenches,
// loop_residual and loop_rank allocate nothing once Data is built: 10^4 calls
// on a random tree with one loop of every kind, with random prescribed/regular
// flag changes between calls, counted by the allocation counter
// (allocation_counter.cpp). Random flags often prescribe more DOFs than the
// loops leave free, so many calls are redundantly actuated (the minimum-norm
// actuator forces) and some have closure accelerations that cannot be met
// (inconsistent_loop_equations, with the least-squares answer): both paths
// run in full and are counted, on a 60-body rigid tree (the articulated-body
// response), on a 20-body one, the four-bar and the Delta robot (the
// mass-matrix path in tree frames), and on the 20-body tree with flexible
// bodies added (the mass-matrix path in body frames). Before counting, a distance loop added
// without a length takes the distance between its frames at the neutral
// configuration, or at a given one.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>
#include "soadyn/soadyn.hpp"
#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn_scenes/scenes.hpp"

using namespace soadyn_test;

namespace {

constexpr int kCalls = 10000;
constexpr int kStates = 16;

soadyn::Transform<double> offset(double x, double y, double z) {
  soadyn::Transform<double> X;
  X.translation << x, y, z;
  X.rotation = soadyn::axis_angle_rotation<double>(soadyn::Vec3<double>(0.6, 0.0, 0.8), 0.3 * (x + y + z));
  return X;
}

void add_every_kind_of_loop(soadyn::Model& m) {
  using K = soadyn::LoopKind;
  const auto& n = m.body_names;
  m.add_loop("point", n[19], n[3], K::point, offset(0.1, 0, 0), offset(0, 0.2, 0));
  m.add_loop("revolute", n[15], "", K::revolute, offset(0, 0.1, 0), offset(0.3, 0.1, 0.2));
  m.add_loop("prismatic", n[10], n[5], K::prismatic, offset(0, 0, 0.1), offset(0.1, 0.1, 0));
  m.add_loop("weld", n[7], n[12], K::weld, offset(0.2, 0, 0), offset(0, 0, 0.2));
  m.add_loop("distance", n[18], n[0], K::distance, offset(0.1, 0.1, 0), offset(-0.1, 0, 0.1), 0.5);
}

// A distance loop without a length measures it: at the neutral configuration,
// or at the configuration given. Returns the number of mismatches.
int check_measured_distance_lengths(const soadyn::Model& tree) {
  soadyn::Model m = tree;
  const auto& n = m.body_names;
  const soadyn::Transform<double> A = offset(0.1, 0.1, 0), B = offset(-0.1, 0, 0.1);
  soadyn::Data d(m);
  int failures = 0;
  Eigen::VectorXd q(m.nq);
  soadyn::neutral_configuration<double>(m, q);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) soadyn::random_configuration<double>(m, 5, q);
    const int l = m.add_loop(pass ? "rod at q" : "rod", n[18], n[0], soadyn::LoopKind::distance, A, B, 0.0,
                             pass ? q.data() : nullptr);
    soadyn::forward_kinematics<double>(m, d, q.data(), nullptr);
    const double expected = (d.pose_in_world[18].apply_point(A.translation) - d.pose_in_world[0].apply_point(B.translation)).norm();
    const double length = m.loops[static_cast<std::size_t>(l)].length;
    std::printf("distance loop without length (%s): %.15g, frames %.15g apart\n", pass ? "at q" : "neutral", length,
                expected);
    if (!(std::abs(length - expected) <= 1e-14 * expected)) ++failures;
  }
  return failures;
}

// 10^4 counted calls on `model` (flags flipped at random between calls);
// prints the summary lines under `label`. Returns whether nothing was
// allocated and no call failed.
bool run_counted(const char* label, soadyn::Model model) {
  soadyn::Data data(model);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 300 + k));
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> dof(0, model.nv - 1), flag(0, 1);
  long failed = 0, inconsistent = 0, redundant = 0, wrench_calls = 0, rank_sum = 0;

  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    const int k = dof(rng);
    const bool prescribe = flag(rng) != 0;
    if (!model.modal_dof[static_cast<std::size_t>(k)]) model.set_prescribed(k, prescribe);  // modal DOFs stay regular
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    const double* f_ext = call % 2 ? s.f_ext.data() : nullptr;
    const bool wrenches = call % 3 == 0;
    const soadyn::Status status =
        soadyn::constrained_dynamics(model, data, s.q, s.v, s.u, f_ext, soadyn::DynamicsOutputs{wrenches});
    if (status.code == soadyn::StatusCode::inconsistent_loop_equations)
      ++inconsistent;
    else if (!status.ok())
      ++failed;
    if (data.loops.delassus_solve.rank < model.nloop_equations && model.n_prescribed > 0) ++redundant;
    if (wrenches) ++wrench_calls;
    if (call % 5 == 0) {  // the loop wrenches just found, fed back at the accelerations found
      ++wrench_calls;
      if (!soadyn::loop_joint_wrenches<double>(model, data, s.q, s.v, data.qdd, data.loops.wrench[0].data(), f_ext).ok())
        ++failed;
    }
    if (call % 10 == 0) {
      soadyn::loop_residual(model, data, s.q, s.v.data());
      rank_sum += soadyn::loop_rank(model, data, s.q);
    }
  }
  const AllocationCounts counts = disarm_counter();

  std::printf("%s: %d bodies (%zu flexible)\n", label, model.nbodies(), model.flexible_bodies.size());
  std::printf("loops: %d, equations: %d, nv = %d, mean rank %.2f\n", model.nloops(), model.nloop_equations, model.nv,
              static_cast<double>(rank_sum) / (kCalls / 10));
  std::printf("calls: %d constrained_dynamics; failed statuses: %ld\n", kCalls, failed);
  std::printf("joint wrench calls: %ld; rank-deficient Delassus with prescribed DOFs: %ld; inconsistent loop "
              "equations (least-squares answer): %ld\n", wrench_calls, redundant, inconsistent);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  return counts.allocations() == 0 && counts.frees == 0 && failed == 0;
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_loops_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  add_every_kind_of_loop(model);
  const int length_failures = check_measured_distance_lengths(model);
  // The loop solvers (Model::loops_through_mass_matrix): a 60-body rigid
  // tree with the same loops takes the articulated-body response
  // (articulated_loop_response.hxx); the 20-body tree, the four-bar and the
  // Delta robot (scenes.hpp) the mass matrix in tree frames; with flexible
  // bodies (not in the loops), the mass matrix in body frames.
  soadyn::Model large = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 60));
  add_every_kind_of_loop(large);
  soadyn::Model flexible = model;
  soadyn_test::add_flexible_bodies(flexible);
  const soadyn::Model four_bar = soadyn::four_bar_model<double>(soadyn::LoopKind::point);
  const soadyn::Model delta = soadyn::delta_robot_model<double>();
  const auto solver = [](const soadyn::Model& m) { return m.loops_through_mass_matrix() ? "mass matrix" : "articulated"; };
  std::printf("loop solvers: 60-body tree %s, 20-body tree %s, four-bar %s, Delta robot %s\n", solver(large),
              solver(model), solver(four_bar), solver(delta));
  const bool solvers_as_claimed = !large.loops_through_mass_matrix() && model.loops_through_mass_matrix() &&
                                  four_bar.loops_through_mass_matrix() && delta.loops_through_mass_matrix();
  const bool large_ok = run_counted("60-body rigid tree", large);
  const bool rigid_ok = run_counted("20-body rigid tree", model);
  const bool flexible_ok = run_counted("20-body tree with flexible bodies", flexible);
  const bool four_bar_ok = run_counted("four-bar", four_bar);
  const bool delta_ok = run_counted("Delta robot", delta);
  const bool pass = solvers_as_claimed && large_ok && rigid_ok && flexible_ok && four_bar_ok && delta_ok &&
                    length_failures == 0;
  std::printf("test_loops_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
