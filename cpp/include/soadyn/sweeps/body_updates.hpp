// Per-body updates shared by the sweeps of every algorithm (Jain & Rodriguez
// 1993, Eqs. 1-4, 14, 28, 29). Body i's quantities are in its own frame;
// `pose_in_parent[i]` carries them to the parent frame (the paper's phi(k+1, k)).
#pragma once
#include <Eigen/Cholesky>
#include <limits>
#include <cmath>
#include "soadyn/joints/fast_path_updates.hpp"
#include "soadyn/linalg/small_cholesky.hpp"
#include "soadyn/model/data.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn {

// Vector arguments. The nested ::type makes them non-deduced, so the scalar
// comes from the Model alone and plain Eigen vectors bind without <double>.
namespace detail {
template <class T>
struct type_identity {
  using type = T;
};
}  // namespace detail
template <class S> using ConstVecRef = typename detail::type_identity<Eigen::Ref<const VecX<S>>>::type;
template <class S> using VecRef = typename detail::type_identity<Eigen::Ref<VecX<S>>>::type;

// Outputs a caller may ask for beyond qdd and tau.
struct DynamicsOutputs {
  // Fill data.hinge_force with every joint reaction wrench (body frames).
  bool hinge_forces = false;
};

// The updates below are the sweeps' own: internal (namespace detail).
namespace detail {

// The two kinds of frame the sweeps work in (data.hpp): body frames and tree frames.
enum class Frames { body, tree };

// `body` or `tree` as F says: one quantity of the sweeps in the two kinds of frame.
template <Frames F, class T>
SOADYN_ALWAYS_INLINE T& by_frame(T& body, T& tree) {
  if constexpr (F == Frames::body) return body; else return tree;
}

// The sweep quantities in frames F, for the updates both kinds of sweep share
// (hinge_updates.hpp). `D` is DataTpl<S> or const DataTpl<S>.
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_subspace(D& d) { return by_frame<F>(d.sweep.body_subspace, d.sweep.tree_subspace); }
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_coriolis(D& d) { return by_frame<F>(d.sweep.body_coriolis, d.sweep.tree_coriolis); }
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_acceleration(D& d) {
  return by_frame<F>(d.body_acceleration, d.sweep.tree_acceleration);
}
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_hinge_force(D& d) { return by_frame<F>(d.hinge_force, d.sweep.tree_hinge_force); }
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_articulated_inertia(D& d) {
  return by_frame<F>(d.sweep.body_articulated_inertia, d.sweep.tree_articulated_inertia);
}
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_bias_and_children_z(D& d) {
  return by_frame<F>(d.sweep.body_bias_and_children_z, d.sweep.tree_bias_and_children_z);
}
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_gain(D& d) { return by_frame<F>(d.sweep.body_gain, d.sweep.tree_gain); }
template <Frames F, class D>
SOADYN_ALWAYS_INLINE auto& frame_regular_subspace(D& d) {
  return by_frame<F>(d.sweep.body_regular_subspace, d.sweep.tree_regular_subspace);
}

// Spatial acceleration of the world: gravity enters as a base acceleration
// [0; -g], so every hinge force includes it.
template <class S>
Vec6<S> world_acceleration(const ModelTpl<S>& m) {
  Vec6<S> a;
  a << Vec3<S>::Zero(), -m.gravity;
  return a;
}

// The velocities the sweeps are given, from nv velocities `v` (null: zero
// velocity, kept): nullptr for a rigid model at rest (every entry of v zero),
// so they skip every velocity term (joint velocity products, Coriolis and
// gyroscopic forces) with the same result. A flexible model always gets v:
// its elastic forces are computed with the velocity terms (flexible_updates.hpp).
template <class S>
const S* velocities_unless_at_rest(const ModelTpl<S>& m, const S* v) {
  if (!v || m.has_flexible_bodies()) return v;
  for (int k = 0; k < m.nv; ++k)
    if (v[k] != S(0)) return v;
  return nullptr;
}

// The same for a vector of nv velocities.
template <class S>
const S* velocities_unless_at_rest(const ModelTpl<S>& m, const ConstVecRef<S>& v) {
  return velocities_unless_at_rest(m, v.data());
}

// S x for a hinge subspace S (6 x n, n <= 6) and n values x, column by
// column with fixed-size vectors (no dynamic-size product for 1-6 columns).
template <class S, class Derived>
SOADYN_ALWAYS_INLINE Vec6<S> subspace_times(const Mat6N<S>& s, const Eigen::MatrixBase<Derived>& x) {
  Vec6<S> r = s.col(0) * x[0];
  for (Eigen::Index k = 1; k < s.cols(); ++k) r += s.col(k) * x[k];
  return r;
}
template <class S>
SOADYN_ALWAYS_INLINE Vec6<S> subspace_times(const Mat6N<S>& s, const S* x) {
  if (s.cols() == 0) return Vec6<S>::Zero();
  return subspace_times(s, Eigen::Map<const VecN<S>>(x, s.cols()));
}

// out = S' f (n values), column by column.
template <class S, class Derived>
inline void subspace_transpose_times(const Mat6N<S>& s, const Vec6<S>& f, Eigen::MatrixBase<Derived>&& out) {
  for (Eigen::Index k = 0; k < s.cols(); ++k) out[k] = s.col(k).dot(f);
}

// Joint transform, motion subspace and joint bias of body i. Axis-aligned
// revolute and prismatic joints and the fixed joint (their fast paths:
// joints/revolute.hpp, prismatic.hpp, fixed.hpp) keep the constant subspace
// and zero bias Data was built with and only compose the placement with the
// joint motion; every other joint goes through its own calc.
template <class S>
inline void joint_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  const int iq = m.q_index[i], iv = m.v_index[i];
  Transform<S>& pose = d.pose_in_parent[i];
  if (fast_path_body_pose(m.joint_fast_path[i], m.placement[i], q + iq, m.axis_sign[i], pose)) return;
  Transform<S> joint_pose;
  joint_calc(m.joints[i], q + iq, v ? v + iv : nullptr, joint_pose, d.sweep.body_subspace[i], d.sweep.body_joint_bias[i]);
  pose = m.placement[i] * joint_pose;
}

// Body velocity V(i) = phi* V(parent) + S v_i and Coriolis term
// a(i) = dS/dt v_i + V(i) x (S v_i) (Jain & Rodriguez 1993, Eq. 1), body frame.
template <class S>
inline void velocity_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* v) {
  const int p = m.parent[i];
  const Vec6<S> joint_velocity = subspace_times(d.sweep.body_subspace[i], v + m.v_index[i]);
  if (p >= 0)
    d.body_velocity[i] =
        d.pose_in_parent[i].motion_to_child(d.body_velocity[static_cast<std::size_t>(p)]) + joint_velocity;
  else
    d.body_velocity[i] = joint_velocity;
  d.sweep.body_coriolis[i] = d.sweep.body_joint_bias[i] + motion_cross(d.body_velocity[i], joint_velocity);
}

// Gyroscopic force minus the external wrench: b(i) = V x* (M V) - f_ext(i)
// (Jain & Rodriguez 1993, Eq. 1), body frame. `f_ext` holds nbodies rows of
// 6 (body frame, about the body origin, [torque; force]) or is null.
template <class S>
inline void bias_force_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* f_ext) {
  const Vec6<S>& V = d.body_velocity[i];
  d.sweep.body_bias_force[i] = force_cross(V, Vec6<S>(m.inertia[i] * V));
  if (f_ext) d.sweep.body_bias_force[i] -= Eigen::Map<const Vec6<S>>(f_ext + 6 * i);
}

// Velocity, Coriolis and bias force of body i; `v` null means zero velocity
// (impulse problems), where all three reduce to the external wrench.
template <class S>
inline void motion_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* v, const S* f_ext) {
  if (v) {
    velocity_update(m, d, i, v);
    bias_force_update(m, d, i, f_ext);
    return;
  }
  d.body_velocity[i].setZero();
  d.sweep.body_coriolis[i].setZero();
  d.sweep.body_bias_force[i].setZero();
  if (f_ext) d.sweep.body_bias_force[i] -= Eigen::Map<const Vec6<S>>(f_ext + 6 * i);
}

// Parent acceleration seen in body i's frame: alpha+(i) = phi* alpha(parent)
// (Jain & Rodriguez 1993, Eq. 29).
template <class S>
inline Vec6<S> parent_acceleration(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i,
                                   const Vec6<S>& world_acc) {
  const int p = m.parent[i];
  return d.pose_in_parent[i].motion_to_child(p >= 0 ? d.body_acceleration[static_cast<std::size_t>(p)] : world_acc);
}

// Adds body i's hinge force f (body frame) to its parent's accumulator.
template <class S>
inline void push_force_to_parent(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Vec6<S>& f) {
  const int p = m.parent[i];
  if (p >= 0) d.hinge_force[static_cast<std::size_t>(p)] += d.pose_in_parent[i].force_to_parent(f);
}

// How a hinge update delivers P+: stored in `P_plus`; added to it when
// `P_plus` is the parent's articulated inertia in the same frame (tree
// frames, Eq. 14 with phi = 1): one pass over the parent instead of a
// copy, an update and an addition; or not at all, when only P+ times a known
// acceleration is needed (articulated_plus_times, hinge_updates.hpp).
enum class PlusMode { store, add, none };

// P_plus = P - G U' (store), P_plus += P - G U' column by column in one
// pass (add), or nothing (none).
template <PlusMode Mode, class S, class Gain, class Product>
SOADYN_ALWAYS_INLINE void deliver_p_plus(const Mat6<S>& P, const Gain& G, const Product& U, Mat6<S>& P_plus) {
  if constexpr (Mode == PlusMode::store) {
    P_plus = P;
    P_plus.noalias() -= G * U.transpose();
  } else if constexpr (Mode == PlusMode::add) {
    for (int c = 0; c < 6; ++c) P_plus.col(c) += P.col(c) - G * U.row(c).transpose();
  }
}

// The rest of articulated_hinge_update_fixed for two regular DOFs (a universal
// joint), D = [a b; b c] given: G and nu by D = L' diag(a, d1) L'' (L' unit
// lower triangular, l = b / a, d1 = c - l b), two divisions and no square
// root on the way to P+ and z+. The Cholesky factor, for later solves, is
// formed beside them as cholesky_in_place forms it, and its pivots are
// tested against `threshold` as there (d1 too, the same pivot rounded
// otherwise).
template <PlusMode Mode, class S>
SOADYN_ALWAYS_INLINE int two_dof_hinge_update(const Mat6<S>& P, const Eigen::Matrix<S, 6, 2>& U,
                                            const Eigen::Matrix<S, 2, 2>& D, const Eigen::Matrix<S, 2, 1>& e,
                                            Mat6N<S>& G, VecN<S>& nu, Mat6<S>& factor, Mat6<S>& P_plus,
                                            const Vec6<S>& z, Vec6<S>& z_plus, const S& threshold) {
  using std::sqrt;
  const S a = D(0, 0), b = D(1, 0), c = D(1, 1);
  if (!(a > threshold)) return 0;
  const S root_a = sqrt(a), lower = b * (S(1) / root_a), pivot = c - lower * lower;  // the factor's, below
  const S inverse_a = S(1) / a, l = b * inverse_a, d1 = c - l * b;
  // Both forms of the second pivot: they differ by rounding, which can
  // exceed the threshold when D's entries are far larger than P's diagonal.
  if (!(pivot > threshold) || !(d1 > threshold)) return 1;
  const S inverse_d1 = S(1) / d1;
  const auto solve = [&](const auto& x0, const auto& x1, auto&& y0, auto&& y1) {  // [y0 y1] = D^-1 [x0 x1]
    y1 = (x1 - l * x0) * inverse_d1;
    y0 = x0 * inverse_a - l * y1;
  };
  Eigen::Matrix<S, 6, 2> gain;
  solve(U.col(0), U.col(1), gain.col(0), gain.col(1));
  nu.resize(2);  // within VecN's fixed capacity: no allocation
  solve(e[0], e[1], nu[0], nu[1]);
  G = gain;
  deliver_p_plus<Mode>(P, gain, U, P_plus);
  z_plus = z;
  z_plus.noalias() += gain * e;
  factor(0, 0) = root_a;
  factor(0, 1) = b;  // the upper triangle as cholesky_in_place leaves it
  factor(1, 0) = lower;
  factor(1, 1) = sqrt(pivot);
  return -1;
}

// articulated_hinge_update (below) for a hinge of N regular DOFs, N fixed at
// compile time: universal (2), spherical (3) and free (6) joints.
template <int N, PlusMode Mode, class S>
inline int articulated_hinge_update_fixed(const Mat6<S>& P, const Mat6N<S>& Sr, const Vec6<S>& z,
                                        const VecN<S>& torque, const S* armature, Mat6N<S>& G, VecN<S>& nu,
                                        Mat6<S>& factor, Mat6<S>& P_plus, Vec6<S>& z_plus, const S& threshold) {
  using Mat6n = Eigen::Matrix<S, 6, N>;
  using Vecn = Eigen::Matrix<S, N, 1>;
  const Mat6n s = Sr;
  Mat6n U;  // P S column by column: inlined, where the 6 x N product was a loop called out of line
  for (int k = 0; k < N; ++k) U.col(k).noalias() = P * s.col(k);
  Vecn e = torque.template head<N>();  // eps = T - S' z
  e.noalias() -= s.transpose() * z;
  Eigen::Matrix<S, N, N> L = s.transpose() * U;  // D = S' P S (+ armature), factored in place
  if (armature)
    for (int k = 0; k < N; ++k) L(k, k) += armature[k];
  if constexpr (N == 2) return two_dof_hinge_update<Mode>(P, U, L, e, G, nu, factor, P_plus, z, z_plus, threshold);
  const int bad = cholesky_in_place(L, threshold);
  if (bad >= 0) return bad;
  factor.template topLeftCorner<N, N>() = L;
  Eigen::Matrix<S, N, 6> gain_transpose = U.transpose();  // G' = D^-1 (P S)'
  cholesky_solve_in_place(L, gain_transpose);
  const Mat6n gain = gain_transpose.transpose();
  Vecn solved = e;  // nu = D^-1 eps
  cholesky_solve_in_place(L, solved);
  nu = solved;
  G = gain;
  deliver_p_plus<Mode>(P, gain, U, P_plus);
  z_plus = z;
  z_plus.noalias() += gain * e;
  return -1;
}

// The regular part of a hinge in the tip-to-base sweep (Jain & Rodriguez 1993, Eqs. 14, 28):
//   D = S' P S + A,  G = P S D^-1,  eps = T - S' z,  nu = D^-1 eps,
//   P+ = (I - G S') P,  z+ = z + G eps,
// with A the diagonal of the regular DOFs' armatures (`armature`, null: none;
// ModelTpl::set_armature): the hinge equation T = S' f + A qdd adds A to D
// and leaves G's role in P+ and in qdd = nu - G' alpha+ unchanged.
// `z` already holds b + children + P (S_p qdd_p + a); `torque` holds the
// regular hinge torques T. P+ goes to `P_plus` as `Mode` says; D goes to
// `factor` (hinge_factor, data.hpp) for later solves with the same D (the
// loops' unit-multiplier response). Returns the local column of a singular
// D, or -1.
template <PlusMode Mode = PlusMode::store, class S>
inline int articulated_hinge_update(const Mat6<S>& P, const Mat6N<S>& Sr, const Vec6<S>& z, const VecN<S>& torque,
                                  const S* armature, Mat6N<S>& G, VecN<S>& nu, Mat6<S>& factor, Mat6<S>& P_plus,
                                  Vec6<S>& z_plus) {
  const S threshold = singular_pivot_threshold(P);
  if (Sr.cols() == 1) {  // the common case, in fixed-size arithmetic: a scalar D
    const Vec6<S> u = P * Sr.col(0);
    S D = Sr.col(0).dot(u);
    if (armature) D += armature[0];
    if (!(D > threshold)) return 0;
    factor(0, 0) = D;
    const S inverse_D = S(1) / D;  // one division, not seven
    const Vec6<S> g = u * inverse_D;
    const S e = torque[0] - Sr.col(0).dot(z);
    G.col(0) = g;
    nu[0] = e * inverse_D;
    deliver_p_plus<Mode>(P, g, u, P_plus);
    z_plus = z + g * e;
    return -1;
  }
  switch (Sr.cols()) {  // multi-DOF hinges in fixed-size arithmetic
    case 2: return articulated_hinge_update_fixed<2, Mode>(P, Sr, z, torque, armature, G, nu, factor, P_plus, z_plus, threshold);
    case 3: return articulated_hinge_update_fixed<3, Mode>(P, Sr, z, torque, armature, G, nu, factor, P_plus, z_plus, threshold);
    case 6: return articulated_hinge_update_fixed<6, Mode>(P, Sr, z, torque, armature, G, nu, factor, P_plus, z_plus, threshold);
    default: break;
  }
  const Mat6N<S> U = P * Sr;  // 6 x nr
  VecN<S> eps = torque;
  eps.noalias() -= Sr.transpose() * z;
  {
    MatN<S> D = Sr.transpose() * U;
    if (armature)
      for (Eigen::Index k = 0; k < D.rows(); ++k) D(k, k) += armature[k];
    const Eigen::LLT<MatN<S>> llt(D);
    if (llt.info() != Eigen::Success) return 0;
    const VecN<S> pivots = llt.matrixLLT().diagonal();
    for (Eigen::Index k = 0; k < pivots.size(); ++k)
      if (!(pivots[k] * pivots[k] > threshold)) return static_cast<int>(k);
    factor.topLeftCorner(D.rows(), D.cols()) = llt.matrixL();
    nu = llt.solve(eps);
    G = llt.solve(U.transpose()).transpose();
  }
  deliver_p_plus<Mode>(P, G, U, P_plus);
  z_plus = z;
  z_plus.noalias() += G * eps;
  return -1;
}

// Adds P+ and z+ of body i to its parent, body frames (Jain & Rodriguez
// 1993, Eq. 14: P(k) = phi P+ phi* + M).
template <class S>
inline void push_articulated_to_parent(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Mat6<S>& P_plus,
                                       const Vec6<S>& z_plus) {
  const std::size_t p = static_cast<std::size_t>(m.parent[i]);
  d.sweep.body_articulated_inertia[p] += d.pose_in_parent[i].inertia_to_parent(P_plus);
  d.sweep.body_bias_and_children_z[p] += d.pose_in_parent[i].force_to_parent(z_plus);
}

// The mass matrix with every prescribed DOF's row and column replaced by the
// identity's (M~ of the partitioned hybrid problem, Jain & Rodriguez 1993,
// Eq. 12): factoring it factors M_RR, and it keeps the tree's sparsity.
template <class S>
inline void replace_prescribed_by_identity(const ModelTpl<S>& m, MatX<S>& mass) {
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    mass.row(p).setZero();
    mass.col(p).setZero();
    mass(p, p) = S(1);
  }
}

// T_k += armature_k qdd_k for body i's hinge DOFs (ModelTpl::set_armature),
// on top of T = H f: the rotor's own share of the hinge torque.
template <class S>
inline void add_armature_torques(const ModelTpl<S>& m, std::size_t i, const S* qdd, S* tau) {
  if (!m.modes[i].has_armature) return;
  const int vi = m.v_index[i];
  for (int k = 0; k < m.nv_body[i]; ++k) tau[vi + k] += m.armature[static_cast<std::size_t>(vi + k)] * qdd[vi + k];
}

template <class S>
inline Status check_finite(const VecX<S>& x) {
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (!std::isfinite(scalar_value(x[k]))) return Status{StatusCode::non_finite_result, static_cast<int>(k)};
  return Status{};
}

// check_finite of a matrix, naming the first non-finite column. x * 0 is 0
// for finite x and NaN for NaN or inf: one vectorised sum tells whether every
// entry is finite (Eigen's allFinite is a scalar loop); the column at fault
// is searched only on failure.
template <class Derived>
inline Status check_finite_columns(const Eigen::MatrixBase<Derived>& x) {
  using S = typename Derived::Scalar;
  if ((x.array() * S(0)).sum() == S(0)) return Status{};
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    if (!x.col(c).allFinite()) return Status{StatusCode::non_finite_result, static_cast<int>(c)};
  return Status{};
}

// check_finite of the hybrid torques once the accelerations are finite: a
// regular DOF's torque is its given input, and a non-finite input gives a
// non-finite acceleration of that DOF, so only prescribed DOFs can fail here.
template <class S>
inline Status check_prescribed_finite(const ModelTpl<S>& m, const VecX<S>& tau) {
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int dof = m.prescribed_dofs[static_cast<std::size_t>(k)];
    if (!std::isfinite(scalar_value(tau[dof]))) return Status{StatusCode::non_finite_result, dof};
  }
  return Status{};
}

}  // namespace detail
}  // namespace soadyn
