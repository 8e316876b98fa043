// The mass matrix's kernels (algorithms/crba.hpp) against each other and
// against the body-frame composite-body algorithm, and the placement shapes
// the sweeps record (spatial/placement_axes.hpp).
//
// Every kernel this processor can run forms M on three models, 20 random
// configurations each: a random tree with every joint kind, a 7-DOF arm, and
// a quarter-turn arm whose placements are URDF's rpy of +-pi/2 (cosines of
// 6e-17, taken for axis permutations), after eight threads made the
// process's first calls at once. Each M must be exactly symmetric, the
// chosen kernel's must be mass_matrix's bit for bit, and every kernel's must
// agree with the baseline's and with composite_body_frames (full rotation
// products, no tree frames) to 1e-14 of M's largest entry: the fused
// multiply-adds and the permutations round differently, by a few units of
// the last place.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "failure_count.hpp"
#include "random_tree.hpp"
#include "threads_at_once.hpp"
#include "soadyn/algorithms/crba.hxx"

using soadyn_test::check;
using soadyn_test::failures;

namespace {

constexpr double kTolerance = 1e-14;  // of M's largest entry
constexpr int kStates = 20;

// rot_x(roll) as a URDF parser builds it, from the double nearest the angle.
Eigen::Matrix3d rotation_about_x(double roll) {
  return Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
}

// A Panda-like arm: revolute joints about z, each placement a quarter turn
// about x (alternating sign), the last one pi/4 about z (general).
soadyn_test::TreeSpec quarter_turn_arm_spec() {
  soadyn_test::TreeSpec arm = soadyn_test::chain_spec(std::vector<soadyn_test::JointKind>(8, soadyn_test::JointKind::revolute), 11);
  const double half_pi = 1.5707963267948966;
  for (std::size_t i = 0; i < arm.size(); ++i) {
    arm[i].axis = Eigen::Vector3d::UnitZ();
    arm[i].rotation = i == 0 ? Eigen::Matrix3d::Identity() : rotation_about_x(i % 2 == 0 ? half_pi : -half_pi);
    arm[i].translation = Eigen::Vector3d(0.08 * (i % 3 == 0), 0, 0.3 * (i % 2));
  }
  arm.back().rotation = Eigen::AngleAxisd(0.7853981633974483, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return arm;
}

struct Worst {
  double kernel_vs_baseline = 0, kernel_vs_body_frames = 0;
  bool kernels_differ_somewhere = false;
};

void compare_kernels(const std::string& label, const soadyn::Model& model, Worst& worst) {
  soadyn::Data data(model), reference(model);
  const std::vector<soadyn::detail::MassMatrixKernel> kernels = soadyn::detail::available_mass_matrix_kernels();
  for (int s = 0; s < kStates; ++s) {
    const Eigen::VectorXd q = soadyn_test::random_state(model, 100 + static_cast<std::uint64_t>(s)).q;
    const std::string at = label + ", state " + std::to_string(s);
    soadyn::detail::composite_body_frames(model, reference, q);
    const Eigen::MatrixXd body_frames = reference.mass_matrix;
    check(soadyn::mass_matrix<double>(model, reference, q).ok(), at + ": mass_matrix failed");
    const Eigen::MatrixXd dispatched = reference.mass_matrix;
    const double scale = body_frames.cwiseAbs().maxCoeff();
    Eigen::MatrixXd baseline;
    for (auto k = kernels.rbegin(); k != kernels.rend(); ++k) {  // the baseline first
      const std::string who = at + ", kernel " + k->name;
      data.mass_matrix.setZero();  // as Data is built: a kernel writes the entries on ancestor paths only
      check(k->run(model, data, q).ok(), who + ": failed");
      const Eigen::MatrixXd& M = data.mass_matrix;
      check(M == M.transpose(), who + ": not exactly symmetric");
      if (k == kernels.rend() - 1) check(M == dispatched, who + ": the chosen kernel is not mass_matrix's");
      if (baseline.size() == 0) baseline = M;
      const double vs_baseline = (M - baseline).cwiseAbs().maxCoeff() / scale;
      const double vs_body_frames = (M - body_frames).cwiseAbs().maxCoeff() / scale;
      check(vs_baseline <= kTolerance, who + ": off the baseline by " + std::to_string(vs_baseline));
      check(vs_body_frames <= kTolerance, who + ": off the body-frame algorithm by " + std::to_string(vs_body_frames));
      worst.kernel_vs_baseline = std::max(worst.kernel_vs_baseline, vs_baseline);
      worst.kernel_vs_body_frames = std::max(worst.kernel_vs_body_frames, vs_body_frames);
      worst.kernels_differ_somewhere = worst.kernels_differ_somewhere || M != baseline;
    }
  }
}

std::string shape_name(const soadyn::PlacementAxes<double>& axes) {
  using Kind = soadyn::PlacementAxes<double>::Kind;
  return axes.kind == Kind::identity ? "identity" : axes.kind == Kind::signed_permutation ? "permutation" : "general";
}

// placement_axes_of on exact, rounded and nearly quarter-turn rotations.
void check_placement_shapes() {
  const double half_pi = 1.5707963267948966;
  const auto shape = [](const Eigen::Matrix3d& r) { return shape_name(soadyn::placement_axes_of<double>(r)); };
  check(shape(Eigen::Matrix3d::Identity()) == "identity", "the identity");
  check(shape(rotation_about_x(1e-17)) == "identity", "a rotation within epsilon of the identity");
  check(shape(rotation_about_x(half_pi)) == "permutation", "rot_x(pi/2) with its 6e-17 cosines");
  check(shape(rotation_about_x(half_pi + 1e-9)) == "general", "rot_x(pi/2 + 1e-9)");
  check(shape(rotation_about_x(2 * half_pi)) == "permutation", "rot_x(pi)");
  check(shape(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix()) == "general",
        "an oblique rotation");
  Eigen::Matrix3d nan_rotation = Eigen::Matrix3d::Identity();
  nan_rotation(0, 1) = std::nan("");
  check(shape(nan_rotation) == "general", "a rotation with a NaN entry");
  // rot_z(pi/2) rot_x(-pi/2): column c is sign[c] e_source[c]; the base's columns are the parent's, permuted.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(half_pi, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                               rotation_about_x(-half_pi);
  const soadyn::PlacementAxes<double> axes = soadyn::placement_axes_of<double>(turn);
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d column = axes.sign[static_cast<std::size_t>(c)] *
                                   Eigen::Vector3d::Unit(axes.source[static_cast<std::size_t>(c)]);
    check((column - turn.col(c)).cwiseAbs().maxCoeff() <= 1e-16, "column " + std::to_string(c) + " of the permutation");
  }
}

// Eight threads make the process's first mass_matrix calls at once (the
// kernel is chosen by whichever gets there first), each on its own Data, 200
// times; every M must equal the one a single thread forms afterwards, bit for
// bit. Returns the number of threads whose M differs.
int first_calls_from_threads(const soadyn::Model& m) {
  constexpr int kThreads = 8, kCalls = 200;
  const Eigen::VectorXd q = soadyn_test::random_state(m, 7).q;
  std::vector<soadyn::Data> data(kThreads, soadyn::Data(m));
  const int failed = soadyn_test::calls_from_threads_at_once(
      kThreads, kCalls, [&](int t) { return soadyn::mass_matrix<double>(m, data[static_cast<std::size_t>(t)], q).ok(); });
  soadyn::Data reference(m);
  check(soadyn::mass_matrix<double>(m, reference, q).ok(), "the single-thread mass_matrix failed");
  int differing = failed;
  for (const soadyn::Data& d : data) differing += d.mass_matrix != reference.mass_matrix;
  check(differing == 0, "a thread's M differs from the single-thread M, or a call failed");
  return differing;
}

}  // namespace

int main() {
  const soadyn::Model arm = soadyn_test::build_model<double>(quarter_turn_arm_spec());
  std::printf("threads: 8 threads from the process's first call, 200 mass matrices each, %d differ\n",
              first_calls_from_threads(arm));  // first: no mass_matrix call may precede it
  check_placement_shapes();
  const std::vector<std::pair<std::string, soadyn::Model>> models{
      {"random tree", soadyn_test::build_model<double>(soadyn_test::random_tree_spec(5, 24))},
      {"7-DOF arm", soadyn_test::build_model<double>(soadyn_test::seven_dof_arm_spec())},
      {"quarter-turn arm", soadyn_test::build_model<double>(quarter_turn_arm_spec())}};
  int permutations = 0;
  for (const soadyn::PlacementAxes<double>& axes : models[2].second.derived.placement_axes)
    permutations += axes.kind == soadyn::PlacementAxes<double>::Kind::signed_permutation;
  std::printf("quarter-turn arm: %d of %d placements applied as axis permutations\n", permutations,
              models[2].second.nbodies());
  check(permutations == 6, "the quarter-turn arm's placements 1-6 recorded as permutations");
  Worst worst;
  for (const auto& [label, model] : models) compare_kernels(label, model, worst);
  std::string names;
  for (const soadyn::detail::MassMatrixKernel& k : soadyn::detail::available_mass_matrix_kernels())
    names += std::string(names.empty() ? "" : ", ") + k.name;
  std::printf("kernels: %s (chosen: %s)\n", names.c_str(), soadyn::mass_matrix_kernel());
  std::printf("max relative difference: %.2e between kernels, %.2e from the body-frame algorithm (tolerance %.0e), "
              "kernels differ bit for bit: %s\n",
              worst.kernel_vs_baseline, worst.kernel_vs_body_frames, kTolerance,
              worst.kernels_differ_somewhere ? "yes" : "no");
  if (failures == 0) std::printf("test_mass_matrix_kernels: PASS: 3 models, %d states each\n", kStates);
  return failures == 0 ? 0 : 1;
}
