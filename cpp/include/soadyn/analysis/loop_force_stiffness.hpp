// Stiffness of the cut-joint reactions: d(C(q)' nu)/dq at fixed multipliers
// nu, the loop part of the Newton matrix of static equilibrium
// ("Joint Coordinate Method, Part 1", Eq. 1.34: d(B'g + C' nu)/d theta).
//
// Derivatives with respect to q are taken in the tangent space, as
// inverse_dynamics_derivatives takes them: column k is d/de at
// integrate(q, e e_k).
//
// Derivation. Loop l contributes C_l' nu_l = J_A(p_A)' w - J_B(P)' w with
// w = W nu_l = [tau; f] the world-aligned wrench about A's origin p_A
// (model/loop.hpp). Moved to the world origin, w_O = [tau + p x f; f], and
// with psi_j = [omega_j; c_j] DOF j's world Plucker axis (about the world
// origin), J(p)' w = psi_j . w_O row by row. When q_k changes:
//   - psi_j turns with every DOF k inboard of it (or of its own joint):
//     d psi_j = psi_k x psi_j (a universal joint's first axis does not turn
//     with its second angle);
//   - the point p moves with the body carrying it: d w_O = [dp x f; 0] with
//     dp = c_k + omega_k x p, the point's velocity per unit qdot_k;
//   - W itself turns: x_A, y_A of a revolute loop with body A, x_B, y_B of a
//     prismatic loop with body B, and a distance loop's n = d/|d| changes by
//     (I - n n') dd / |d|; this adds J_rel' (dW/dq_k) nu_l to column k.
// Cost O(sum over loops of depth^2); allocation free after Data is built.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// out (nv x nv) = d(C(q)' nu)/dq, nu: the model's nloop_equations
// multipliers (lambda of constrained_dynamics: M qdd + h = tau + C' lambda).
// Runs forward kinematics and leaves Psi(q) in data.loops.residual and C(q)
// in data.loops.jacobian. Status: non_finite_result naming the first
// non-finite column. A model without loops gives zero.
template <class S>
Status loop_force_stiffness(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                            const ConstVecRef<S>& nu, Eigen::Ref<MatX<S>> out);

}  // namespace soadyn
