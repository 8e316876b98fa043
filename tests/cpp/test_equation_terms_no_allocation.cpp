// gravity_forces, external_forces_to_generalized, coriolis_matrix,
// mass_matrix_derivative and christoffel_symbols allocate nothing once Data,
// the EquationTermsWorkspace and the output matrices are built: 10^4 calls on
// a random 20-body tree with every joint kind (free root), counted by the
// allocation counter (allocation_counter.cpp). Each call's result is checked
// against an identity (C v + g = h, Mdot = C + C', sum_k Gamma_k v_k = C), so
// the calls do their work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/algorithms/equation_terms.hpp"
#include "soadyn/soadyn.hpp"

using namespace soadyn_test;

namespace {

constexpr int kCalls = 10000;
constexpr int kStates = 16;
constexpr double kTolerance = 1e-12;

// Arguments are stored matrices (an expression would be evaluated into a heap temporary).
double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_equation_terms_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  const soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  soadyn::Data data(model);
  soadyn::EquationTermsWorkspace<double> workspace(model);
  const Eigen::Index nv = model.nv;
  Eigen::MatrixXd C(nv, nv), Mdot(nv, nv), gamma(nv, nv * nv), contracted(nv, nv);
  Eigen::MatrixXd g(nv, 1), h(nv, 1), generalized(nv, 1), cv(nv, 1);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 700 + k));
  long failed = 0, checked = 0, christoffel_calls = 0;
  double worst = 0.0;

  arm_counter();
  for (int call = 0; call < kCalls; ++call) {
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    bool ok = soadyn::gravity_forces<double>(model, data, s.q).ok();
    g = data.tau;
    ok = ok && soadyn::external_forces_to_generalized<double>(model, data, s.q, s.f_ext.data()).ok();
    generalized = data.tau;
    ok = ok && soadyn::mass_matrix_derivative<double>(model, data, workspace, s.q, s.v, C, Mdot).ok();
    ok = ok && soadyn::bias_forces<double>(model, data, s.q, s.v).ok();
    h = data.tau;
    cv.noalias() = C * s.v;
    cv += g;
    worst = std::max(worst, relative(cv, h));
    ok = ok && soadyn::coriolis_matrix<double>(model, data, workspace, s.q, s.v, C).ok();
    contracted = C + C.transpose();  // (no aliasing: a separate matrix)
    worst = std::max(worst, relative(contracted, Mdot));
    if (call % 100 == 0) {
      ++christoffel_calls;
      ok = ok && soadyn::christoffel_symbols<double>(model, data, workspace, s.q, gamma).ok();
      contracted.setZero();
      for (Eigen::Index k = 0; k < nv; ++k) contracted += s.v[k] * gamma.middleCols(k * nv, nv);
      worst = std::max(worst, relative(contracted, C));
    }
    ++checked;
    if (!ok || !generalized.allFinite()) ++failed;
  }
  const AllocationCounts counts = disarm_counter();

  std::printf("bodies: %d, nv = %d\n", model.nbodies(), model.nv);
  std::printf("calls: %d of each term, %ld christoffel_symbols; failed statuses: %ld\n", kCalls, christoffel_calls,
              failed);
  std::printf("identities: %ld states, max relative error %.3g (tolerance %.0e)\n", checked, worst, kTolerance);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0 && worst <= kTolerance;
  std::printf("test_equation_terms_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
