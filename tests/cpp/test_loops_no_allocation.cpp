// constrained_dynamics, loop_residual and loop_rank allocate nothing once
// Data is built: 10^4 calls on a random tree with one loop of every kind,
// with random prescribed/regular flag changes between calls, counted by the
// allocation counter (allocation_counter.cpp).
#include <cstdio>
#include <random>
#include <vector>
#include "soadyn/soadyn.hpp"
#include "allocation_counter.hpp"
#include "random_tree.hpp"

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

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_loops_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  add_every_kind_of_loop(model);
  soadyn::Data data(model);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 300 + k));
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> dof(0, model.nv - 1), flag(0, 1);
  long failed = 0, rank_sum = 0;

  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    model.set_prescribed(dof(rng), flag(rng) != 0);
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    const double* f_ext = call % 2 ? s.f_ext.data() : nullptr;
    if (!soadyn::constrained_dynamics(model, data, s.q, s.v, s.u, f_ext).ok()) ++failed;
    if (call % 10 == 0) {
      soadyn::loop_residual(model, data, s.q, s.v.data());
      rank_sum += soadyn::loop_rank(model, data, s.q);
    }
  }
  const AllocationCounts counts = disarm_counter();

  std::printf("loops: %d, equations: %d, nv = %d, mean rank %.2f\n", model.nloops(), model.nloop_equations, model.nv,
              static_cast<double>(rank_sum) / (kCalls / 10));
  std::printf("calls: %d constrained_dynamics; failed statuses: %ld\n", kCalls, failed);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0;
  std::printf("test_loops_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
