// Hybrid dynamics with closed loops: the regular/prescribed problem of
// hybrid_dynamics (hybrid.hpp) plus the loop-closure equations
// C qdd = kappa (loop_closure.hpp) with their Lagrange multipliers lambda:
//   M qdd + h = tau + C' lambda,   C qdd = kappa
// ("Joint Coordinate Method, Part 1", Eq. 1.13; Saha, Shah & Nandihal 2013,
// Eqs. 50-54), with qdd_p given on prescribed DOFs and tau_r on regular ones
// (Jain & Rodriguez 1993, Eq. 12, with constraints).
//
// Method. M (mass_matrix) and h - J' f_ext (inverse dynamics at qdd = 0)
// come from the O(N) tree algorithms. Substituting the prescribed
// accelerations leaves M_rr qdd_r = b_r + C_r' lambda, solved by the
// Cholesky factor of M with its prescribed rows and columns replaced by the
// identity (sizes stay nv, so flipping flags needs no reallocation). The
// multipliers solve the Delassus system
//   (C_r M_rr^-1 C_r') lambda = kappa - C_p qdd_p - C_r M_rr^-1 b_r
// by a pivoted Cholesky factorisation (semidefinite_solve.hpp): pivots below
// delassus_threshold times the largest diagonal entry count as zero, so redundant loop equations (a planar four-bar closed
// by a revolute cut: 5 equations of rank 2) give the minimum-norm lambda,
// exact for consistent equations; for inconsistent ones the answer is the
// least-squares lambda (closure accelerations are then not met). The
// accelerations are unique whenever the equations are consistent. Then
// tau_p = (M qdd + h - J' f_ext - C' lambda)_p.
//
// Allocation free after Data is built; never throws. With no loops this is
// hybrid_dynamics itself.
#pragma once
#include "soadyn/algorithms/steps.hpp"

namespace soadyn {

// data.qdd, data.tau as hybrid_dynamics; data.loops.multipliers (lambda),
// data.loops.wrench (per loop, [torque; force] of frame B's side on frame A's
// side, world axes, about frame A's origin), and the closure equations.
// Status: singular_articulated_inertia when M_rr is not positive definite,
// non_finite_result naming the first non-finite acceleration or force.
template <class S>
Status constrained_dynamics(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                            const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext = nullptr);

namespace detail {
// The solve behind constrained_dynamics, from what is already in `data`:
// mass_matrix (M), loops.bias (h - J' f_ext), loops.jacobian (C) and
// loops.kappa. Fills qdd, tau, loops.multipliers and loops.wrench. The same
// kernel solves the impulse problem of a mode switch in a loop model
// (M dv = tau + C' Lambda, C dv = -C v, dv_p given): bias = 0, kappa = -C v.
template <class S>
Status constrained_solve(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& u);
}  // namespace detail

template <class S>
S delassus_threshold() { return S(1e3) * Eigen::NumTraits<S>::epsilon(); }

}  // namespace soadyn
