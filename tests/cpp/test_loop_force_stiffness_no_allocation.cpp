// loop_force_stiffness (d(C(q)' nu)/dq, called once per Newton iteration of a
// static equilibrium) allocates nothing once Data and the output matrix are
// built: 2000 calls on a random 20-body tree (every joint kind, free root)
// with one loop of every kind, to the world and between bodies, counted by the
// allocation counter (allocation_counter.cpp). Each result is compared with
// central differences of C(q)' nu in the tangent space (computed before the
// counter is armed), so the calls do their work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>
#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/analysis/loop_force_stiffness.hpp"
#include "soadyn/soadyn.hpp"

using namespace soadyn_test;

namespace {

constexpr int kCalls = 2000;
constexpr int kStates = 8;
constexpr double kTolerance = 1e-8;  // central differences, step 1e-6: truncation and rounding ~1e-10

soadyn::Transform<double> placement(double x, double y, double z) {
  soadyn::Transform<double> X;
  X.translation << x, y, z;
  X.rotation = soadyn::axis_angle_rotation<double>(soadyn::Vec3<double>(0.0, 0.6, 0.8), 0.7 * (x - y + z));
  return X;
}

void add_loops(soadyn::Model& m) {
  using K = soadyn::LoopKind;
  const auto& n = m.body_names;
  m.add_loop("point", n[17], "", K::point, placement(0.1, 0, 0), placement(0, 0.2, 0));
  m.add_loop("revolute", n[14], n[2], K::revolute, placement(0, 0.1, 0), placement(0.3, 0.1, 0.2));
  m.add_loop("prismatic", n[11], "", K::prismatic, placement(0, 0, 0.1), placement(0.1, 0.1, 0));
  m.add_loop("weld", n[8], n[13], K::weld, placement(0.2, 0, 0), placement(0, 0, 0.2));
  m.add_loop("distance", n[19], n[1], K::distance, placement(0.1, 0.1, 0), placement(-0.1, 0, 0.1), 0.5);
}

// d(C' nu)/dq by central differences along integrate(q, +-h e_k).
Eigen::MatrixXd by_differences(const soadyn::Model& m, soadyn::Data& d, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& nu) {
  const double h = 1e-6;
  Eigen::MatrixXd K(m.nv, m.nv);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(m.nv), qp(m.nq), qm(m.nq), plus(m.nv);
  for (int k = 0; k < m.nv; ++k) {
    e.setZero();
    e[k] = 1.0;
    soadyn::integrate<double>(m, q, e, h, qp);
    soadyn::integrate<double>(m, q, e, -h, qm);
    soadyn::loop_residual<double>(m, d, qp, nullptr);
    plus = d.loops.jacobian.transpose() * nu;
    soadyn::loop_residual<double>(m, d, qm, nullptr);
    K.col(k) = (plus - d.loops.jacobian.transpose() * nu) / (2 * h);
  }
  return K;
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_loop_force_stiffness_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2026, 20));
  add_loops(model);
  soadyn::Data data(model);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::vector<Eigen::VectorXd> qs, nus;
  std::vector<Eigen::MatrixXd> references;
  for (int k = 0; k < kStates; ++k) {
    qs.push_back(soadyn_test::random_state(model, 500 + k).q);
    nus.push_back(Eigen::VectorXd::NullaryExpr(model.nloop_equations, [&] { return normal(rng); }));
    references.push_back(by_differences(model, data, qs.back(), nus.back()));
  }
  Eigen::MatrixXd stiffness(model.nv, model.nv);
  long failed = 0;
  double worst = 0.0;
  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    const std::size_t s = static_cast<std::size_t>(call % kStates);
    if (!soadyn::loop_force_stiffness<double>(model, data, qs[s], nus[s], stiffness).ok()) ++failed;
    const double scale = std::max(references[s].cwiseAbs().maxCoeff(), 1.0);
    worst = std::max(worst, (stiffness - references[s]).cwiseAbs().maxCoeff() / scale);
  }
  const AllocationCounts counts = disarm_counter();
  std::printf("bodies: %d, nv = %d, loops: %d (%d equations)\n", model.nbodies(), model.nv,
              static_cast<int>(model.loops.size()), model.nloop_equations);
  std::printf("calls: %d; failed statuses: %ld\n", kCalls, failed);
  std::printf("central differences: max relative error %.3g (tolerance %.0e)\n", worst, kTolerance);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0 && worst <= kTolerance;
  std::printf("test_loop_force_stiffness_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
