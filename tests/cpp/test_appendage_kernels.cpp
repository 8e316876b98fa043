// The flexible appendages' step kernels (sweeps/appendage_update.hpp)
// against each other and against the elimination of the modal DOFs from the
// body's full mass matrix.
//
// Eight threads first make the process's first hybrid_dynamics calls on the
// cassini scene at once (the kernel is chosen by whichever gets there
// first); each result must equal the single-thread one bit for bit. Then,
// for every mode count from 1 to 7 (each fixed count's compiled step and the
// generic one beyond max_fixed_appendage_modes), a boom clamped to a free bus
// with K and C dense (coupled modes) takes 20 random states, with and without
// an external wrench, and every kernel runs the step on it:
//   - the chosen kernel's outputs must be those of the step the sweeps call
//     (detail::compiled_appendage_update), bit for bit;
//   - every kernel must agree with the baseline to 1e-14 of each output's
//     largest entry (fused multiply-adds round differently);
//   - P^ and G' must match M_VV - M_Ve M_ee^-1 M_eV and M_ee^-1 M_eV formed
//     from FlexibleBody::augmented_mass_matrix with Eigen's LDLT, to 1e-13.
#include <cstdio>
#include <string>
#include <vector>

#include "failure_count.hpp"
#include "random_tree.hpp"
#include "threads_at_once.hpp"
#include "soadyn/sweeps/appendage_update.hpp"
#include "soadyn/soadyn.hpp"
#include "soadyn_scenes/scenes.hpp"

using soadyn_test::check;
using soadyn_test::failures;

namespace {

constexpr double kKernelTolerance = 1e-14;     // kernel vs baseline, of each output's largest entry
constexpr double kEliminationTolerance = 1e-13;  // vs the full mass matrix's elimination
constexpr int kStates = 20;
constexpr int kMaxModes = 7;

// A boom with its first `modes` modes (of a cantilever's eight), their
// stiffness and damping coupled by a positive semidefinite rank-one term.
soadyn::FlexibleBody boom_with_modes(int modes) {
  soadyn::FlexibleBodyDescription<double> full = soadyn::cantilever_beam<double>(6.0, 900.0, 1.5, 4, 24).description();
  soadyn::FlexibleBodyDescription<double> d;
  for (const soadyn::FlexibleNode<double>& node : full.nodes) {
    soadyn::FlexibleNode<double> cut = node;
    cut.mode_shape = node.mode_shape.leftCols(modes);
    d.nodes.push_back(cut);
  }
  const Eigen::VectorXd coupling = Eigen::VectorXd::LinSpaced(modes, 0.3, 1.1);
  d.stiffness = full.stiffness.topLeftCorner(modes, modes) + 0.05 * coupling * coupling.transpose();
  d.damping = 0.002 * d.stiffness + 0.01 * coupling * coupling.transpose();
  return soadyn::FlexibleBody(d);
}

soadyn::Model bus_with_boom(int modes) {
  soadyn::Model m;
  m.add_body("bus", -1, soadyn::FreeJoint<double>{}, soadyn::Transform<double>(), 800.0, Eigen::Vector3d(0.1, 0, 0.4),
             Eigen::Vector3d(300, 350, 280).asDiagonal());
  soadyn::Transform<double> mount;
  mount.translation = Eigen::Vector3d(0.5, 0.2, 1.0);
  mount.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  m.add_flexible_body("boom", "bus", soadyn::FixedJoint<double>{}, mount, boom_with_modes(modes));
  return m;
}

// What a step leaves: P^, z^, b_V - f_ext, G' and nu.
struct StepOutputs {
  soadyn::Mat6<double> P;
  soadyn::Vec6<double> z, bias;
  Eigen::MatrixXd gain_transpose;
  Eigen::VectorXd innovation;
};

StepOutputs run_step(soadyn::AppendageUpdateFunction<double>* step, const soadyn::Model& m, soadyn::Data& d,
                     std::size_t i, const soadyn_test::State& s, const soadyn::Vec6<double>& V,
                     const soadyn::Vec6<double>* external) {
  StepOutputs out;
  const soadyn::ModalIntegrals<double>& mi = m.flexible_body(static_cast<int>(i)).modal_integrals();
  step(m, d, i, mi, s.q.data(), s.v.data(), s.u.data(), external, V, out.P, out.z);
  const soadyn::FlexibleBodyData<double>& fd = d.sweep.flexible[static_cast<std::size_t>(m.flexible_index[i])];
  out.bias = d.sweep.body_bias_force[i];
  out.gain_transpose = fd.gain_transpose;
  out.innovation = fd.innovation;
  return out;
}

bool identical(const StepOutputs& a, const StepOutputs& b) {
  return a.P == b.P && a.z == b.z && a.bias == b.bias && a.gain_transpose == b.gain_transpose &&
         a.innovation == b.innovation;
}

// The largest difference of a and b relative to b's largest entry.
template <class A, class B>
double relative_difference(const A& a, const B& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return (a - b).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

double kernel_difference(const StepOutputs& a, const StepOutputs& b) {
  return std::max({relative_difference(a.P, b.P), relative_difference(a.z, b.z), relative_difference(a.bias, b.bias),
                   relative_difference(a.gain_transpose, b.gain_transpose),
                   relative_difference(a.innovation, b.innovation)});
}

// P^ and G' from the body's full mass matrix M(eta), by Eigen's LDLT.
double elimination_difference(const soadyn::Model& m, std::size_t i, const soadyn_test::State& s, const StepOutputs& out) {
  const int body = static_cast<int>(i);
  const int n = m.n_modes[i];
  const Eigen::MatrixXd M =
      m.flexible_body(body).augmented_mass_matrix(s.q.segment(m.modal_q_index(body), n));
  const Eigen::MatrixXd gain_transpose = M.bottomRightCorner(n, n).ldlt().solve(M.bottomLeftCorner(n, 6));
  const Eigen::MatrixXd P = M.topLeftCorner(6, 6) - M.topRightCorner(6, n) * gain_transpose;
  return std::max(relative_difference(out.P, P), relative_difference(out.gain_transpose, gain_transpose));
}

struct Worst {
  double kernel_vs_baseline = 0, vs_elimination = 0;
  bool kernels_differ_somewhere = false;
};

void compare_kernels(int modes, Worst& worst) {
  const soadyn::Model m = bus_with_boom(modes);
  soadyn::Data d(m);
  const std::size_t boom = 1;
  check(m.n_modes[boom] == modes, std::to_string(modes) + " modes: the boom's mode count");
  const std::vector<soadyn::detail::AppendageKernel> kernels = soadyn::detail::available_appendage_kernels();
  soadyn_test::Random rng(500 + static_cast<std::uint64_t>(modes));
  for (int k = 0; k < kStates; ++k) {
    const soadyn_test::State s = soadyn_test::random_state(m, 40 + static_cast<std::uint64_t>(k));
    const soadyn::Vec6<double> V = rng.uniform_vector(6, 2.0);
    const soadyn::Vec6<double> wrench = rng.uniform_vector(6, 5.0);
    for (const soadyn::Vec6<double>* external : {static_cast<const soadyn::Vec6<double>*>(nullptr), &wrench}) {
      const std::string at = std::to_string(modes) + " modes, state " + std::to_string(k) +
                             (external ? ", with a wrench" : "");
      const StepOutputs dispatched = run_step(soadyn::detail::compiled_appendage_update, m, d, boom, s, V, external);
      const StepOutputs baseline = run_step(kernels.back().run, m, d, boom, s, V, external);
      for (const soadyn::detail::AppendageKernel& kernel : kernels) {
        const std::string who = at + ", kernel " + kernel.name;
        const StepOutputs out = run_step(kernel.run, m, d, boom, s, V, external);
        if (&kernel == &kernels.front()) check(identical(out, dispatched), who + ": not the sweeps' step");
        const double vs_baseline = kernel_difference(out, baseline);
        const double vs_elimination = elimination_difference(m, boom, s, out);
        check(vs_baseline <= kKernelTolerance, who + ": off the baseline by " + std::to_string(vs_baseline));
        check(vs_elimination <= kEliminationTolerance,
              who + ": off the full elimination by " + std::to_string(vs_elimination));
        worst.kernel_vs_baseline = std::max(worst.kernel_vs_baseline, vs_baseline);
        worst.vs_elimination = std::max(worst.vs_elimination, vs_elimination);
        worst.kernels_differ_somewhere = worst.kernels_differ_somewhere || !identical(out, baseline);
      }
    }
  }
}

// Eight threads make the process's first dynamics calls at once, each on its
// own Data, 200 times; every qdd must equal the one a single thread forms
// afterwards, bit for bit. Returns the number of threads whose qdd differs.
int first_calls_from_threads(const soadyn::Model& m) {
  constexpr int kThreads = 8, kCalls = 200;
  const soadyn_test::State s = soadyn_test::random_state(m, 7);
  std::vector<soadyn::Data> data(kThreads, soadyn::Data(m));
  const int failed = soadyn_test::calls_from_threads_at_once(kThreads, kCalls, [&](int t) {
    return soadyn::hybrid_dynamics<double>(m, data[static_cast<std::size_t>(t)], s.q, s.v, s.u).ok();
  });
  soadyn::Data reference(m);
  check(soadyn::hybrid_dynamics<double>(m, reference, s.q, s.v, s.u).ok(), "the single-thread hybrid_dynamics failed");
  int differing = failed;
  for (const soadyn::Data& d : data) differing += d.qdd != reference.qdd;
  check(differing == 0, "a thread's qdd differs from the single-thread qdd, or a call failed");
  return differing;
}

}  // namespace

int main() {
  const soadyn::Model cassini = soadyn::cassini_model<double>();
  std::printf("threads: 8 threads from the process's first call, 200 cassini dynamics each, %d differ\n",
              first_calls_from_threads(cassini));  // first: no dynamics call may precede it
  Worst worst;
  for (int modes = 1; modes <= kMaxModes; ++modes) compare_kernels(modes, worst);
  std::string names;
  for (const soadyn::detail::AppendageKernel& k : soadyn::detail::available_appendage_kernels())
    names += std::string(names.empty() ? "" : ", ") + k.name;
  std::printf("kernels: %s (chosen: %s)\n", names.c_str(), soadyn::appendage_kernel());
  std::printf("max relative difference: %.2e between kernels (tolerance %.0e), %.2e from the full elimination "
              "(tolerance %.0e), kernels differ bit for bit: %s\n",
              worst.kernel_vs_baseline, kKernelTolerance, worst.vs_elimination, kEliminationTolerance,
              worst.kernels_differ_somewhere ? "yes" : "no");
  if (failures == 0)
    std::printf("test_appendage_kernels: PASS: mode counts 1 to %d, %d states each\n", kMaxModes, kStates);
  return failures == 0 ? 0 : 1;
}
