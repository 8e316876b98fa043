// The float instantiation of the frame functions (algorithms/frames.hpp)
// agrees with the double one: on a random 20-body tree with every joint type,
// built as ModelTpl<double> and ModelTpl<float> from the same spec, at 16
// random states (double, then rounded to float), the pose, velocity,
// acceleration (spatial and classical), J and dJ/dt of every body in the three
// references and the centre-of-mass Jacobian satisfy
//   max|f - d| <= 1e-4 * max(1, max|d|).
#include <algorithm>
#include <cstdio>
#include "random_tree.hpp"
#include "soadyn/algorithms/frames.hpp"

namespace {

constexpr double kTolerance = 1e-4;
constexpr int kStates = 16;
constexpr soadyn::Reference kReferences[] = {soadyn::Reference::world, soadyn::Reference::local,
                                             soadyn::Reference::local_world_aligned};

struct Worst {
  double error = 0;
  long comparisons = 0, failures = 0;
  template <class F, class D>
  void compare(const F& f, const D& d) {
    const double e = (f.template cast<double>() - d).cwiseAbs().maxCoeff() / std::max(1.0, d.cwiseAbs().maxCoeff());
    error = std::max(error, e);
    ++comparisons;
    if (!(e <= kTolerance)) ++failures;  // NaN fails too
  }
};

// Every frame output of body `body` at one state, in scalar S, stacked as columns.
template <class S>
Eigen::Matrix<S, 6, Eigen::Dynamic> frame_outputs(const soadyn::ModelTpl<S>& m, soadyn::DataTpl<S>& d,
                                                  const soadyn_test::StateTpl<S>& s, int body) {
  const soadyn::FrameLocation<S> f = soadyn::locate_frame(m, body);
  Eigen::Matrix<S, 6, Eigen::Dynamic> out(6, 4 + 3 * (3 + 2 * m.nv));
  Eigen::Index c = 0;
  const soadyn::Transform<S> X = soadyn::frame_pose<S>(m, d, s.q, f);
  out.col(c++) << X.rotation.col(0), X.rotation.col(1);
  out.col(c++) << X.rotation.col(2), X.translation;
  Eigen::Matrix<S, 6, Eigen::Dynamic> J(6, m.nv);
  for (const soadyn::Reference r : kReferences) {
    out.col(c++) = soadyn::frame_velocity<S>(m, d, s.q, s.v, f, r);
    out.col(c++) = soadyn::frame_acceleration<S>(m, d, s.q, s.v, s.u, f, r, false);
    out.col(c++) = soadyn::frame_acceleration<S>(m, d, s.q, s.v, s.u, f, r, true);
    soadyn::frame_jacobian<S>(m, d, s.q, f, r, J);
    out.middleCols(c, m.nv) = J;
    c += m.nv;
    soadyn::frame_jacobian_time_variation<S>(m, d, s.q, s.v, f, r, J);
    out.middleCols(c, m.nv) = J;
    c += m.nv;
  }
  return out.leftCols(c);
}

template <class S>
Eigen::Matrix<S, 3, Eigen::Dynamic> com_jacobian(const soadyn::ModelTpl<S>& m, soadyn::DataTpl<S>& d,
                                                 const soadyn_test::StateTpl<S>& s) {
  soadyn::SubtreeMassWorkspace<S> workspace(m);
  Eigen::Matrix<S, 3, Eigen::Dynamic> J(3, m.nv);
  soadyn::center_of_mass_jacobian<S>(m, d, s.q, workspace, J);
  return J;
}

}  // namespace

int main() {
  const soadyn_test::TreeSpec spec = soadyn_test::random_tree_spec(2024, 20);
  const soadyn::Model md = soadyn_test::build_model<double>(spec);
  const soadyn::ModelF mf = soadyn_test::build_model<float>(spec);
  soadyn::Data dd(md);
  soadyn::DataF df(mf);
  Worst worst;
  for (int k = 0; k < kStates; ++k) {
    const soadyn_test::State s = soadyn_test::random_state(md, 500 + k);
    const soadyn_test::StateTpl<float> sf = s.cast<float>();
    for (int body = 0; body < md.nbodies(); ++body)
      worst.compare(frame_outputs<float>(mf, df, sf, body), frame_outputs<double>(md, dd, s, body));
    worst.compare(com_jacobian<float>(mf, df, sf), com_jacobian<double>(md, dd, s));
  }
  const bool pass = worst.failures == 0 && worst.comparisons == kStates * (md.nbodies() + 1);
  std::printf("test_frames_float_vs_double: %s: max relative error %.3e (tolerance 1e-04), %ld comparisons, "
              "%ld failures\n", pass ? "PASS" : "FAIL", worst.error, worst.comparisons, worst.failures);
  return pass ? 0 : 1;
}
