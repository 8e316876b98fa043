// The float instantiation of constrained_dynamics agrees with the double one.
//
// Random trees (random_tree.hpp: masses ~1 kg, links ~0.3 m, a free root)
// closed by 1-4 loops of every kind, each loop closed at the drawn
// configuration, are built as ModelTpl<double> and ModelTpl<float> from the
// same spec. At that configuration, with a velocity on the loops' tangent
// space and a random prescribed/regular mask (prescribed accelerations taken
// from an admissible acceleration, so the equations stay consistent), the
// float results must agree with the double ones:
//   qdd:           max|f - d| <= 1e-4 * max(1, max|qdd|)
//   tau:           max|f - d| <= 1e-4 * max(1, max|tau|, max|C' lambda|)
//   loop wrenches: max|f - d| <= 1e-4 * max(1, largest wrench entry of any loop)
//   (where the multipliers are not determined, see multipliers_indeterminate,
//   C' lambda instead, relative to max(1, max|C' lambda|))
// (tau_p = (M qdd + h - C' lambda)_p and the multipliers of all loops come
// from one solve, so their rounding scales with the largest term, not with
// the result.)
// Why 1e-4: the float inputs are the double ones rounded (eps_f = 6e-8) and
// the solve amplifies that by about the condition numbers of the regular
// mass matrix M_rr and of the Delassus matrix C_r M_rr^-1 C_r' (its nonzero
// part): to first order the float error is ~eps_f (cond(M_rr) + cond(D)).
// A case is compared only if, measured in double, cond(M_rr) <= 2e3 and
// cond(D) <= 1e3 (worst-case estimate ~2e-4; rounding errors rarely add up
// to it: the observed largest error is ~9e-5, typical ones 1e-6..1e-5);
// cases are drawn until kCases are accepted and the rejected draws are
// counted (random trees often have a light distal body, cond(M_rr) > 2e3).
// The Delassus bound also keeps the smallest nonzero pivot ratio (>= 1e-3)
// ten times above float's rank threshold (delassus_threshold<float> =
// 1e3 eps_f = 1.2e-4): beyond it float legitimately counts a weak loop
// direction as redundant and the two precisions solve different
// (minimum-norm) problems: of the draws this loop rejects, most of those with
// cond(D) between 2e4 and 1e6 have a float rank one below the double rank,
// and their tau then differs by 0.2..12 relative to max|tau|.
#include <Eigen/SVD>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>
#include "float_error_tracker.hpp"
#include "random_tree.hpp"

namespace {

using soadyn::LoopKind;
using soadyn::Transform;

constexpr double kTolerance = 1e-4;
constexpr double kMassConditionBound = 2e3;
constexpr double kDelassusConditionBound = 1e3;
constexpr int kCases = 48;
constexpr int kMaxDraws = 200;

const LoopKind kKinds[] = {LoopKind::point, LoopKind::revolute, LoopKind::prismatic, LoopKind::weld,
                           LoopKind::distance};

using ErrorTracker = soadyn_test::FloatErrorTracker;

Transform<double> translation(const Eigen::Vector3d& p) {
  Transform<double> X;
  X.translation = p;
  return X;
}

// Frame B relative to frame A for a loop of `kind` closed at the current
// configuration: any orientation for a point, a turn about z for a revolute,
// a shift along z for a prismatic, the identity for a weld, a rod for a
// distance loop (its length returned in `length`).
Transform<double> closed_offset(LoopKind kind, soadyn_test::Random& rng, double& length) {
  Transform<double> X;
  length = 0.0;
  switch (kind) {
    case LoopKind::point: X.rotation = rng.rotation(); break;
    case LoopKind::revolute:
      X.rotation = soadyn::axis_angle_rotation<double>(Eigen::Vector3d::UnitZ(), rng.uniform(-3.0, 3.0));
      break;
    case LoopKind::prismatic: X = translation(Eigen::Vector3d(0, 0, rng.uniform(-0.2, 0.2))); break;
    case LoopKind::weld: break;
    case LoopKind::distance:
      length = rng.uniform(0.2, 0.4);
      X = translation(length * rng.unit_vector());
      break;
  }
  return X;
}

Transform<float> cast(const Transform<double>& X) {
  Transform<float> out;
  out.rotation = X.rotation.cast<float>();
  out.translation = X.translation.cast<float>();
  return out;
}

// Adds 1-4 loops (kinds cycling from `first_kind`) closed at q to both models.
void add_closed_loops(soadyn::Model& md, soadyn::ModelF& mf, const Eigen::VectorXd& q, std::uint64_t seed,
                      int nloops, int first_kind) {
  soadyn::Data data(md);
  soadyn::forward_kinematics<double>(md, data, q.data(), nullptr);
  soadyn_test::Random rng(seed);
  for (int k = 0; k < nloops; ++k) {
    const LoopKind kind = kKinds[(first_kind + k) % 5];
    const int a = rng.integer(0, md.nbodies() - 1);
    int b = rng.integer(-1, md.nbodies() - 2);
    if (b >= a) ++b;
    Transform<double> placement_a;
    placement_a.rotation = rng.rotation();
    placement_a.translation = rng.uniform_vector3(0.15);
    double length = 0.0;
    const Transform<double> B_world =
        data.pose_in_world[static_cast<std::size_t>(a)] * placement_a * closed_offset(kind, rng, length);
    const Transform<double> placement_b =
        b < 0 ? B_world : data.pose_in_world[static_cast<std::size_t>(b)].inverse() * B_world;
    const std::string name = "loop" + std::to_string(k);
    const std::string body_b = b < 0 ? "" : md.body_names[static_cast<std::size_t>(b)];
    md.add_loop(name, md.body_names[static_cast<std::size_t>(a)], body_b, kind, placement_a, placement_b, length);
    mf.add_loop(name, mf.body_names[static_cast<std::size_t>(a)], body_b, kind, cast(placement_a), cast(placement_b),
                static_cast<float>(length));
  }
}

Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& A) {
  return A.completeOrthogonalDecomposition().pseudoInverse();
}

// Largest over smallest singular value among those above 1e-9 times the largest.
double condition_number(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  double smallest = s[0];
  for (Eigen::Index i = 0; i < s.size(); ++i)
    if (s[i] > 1e-9 * s[0]) smallest = s[i];
  return s[0] / smallest;
}

// Condition numbers of M_rr and of the Delassus matrix under the model's flags, in double.
std::pair<double, double> conditioning(const soadyn::Model& m, soadyn::Data& d, const Eigen::VectorXd& q) {
  soadyn::mass_matrix<double>(m, d, q);
  soadyn::loop_residual<double>(m, d, q, nullptr);
  std::vector<int> regular;
  for (int k = 0; k < m.nv; ++k)
    if (!m.is_prescribed(k)) regular.push_back(k);
  const Eigen::MatrixXd M_rr = d.mass_matrix(regular, regular);
  const Eigen::MatrixXd C_r = d.loops.jacobian(Eigen::all, regular);
  const Eigen::MatrixXd delassus = C_r * M_rr.ldlt().solve(C_r.transpose());
  return {condition_number(M_rr), condition_number(delassus)};
}

// True when the loop multipliers are not determined by the motion and the
// actuator forces: some null vector of C_r' (a multiplier change that leaves
// qdd alone) changes tau_p (redundant actuation: tau_p is then chosen of
// minimum norm) and C has dependent rows (so part of lambda stays free and
// the wrenches are one consistent choice). Then only C' lambda is compared.
bool multipliers_indeterminate(const soadyn::Model& m, const soadyn::Data& d) {
  std::vector<int> regular, prescribed;
  for (int k = 0; k < m.nv; ++k) (m.is_prescribed(k) ? prescribed : regular).push_back(k);
  const Eigen::MatrixXd& C = d.loops.jacobian;
  const double tolerance = 1e-9 * std::max(1.0, C.norm());
  Eigen::JacobiSVD<Eigen::MatrixXd> regular_svd(C(Eigen::all, regular).transpose(), Eigen::ComputeFullV);
  regular_svd.setThreshold(tolerance / std::max(tolerance, regular_svd.singularValues().maxCoeff()));
  const Eigen::MatrixXd null_regular = regular_svd.matrixV().rightCols(C.rows() - regular_svd.rank());
  const bool redundant_actuation =
      null_regular.cols() > 0 && !prescribed.empty() &&
      (C(Eigen::all, prescribed).transpose() * null_regular).cwiseAbs().maxCoeff() > tolerance;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(C);
  svd.setThreshold(tolerance / std::max(tolerance, svd.singularValues().maxCoeff()));
  return redundant_actuation && svd.rank() < C.rows();
}

struct Tally {
  double mass = 0, delassus = 0;  // largest condition numbers among accepted cases
  int accepted = 0, rejected = 0, redundant = 0, indeterminate = 0;
};

// One draw: a random tree with 1-4 closed loops at one state. Returns without
// comparing (counted as rejected) when the problem is outside the condition
// bounds that the tolerance assumes.
void compare_draw(int draw, ErrorTracker& errors, Tally& tally) {
  const std::uint64_t seed = 700 + static_cast<std::uint64_t>(draw);
  const soadyn_test::TreeSpec spec = soadyn_test::random_tree_spec(seed, 8 + draw % 5);
  soadyn::Model model_d = soadyn_test::build_model<double>(spec);
  soadyn::ModelF model_f = soadyn_test::build_model<float>(spec);
  const soadyn_test::State state = soadyn_test::random_state(model_d, seed);
  add_closed_loops(model_d, model_f, state.q, seed, 1 + draw % 4, draw);
  soadyn::Data data_d(model_d);
  soadyn::DataF data_f(model_f);
  // Velocity on the tangent space of the loops; an admissible acceleration (all regular, double).
  soadyn::loop_residual<double>(model_d, data_d, state.q, nullptr);
  const Eigen::MatrixXd C = data_d.loops.jacobian;
  const Eigen::VectorXd v = state.v - pseudo_inverse(C) * (C * state.v);
  if (!soadyn::constrained_dynamics<double>(model_d, data_d, state.q, v, state.u).ok())
    return errors.fail("draw " + std::to_string(draw) + ": all-regular double solve failed");
  const Eigen::VectorXd admissible = data_d.qdd;
  soadyn_test::Random mask_rng(seed);
  const std::vector<bool> mask = soadyn_test::random_mask(model_d.nv, mask_rng, 0.3);
  soadyn_test::apply_mask(model_d, mask);
  soadyn_test::apply_mask(model_f, mask);
  Eigen::VectorXd u = state.u;
  for (int k = 0; k < model_d.nv; ++k)
    if (mask[static_cast<std::size_t>(k)]) u[k] = admissible[k];

  const auto [cond_mass, cond_delassus] = conditioning(model_d, data_d, state.q);
  if (!(cond_mass <= kMassConditionBound && cond_delassus <= kDelassusConditionBound)) {
    ++tally.rejected;
    return;
  }
  ++tally.accepted;
  tally.mass = std::max(tally.mass, cond_mass);
  tally.delassus = std::max(tally.delassus, cond_delassus);
  if (soadyn::loop_rank<double>(model_d, data_d, state.q) < model_d.nloop_equations) ++tally.redundant;

  const bool ok_d = soadyn::constrained_dynamics<double>(model_d, data_d, state.q, v, u).ok();
  const Eigen::VectorXf qf = state.q.cast<float>(), vf = v.cast<float>(), uf = u.cast<float>();
  const bool ok_f = soadyn::constrained_dynamics<float>(model_f, data_f, qf, vf, uf).ok();
  if (!ok_d || !ok_f) return errors.fail("draw " + std::to_string(draw) + ": a failed Status");
  const Eigen::VectorXd loop_force = data_d.loops.jacobian.transpose() * data_d.loops.multipliers;
  double wrench_scale = 1.0;
  for (const auto& w : data_d.loops.wrench) wrench_scale = std::max(wrench_scale, w.cwiseAbs().maxCoeff());
  errors.compare("qdd", data_f.qdd, data_d.qdd, std::max(1.0, data_d.qdd.cwiseAbs().maxCoeff()));
  errors.compare("tau", data_f.tau, data_d.tau,
                 std::max({1.0, data_d.tau.cwiseAbs().maxCoeff(), loop_force.cwiseAbs().maxCoeff()}));
  if (multipliers_indeterminate(model_d, data_d)) {
    ++tally.indeterminate;
    const Eigen::VectorXd loop_force_f =
        data_f.loops.jacobian.transpose().cast<double>() * data_f.loops.multipliers.cast<double>();
    errors.compare("C' lambda (indeterminate lambda)", loop_force_f, loop_force,
                   std::max(1.0, loop_force.cwiseAbs().maxCoeff()));
    return;
  }
  for (std::size_t l = 0; l < model_d.loops.size(); ++l)
    errors.compare(std::string("wrench (") + soadyn::loop_kind_name(model_d.loops[l].kind) + ")",
                   data_f.loops.wrench[l], data_d.loops.wrench[l], wrench_scale);
}

}  // namespace

int main() {
  ErrorTracker errors(kTolerance);
  Tally tally;
  for (int draw = 0; tally.accepted < kCases && draw < kMaxDraws; ++draw) compare_draw(draw, errors, tally);
  errors.print();
  std::printf("cases: %d accepted (%d with redundant loop equations, %d of them with indeterminate multipliers), "
              "%d rejected; largest condition numbers: M_rr %.1f (bound %.0e), Delassus %.1f (bound %.0e)\n",
              tally.accepted, tally.redundant, tally.indeterminate, tally.rejected, tally.mass, kMassConditionBound,
              tally.delassus, kDelassusConditionBound);
  const bool pass = errors.failures() == 0 && tally.accepted == kCases;
  std::printf("test_loops_float_vs_double: %s: max relative error %.3e (tolerance %.0e), %d cases, %d failures\n",
              pass ? "PASS" : "FAIL", errors.max_error(), kTolerance, tally.accepted, errors.failures());
  return pass ? 0 : 1;
}
