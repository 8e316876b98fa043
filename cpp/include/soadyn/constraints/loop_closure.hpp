// Loop-closure equations of the model's cut joints (model/loop.hpp): the
// position residual Psi(q), the constraint Jacobian C (m x nv, a map of the
// generalized velocities v) and the velocity-product term kappa of
// C qdd = kappa ("Joint Coordinate Method, Part 1", Eqs. 1.6-1.8;
// Saha, Shah & Nandihal 2013, Eq. 52b for the planar four-bar).
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.loops.residual = Psi(q), data.loops.jacobian = C(q) and, with `v`
// (may be null), data.loops.velocity_residual = C v. Runs forward kinematics.
template <class S>
void loop_residual(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const S* v);

// Rank of C(q) by column-pivoted Householder QR: pivots below
// loop_rank_threshold times the largest one count as zero.
template <class S>
int loop_rank(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

template <class S>
S loop_rank_threshold() { return S(1e3) * Eigen::NumTraits<S>::epsilon(); }

namespace detail {
// Which loop equations' terms a call needs besides C: the closure errors
// (Psi and C v: assembly, projection, drift) or the acceleration level
// (kappa: the dynamics, which need no Psi).
enum class LoopTerms { closure, acceleration };

// C, and Psi and C v or kappa, from the kinematics already in `data`:
// pose_in_world, body_subspace, body_velocity and, for kappa, the body
// accelerations of qdd = 0 (with the -gravity base acceleration, as inverse
// dynamics leaves them). Also leaves, per loop, the world positions of frame
// A's origin and of the point P whose velocity C compares (loops.point_a, point_p).
template <class S>
void loop_equations(const ModelTpl<S>& model, DataTpl<S>& data, LoopTerms terms);
}  // namespace detail

}  // namespace soadyn
