// Hybrid dynamics with closed loops: the regular/prescribed problem of
// hybrid_dynamics (hybrid.hpp) plus the loop-closure equations
// C qdd = kappa (loop_closure.hpp) with their Lagrange multipliers lambda:
//   M qdd + h = tau + C' lambda,   C qdd = kappa
// ("Joint Coordinate Method, Part 1", Eq. 1.13; Saha, Shah & Nandihal 2013,
// Eqs. 50-54), with qdd_p given on prescribed DOFs and tau_r on regular ones
// (Jain & Rodriguez 1993, Eq. 12, with constraints).
//
// Method. Substituting the prescribed accelerations leaves
// M_rr qdd_r = b_r + C_r' lambda. Two ways to K = C_r M_rr^-1 C_r' and the
// free accelerations, the same equations:
// - Rigid models (the tree-frame dynamics path): the hybrid sweeps give
//   qdd_free and their articulated-body factors; the recursions run again on
//   the loop wrenches of each unit multiplier, on the loop bodies' root paths
//   only, give Y = M_rr^-1 C_r' there (articulated_loop_response.hxx), and
//   K = C_r Y; O(N + L m) for N bodies, L on loop paths, m equations.
// - Models with flexible bodies, and calls with a body beyond tree-frame
//   reach: M (mass_matrix) and h - J' f_ext (inverse dynamics at qdd = 0),
//   the factor M_rr = L' L of M with its prescribed rows and columns replaced
//   by the identity (sizes stay nv, so flipping flags needs no
//   reallocation), L with the tree's branch-induced sparsity
//   (tree_cholesky.hpp: O(n d^2) for depth d), and K = Y'Y with
//   Y = L'^-1 C_r' (one sparse half-solve per equation).
// The multipliers solve the Delassus system
//   K lambda = kappa - C_p qdd_p - C_r M_rr^-1 b_r = kappa - C qdd_free
// by a pivoted Cholesky factorisation (semidefinite_solve.hpp): pivots below
// delassus_threshold times the largest diagonal entry count as zero, so
// redundant loop equations (a planar four-bar closed by a revolute cut: 5
// equations of rank 2) give the minimum-norm lambda0, exact for consistent
// equations. The accelerations are then unique: qdd_r depends on lambda only
// through C_r' lambda, and null(K) = null(C_r').
//
// Actuator forces. tau_p = (M qdd + h - J' f_ext - C' lambda)_p. When the
// prescribed DOFs are exactly independent coordinates of the mechanism
// (rank C_r = rank C) every lambda with K lambda = rhs gives the same tau_p:
// the "Joint Coordinate Method, Part 1" Eq. 1.31 result E'(M qdd + h), E a
// basis of null(C). With more prescribed DOFs than the mechanism's mobility
// (redundant actuation) tau_p is not unique; the solve returns the
// minimum-norm actuator forces: with N a basis of null(K) (from the pivoted
// factor, N = P'[-L1^-T L2'; I]) and B = C_p' N, lambda = lambda0 + N z with
// z the minimum-norm least-squares solution of B z = tau0_p, tau0 = tau at
// lambda0, so tau_p = tau0_p - B z = min ||tau_p|| over every lambda
// consistent with the motion. The multipliers stay a consistent choice (the
// part of lambda in null(C') remains indeterminate and is not minimised).
//
// Singular and inconsistent cases. When the closure accelerations cannot be
// met (prescribed accelerations inconsistent with the loops, a driven
// mechanism at a dead centre, a prescribed DOF of a locked mechanism moved),
// the rhs is not in the range of K: the solve leaves the least-squares
// lambda (minimum norm) and its accelerations, tau and wrenches in `data`,
// finite, and returns inconsistent_loop_equations with the index of the loop
// whose closure acceleration C qdd - kappa is furthest off (relative to
// |kappa| + |C|(|qdd| + |qdd_free|), above loop_consistency_threshold; only
// checked when K is rank deficient: a full-rank K is solved exactly; an
// absolute floor keeps the drift of a mechanism at rest from counting). The
// check belongs to constrained_dynamics, not to the kernel
// detail::constrained_solve. A locked mechanism
// (mobility zero) with consistent inputs is an ordinary case: qdd is the
// unique motion and tau_p the minimum-norm forces (zero when the structure
// can carry the load).
//
// Joint wrenches (DynamicsOutputs::hinge_forces): data.hinge_force holds each
// hinge's wrench on its body (body frame, about the body origin, as
// inverse_dynamics) in the tree loaded by f_ext and by the loop forces:
// loop l's wrench W lambda on frame A's body (about frame A's origin) and its
// opposite on frame B's body (its force at frame B's origin, or at frame A's
// origin for a prismatic loop: the points whose velocities C compares)
// ("Joint Coordinate Method, Part 1", Sect. 4, Eqs. 1.25-1.29, with the
// cut-joint reactions C' nu).
//
// Allocation free after Data is built; never throws. With no loops this is
// hybrid_dynamics itself.
#pragma once
#include <cmath>
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.qdd, data.tau as hybrid_dynamics; data.loops.multipliers (lambda),
// data.loops.wrench (per loop, [torque; force] of frame B's side on frame A's
// side, world axes, about frame A's origin), the closure equations, and with
// outputs.hinge_forces the joint wrenches data.hinge_force.
// Status: singular_articulated_inertia when M_rr is not positive definite,
// non_finite_result naming the first non-finite acceleration or force,
// inconsistent_loop_equations (index: the loop) with the least-squares
// answer in `data`.
template <class S>
Status constrained_dynamics(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                            const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext = nullptr,
                            DynamicsOutputs outputs = {});

// Joint wrenches of a model with loops at given accelerations: data.hinge_force
// (as inverse_dynamics) of the tree loaded by f_ext and by the loop wrenches
// `loop_wrenches` (nloops rows of 6, [torque; force] of frame B's side on
// frame A's side, world axes, about frame A's origin: data.loops.wrench as
// constrained_dynamics leaves it), each applied as in constrained_dynamics.
// data.tau is inverse dynamics' M qdd + h - J' f_ext (the loop forces not
// subtracted). Status: non_finite_result.
template <class S>
Status loop_joint_wrenches(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                           const ConstVecRef<S>& v, const ConstVecRef<S>& qdd, const S* loop_wrenches,
                           const S* f_ext = nullptr);

namespace detail {
// The solve behind constrained_dynamics, from what is already in `data`:
// mass_matrix (M), loops.bias (h - J' f_ext), loops.jacobian (C) and
// loops.kappa. Fills qdd, tau (minimum-norm actuator forces),
// loops.multipliers and loops.wrench; leaves the least-squares answer of an
// inconsistent system without a status (an impulse's rhs -C v is
// inconsistent only by the velocity drift, which the projection removes). The same
// kernel solves the impulse problem of a mode switch in a loop model
// (M dv = tau + C' Lambda, C dv = -C v, dv_p given): bias = 0, kappa = -C v.
template <class S>
Status constrained_solve(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& u);
}  // namespace detail

template <class S>
S delassus_threshold() { return S(1e3) * Eigen::NumTraits<S>::epsilon(); }

namespace detail {

// C restricted to the columns `keep(k)` accepts (the others zeroed), with
// the entries at rounding level dropped as well: an entry not above 64 eps
// times C's largest is what forming C leaves of a zero (a lever arm crossed
// with a parallel axis). Kept, such noise is all a row has left when its real
// entries sit in dropped columns (or it has none, as the vertical row of a
// point whose only driven joint turns about the vertical); the Delassus
// solve, whose rank threshold is relative to its own largest pivot, would
// take it for a constraint and return a multiplier of order 1/eps. The scale
// is C's largest entry, not its row's: a row can be noise through and through.
template <class S>
S jacobian_noise_floor(const MatX<S>& C) {
  return C.size() > 0 ? S(64) * Eigen::NumTraits<S>::epsilon() * C.cwiseAbs().maxCoeff() : S(0);
}

template <class S, class Keep>
void restrict_jacobian_columns(const MatX<S>& C, Keep&& keep, MatX<S>& restricted) {
  const S floor = jacobian_noise_floor(C);
  restricted = (C.array().abs() > floor).select(C, S(0));
  for (Eigen::Index k = 0; k < C.cols(); ++k)
    if (!keep(k)) restricted.col(k).setZero();
}

// The same restriction written transposed (nv x m), in one pass over C
// (flat loops: a few entries per column, where expressions cost more to set
// up than to run).
template <class S, class Keep>
void restrict_jacobian_columns_transposed(const MatX<S>& C, Keep&& keep, MatX<S>& restricted_transposed) {
  using std::abs;
  const S floor = jacobian_noise_floor(C);
  const Eigen::Index rows = C.rows(), stride = restricted_transposed.rows();
  for (Eigen::Index k = 0; k < C.cols(); ++k) {
    const S* const c = C.data() + k * rows;
    S* const out = restricted_transposed.data() + k;  // row k: entries `stride` apart
    if (keep(k))
      for (Eigen::Index r = 0; r < rows; ++r) out[r * stride] = abs(c[r]) > floor ? c[r] : S(0);
    else
      for (Eigen::Index r = 0; r < rows; ++r) out[r * stride] = S(0);
  }
}

}  // namespace detail

// Closure accelerations off by more than this, relative to |kappa| + |C||qdd|
// per equation, make the loop equations inconsistent: the square root of
// delassus_threshold, the relative size of a singular value of C below
// which the Delassus solve treats a direction as absent.
template <class S>
S loop_consistency_threshold() {
  using std::sqrt;
  return sqrt(delassus_threshold<S>());
}

}  // namespace soadyn
