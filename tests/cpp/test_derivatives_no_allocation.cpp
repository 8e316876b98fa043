// inverse_dynamics_derivatives and dynamics_derivatives allocate nothing once
// Data and the DynamicsDerivatives workspace are built, nor do linearize and
// linearize_step (rk4, euler) once a Linearization is: 2000 calls of each
// derivative function and 200 of each linearization on a
// random 20-body tree with every joint kind (free root), alternating the
// all-regular model with a mixed prescribed/regular mask (flags flipped
// between calls, itself allocation free), counted by the allocation counter
// (allocation_counter.cpp). Each result is checked against an identity of
// the partitioned equations (M dqdd/dq = -dID/dq and M dqdd/du = I on regular
// rows of an all-regular model; dtau/du = I on regular rows), so the calls do
// their work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/linearization.hpp"
#include "soadyn/soadyn.hpp"

using namespace soadyn_test;

namespace {

constexpr int kCalls = 2000;
constexpr int kStates = 16;
constexpr double kTolerance = 1e-11;

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1.0);
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_derivatives_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2025, 20));
  soadyn::Data data(model);
  soadyn::DynamicsDerivatives derivatives(model);
  soadyn::Linearization linearization(model);
  const Eigen::Index nv = model.nv;
  Eigen::MatrixXd product(nv, nv), identity = Eigen::MatrixXd::Identity(nv, nv), negated(nv, nv);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 900 + k));
  long failed = 0;
  double worst = 0.0;

  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    const bool mixed = call % 2 == 1;
    for (int k = 0; k < model.nv; ++k) model.set_prescribed(k, mixed && k % 3 == 0);
    bool ok = soadyn::inverse_dynamics_derivatives<double>(model, data, derivatives, s.q, s.v, s.u,
                                                           s.f_ext.data()).ok();
    ok = ok && soadyn::dynamics_derivatives<double>(model, data, derivatives, s.q, s.v, s.u, s.f_ext.data()).ok();
    if (!mixed) {
      product.noalias() = data.mass_matrix.lazyProduct(derivatives.dqdd_dq);
      negated = -derivatives.inverse_dq;
      worst = std::max(worst, relative(product, negated));
      product.noalias() = data.mass_matrix.lazyProduct(derivatives.dqdd_du);
      worst = std::max(worst, relative(product, identity));
    }
    for (int k = 0; k < model.nv; ++k)
      if (!model.is_prescribed(k) && derivatives.dtau_du(k, k) != 1.0) ok = false;
    if (call % 10 == 0) {  // linearizations: continuous, one rk4 step, one euler step
      ok = ok && soadyn::linearize<double>(model, data, linearization, s.q, s.v, s.u).ok();
      ok = ok && linearization.A.topRightCorner(nv, nv).isIdentity(0.0);
      ok = ok && soadyn::linearize_step<double>(model, data, linearization, s.q, s.v, s.u, 1e-3,
                                                soadyn::Integrator::rk4).ok();
      ok = ok && soadyn::linearize_step<double>(model, data, linearization, s.q, s.v, s.u, 1e-3,
                                                soadyn::Integrator::semi_implicit_euler).ok();
      ok = ok && linearization.A.allFinite() && linearization.B.allFinite();
    }
    if (!ok) ++failed;
  }
  const AllocationCounts counts = disarm_counter();

  std::printf("bodies: %d, nv = %d\n", model.nbodies(), model.nv);
  std::printf("calls: %d of each; failed statuses or checks: %ld\n", kCalls, failed);
  std::printf("identities: max relative error %.3g (tolerance %.0e)\n", worst, kTolerance);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0 && worst <= kTolerance;
  std::printf("test_derivatives_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
