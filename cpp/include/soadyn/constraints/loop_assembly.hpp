// Assembly and projection onto the loop-closure manifold: the position
// equations Psi(q) = 0 and the velocity equations C v = 0 ("Joint Coordinate
// Method, Part 1", Eqs. 1.6-1.7) solved for the DOFs that are not held, and
// the partition of the DOFs into independent and dependent ones (Eqs.
// 1.16-1.20, largest pivots).
//
// Metric. Corrections are minimum-norm in the Euclidean norm of the tangent
// coordinates of the free DOFs: dq = -C_f' (C_f C_f')^+ Psi, with C_f the
// constraint Jacobian with the held DOFs' columns zeroed and ^+ the pivoted-
// Cholesky pseudo-inverse of semidefinite_solve.hpp, so redundant closure
// equations (a planar four-bar closed by a revolute cut) need no special
// case. Positions iterate (Gauss-Newton with step halving); velocities are
// linear and take one projection: v <- v - C_f' (C_f C_f')^+ C v.
//
// assemble_loops and project_loop_velocity allocate nothing and never throw
// (the simulator runs them after every step); independent_coordinates
// allocates and is for analysis.
#pragma once
#include <vector>
#include "soadyn/sweeps/body_updates.hpp"
#include "soadyn/core/interrupt.hpp"

namespace soadyn {

// Position closure in place. `free[k]` != 0: DOF k may move. Stops when every
// |Psi_i| <= tolerance (Status ok); after max_iterations Gauss-Newton steps
// (StatusCode::loop_not_closed, index: the loop with the largest residual);
// when assembly_stall_steps steps in a row, each halved down to 2^-20 of its
// length, did not lower the largest residual, or assembly_halving_steps steps
// did not halve it (StatusCode::loop_assembly_stalled: the DOFs allowed to
// move cannot close the loop from here, e.g. every DOF of the loop is held,
// or creep towards a configuration they cannot reach); or when `interrupt` asks
// (StatusCode::interrupted). `iterations`, if given, receives the number of
// steps taken.
template <class S>
Status assemble_loops(const ModelTpl<S>& model, DataTpl<S>& data, VecRef<S> q, const ConstVecRef<S>& free,
                      S tolerance, int max_iterations, int* iterations = nullptr, const Interrupt* interrupt = nullptr);

// Gauss-Newton steps in a row without progress, and steps without halving
// the largest residual, after which assembly stops. Gauss-Newton halves it in
// a step or two near a regular closure and in a handful where it converges
// linearly (redundant equations, near a dead centre).
constexpr int assembly_stall_steps = 3;
constexpr int assembly_halving_steps = 25;

// Velocity closure in place: the free DOFs' velocities change by the
// smallest correction that makes C v = 0 (least squares when the held DOFs'
// velocities make it impossible). Runs forward kinematics at q.
template <class S>
Status project_loop_velocity(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, VecRef<S> v,
                             const ConstVecRef<S>& free);

// Coordinate partitioning at q: the DOFs whose columns of C are the pivots
// of a fully pivoted LU factorisation (largest pivots first) are dependent;
// the others, in DOF order, are independent. Pivots below
// loop_rank_threshold() times the largest count as zero.
template <class S>
std::vector<int> independent_coordinates(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

// Default tolerance of the closure: 1e-12, or 1e3 machine epsilons when larger (float).
template <class S>
S default_closure_tolerance() {
  const S floor = S(1e3) * Eigen::NumTraits<S>::epsilon();
  return floor > S(1e-12) ? floor : S(1e-12);
}

}  // namespace soadyn
