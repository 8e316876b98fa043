// The float instantiation agrees with the double one.
//
// One 10-body chain with mixed joint types and a free root, and the same chain
// with flexible bodies added, are built as ModelTpl<double> and
// ModelTpl<float> from the same double-precision spec.
// At several random states (double, then rounded to float) every algorithm
// runs in both precisions and each output must satisfy
//   max|f - d| <= 1e-4 * max(1, max|d|).
// The parameters are well conditioned (masses ~1 kg, links ~0.3 m, states
// ~1), so the tolerance measures float rounding, not an ill-posed problem.
// The flexible bodies' light, stiff modes raise the mass matrix's condition
// number: their accelerations lose about five times more digits than the
// rigid chain's (M and h themselves agree to ~1e-6 in both models).
// Cassini (a free bus with two booms of four modes welded to it: the
// appendage step compiled for four modes, in float too) is compared the same
// way.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>
#include "float_error_tracker.hpp"
#include "random_tree.hpp"
#include "soadyn_scenes/scenes.hpp"

namespace {

using soadyn_test::JointKind;

constexpr double kTolerance = 1e-4;
constexpr int kStates = 20;

using ErrorTracker = soadyn_test::FloatErrorTracker;

// Every output of every algorithm at one state, in scalar S.
template <class S>
struct Results {
  bool all_ok = true;
  soadyn::VecX<S> hybrid_qdd, hybrid_tau, hybrid_hinge_forces, forward_qdd, inverse_tau, bias, mass_matrix_flat;
};

// Hinge wrenches of every body as one vector.
template <class S>
soadyn::VecX<S> flatten(const soadyn::aligned_vector<soadyn::Vec6<S>>& wrenches) {
  soadyn::VecX<S> out(6 * static_cast<Eigen::Index>(wrenches.size()));
  for (std::size_t i = 0; i < wrenches.size(); ++i)
    out.template segment<6>(6 * static_cast<Eigen::Index>(i)) = wrenches[i];
  return out;
}

// Hybrid dynamics under `mask` (with external wrenches and hinge forces),
// forward dynamics with tau = u, inverse dynamics with qdd = u, bias forces
// and the mass matrix.
template <class S>
Results<S> run_algorithms(soadyn::ModelTpl<S>& model, soadyn::DataTpl<S>& data,
                          const soadyn_test::StateTpl<S>& s, const std::vector<bool>& mask) {
  Results<S> r;
  soadyn_test::apply_mask(model, mask);
  const soadyn::DynamicsOutputs with_hinge_forces{true};
  r.all_ok &= soadyn::hybrid_dynamics<S>(model, data, s.q, s.v, s.u, s.f_ext.data(), with_hinge_forces).ok();
  r.hybrid_qdd = data.qdd;
  r.hybrid_tau = data.tau;
  r.hybrid_hinge_forces = flatten(data.hinge_force);
  r.all_ok &= soadyn::forward_dynamics<S>(model, data, s.q, s.v, s.u, s.f_ext.data()).ok();
  r.forward_qdd = data.qdd;
  soadyn::inverse_dynamics<S>(model, data, s.q, s.v, s.u, s.f_ext.data());
  r.inverse_tau = data.tau;
  soadyn::bias_forces<S>(model, data, s.q, s.v);
  r.bias = data.tau;
  soadyn::mass_matrix<S>(model, data, s.q);
  r.mass_matrix_flat = data.mass_matrix.reshaped();
  return r;
}

void compare(const Results<float>& f, const Results<double>& d, ErrorTracker& errors) {
  if (!f.all_ok || !d.all_ok) return errors.fail(std::string(f.all_ok ? "double run" : "float run") + " returned a failed Status");
  errors.compare("hybrid_dynamics qdd", f.hybrid_qdd, d.hybrid_qdd);
  errors.compare("hybrid_dynamics tau", f.hybrid_tau, d.hybrid_tau);
  errors.compare("hybrid_dynamics hinge forces", f.hybrid_hinge_forces, d.hybrid_hinge_forces);
  errors.compare("forward_dynamics qdd", f.forward_qdd, d.forward_qdd);
  errors.compare("inverse_dynamics tau", f.inverse_tau, d.inverse_tau);
  errors.compare("bias_forces", f.bias, d.bias);
  errors.compare("mass_matrix", f.mass_matrix_flat, d.mass_matrix_flat);
}

// Every algorithm at kStates random states of `model_d` and its float twin.
void compare_models(const soadyn::Model& model_d_in, const soadyn::ModelF& model_f_in, ErrorTracker& errors) {
  soadyn::Model model_d = model_d_in;
  soadyn::ModelF model_f = model_f_in;
  soadyn::Data data_d(model_d);
  soadyn::DataF data_f(model_f);
  std::printf("model: %d bodies (%zu flexible), nq = %d, nv = %d\n", model_d.nbodies(), model_d.flexible_bodies.size(),
              model_d.nq, model_d.nv);
  soadyn_test::Random mask_rng(5);
  for (int k = 0; k < kStates; ++k) {
    const soadyn_test::State state = soadyn_test::random_state(model_d, 300 + k);
    const std::vector<bool> mask = soadyn_test::random_mask(model_d.nv, mask_rng, 0.5);
    compare(run_algorithms(model_f, data_f, state.cast<float>(), mask),
            run_algorithms(model_d, data_d, state, mask), errors);
  }
}

}  // namespace

int main() {
  const std::vector<JointKind> kinds = {JointKind::free,      JointKind::revolute, JointKind::prismatic,
                                        JointKind::helical,   JointKind::universal, JointKind::spherical,
                                        JointKind::revolute,  JointKind::cylindrical, JointKind::planar,
                                        JointKind::revolute};
  const soadyn_test::TreeSpec spec = soadyn_test::chain_spec(kinds, 11);
  soadyn::Model model_d = soadyn_test::build_model<double>(spec);
  soadyn::ModelF model_f = soadyn_test::build_model<float>(spec);
  ErrorTracker rigid(kTolerance), flexible(kTolerance);
  compare_models(model_d, model_f, rigid);
  rigid.print();
  soadyn_test::add_flexible_bodies(model_d);
  soadyn_test::add_flexible_bodies(model_f);
  compare_models(model_d, model_f, flexible);
  flexible.print();
  ErrorTracker appendages(kTolerance);
  compare_models(soadyn::cassini_model<double>(), soadyn::cassini_model<float>(), appendages);
  appendages.print();
  const bool pass = rigid.failures() == 0 && flexible.failures() == 0 && appendages.failures() == 0;
  std::printf("test_float_vs_double: %s: max relative error %.3e rigid, %.3e with flexible bodies, %.3e on cassini "
              "(tolerance %.0e), %d states per model, %d failures\n",
              pass ? "PASS" : "FAIL", rigid.max_error(), flexible.max_error(), appendages.max_error(), kTolerance,
              kStates, rigid.failures() + flexible.failures() + appendages.failures());
  return pass ? 0 : 1;
}
