// Analytic derivatives of inverse dynamics and of the hybrid dynamics of a
// rigid tree with respect to q, v and the inputs u.
//
// inverse_dynamics_derivatives differentiates the Newton-Euler recursion
// (Jain & Rodriguez 1993, Eqs. 1-4) in one outward and one inward sweep, in the
// manner of Carpentier & Mansard, "Analytical Derivatives of Rigid Body
// Dynamics Algorithms", Robotics: Science and Systems, 2018: every spatial
// quantity in the tree frame (world orientation, a fixed origin), where a
// change of DOF k's coordinate turns everything outboard of it rigidly about
// its motion axis. O(N d) for tree depth d; the mass matrix comes out of the
// same inward sweep (the composite-rigid-body algorithm).
//
// dynamics_derivatives differentiates the hybrid problem (hybrid.hpp): with R
// the regular and P the prescribed DOFs, inverse dynamics ID(q, v, qdd) = tau
// gives, for x in {q, v} (Jain & Rodriguez 1993, Eq. 12, differentiated),
//   dqdd_R/dx = -M_RR^-1 dID_R/dx,           dqdd_P/dx = 0,
//   dtau_P/dx = dID_P/dx + M_PR dqdd_R/dx,    dtau_R/dx = 0,
// and for the inputs (u_R = tau_R, u_P = qdd_P)
//   dqdd/du = M~^-1 (I - M_RP),  dtau_P/du = M_P. dqdd/du,  dtau_R/du = [I 0],
// with M~ the mass matrix whose prescribed rows and columns are the identity,
// factored with the tree's sparsity (tree_cholesky.hpp). With no prescribed
// DOF this is the derivative of forward dynamics, dqdd/du = M^-1. The hybrid
// dynamics itself comes from the same sweeps and factor (qdd_R = M_RR^-1
// (u_R - ID_R(q, v, 0) - M_RP u_P), tau_P = ID_P(q, v, qdd)): no
// articulated-body pass.
//
// Derivatives with respect to q are taken in the tangent space: column k is
// d/de of the output at integrate(q, e e_k) (nv columns: a quaternion joint's
// columns are body-frame rotations, as its velocities are), the convention of
// Pinocchio's derivatives.
//
// Joint springs (model/force_element.hpp) are included: inverse
// dynamics carries their -Q = k (q - rest) + c v. Rigid bodies only, and no
// point springs: building the workspace of a model with a flexible body or a
// point spring throws std::invalid_argument naming it. Loop models: the functions
// differentiate the spanning tree's dynamics (constrained_dynamics'
// derivatives are assembled from them and the closure terms in Python).
#pragma once
#include <stdexcept>
#include <vector>

#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// Whether the analytic sweeps refuse `model` (a flexible body or a point
// spring): its derivatives then come from the dual-number sweeps
// (parameter_sensitivity.hpp), as LinearizationTpl and StaticStiffness do.
template <class S>
bool needs_dual_derivatives(const ModelTpl<S>& model) {
  return model.has_flexible_bodies() || !model.force_elements.point_springs.empty();
}

// Tag of the workspace that holds the eight output matrices only, for
// derivatives computed elsewhere (LinearizationTpl with the dual-number
// sweeps); no model is refused.
struct OutputsOnly {};

template <class S>
struct DynamicsDerivativesTpl {
  explicit DynamicsDerivativesTpl(const ModelTpl<S>& model);
  DynamicsDerivativesTpl(const ModelTpl<S>& model, OutputsOnly);

  // inverse_dynamics_derivatives: dID/dq and dID/dv (nv x nv); dID/dqdd = M
  // is written to data.mass_matrix.
  MatX<S> inverse_dq, inverse_dv;
  // dynamics_derivatives (nv x nv each).
  MatX<S> dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du;

  // Scratch, tree frame. Per body: the subtree's inertia, Coriolis factor
  // B(I, V) (coriolis_inertia.hpp) and Newton-Euler force, and the body's
  // spatial acceleration alpha (with the -gravity base acceleration).
  aligned_vector<Mat6<S>> composite_inertia, composite_coriolis_inertia;
  aligned_vector<Vec6<S>> composite_force, acceleration;
  // Per body: its own inertia and velocity force V x* (I V) - f_ext.
  aligned_vector<Mat6<S>> body_inertia;
  aligned_vector<Vec6<S>> velocity_force;
  // Per DOF k with axis H_k and "inboard" velocity V- and acceleration A-
  // (the parent body's, or for a universal joint's second axis its middle
  // frame's): displacement_lever H_k x V-, displacement_acceleration
  // -H_k x A- + (H_k x V-) x V-, velocity_acceleration (V_r + V-) x H_k
  // with V_r the velocity that turns H_k (dH_k/dt = V_r x H_k).
  // dof_axis: H_k, the motion axis of DOF k in the tree frame; inertia_axis
  // and coriolis_t_axis: Ic H_k and Bc' H_k with the subtree sums of k's body.
  Mat6X<S> displacement_lever, displacement_acceleration, velocity_acceleration, dof_axis;
  Mat6X<S> inertia_axis, coriolis_t_axis;
  MatX<S> regular_mass;  // M~, factored in place (tree_cholesky.hpp)
  VecX<S> inverse_force;  // ID(q, v, qdd) of the last derivative sweeps
  MatX<S> inverse_factor;  // W = U^-1 for the factor M~ = U U' (nv x nv)
  std::vector<int> subtree_end;  // per DOF: the last DOF of its subtree (DOFs k..subtree_end[k])
};

using DynamicsDerivatives = DynamicsDerivativesTpl<double>;
using DynamicsDerivativesF = DynamicsDerivativesTpl<float>;

// dID/dq and dID/dv at (q, v, qdd, f_ext) into derivatives.inverse_dq and
// inverse_dv, M(q) into data.mass_matrix, ID itself into data.tau. `f_ext` as
// in inverse_dynamics (body-frame wrenches, turning with their bodies).
// Allocation free; returns non_finite_result naming the first bad column.
template <class S>
Status inverse_dynamics_derivatives(const ModelTpl<S>& model, DataTpl<S>& data, DynamicsDerivativesTpl<S>& derivatives,
                                    const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& qdd,
                                    const S* f_ext = nullptr);

// The hybrid dynamics (data.qdd, data.tau, as hybrid_dynamics) and its six
// derivatives dqdd_dq ... dtau_du (see the top of this file). Allocation free;
// returns the hybrid dynamics' status, singular_articulated_inertia naming
// the DOF whose pivot of M_RR is not positive, or non_finite_result.
template <class S>
Status dynamics_derivatives(const ModelTpl<S>& model, DataTpl<S>& data, DynamicsDerivativesTpl<S>& derivatives,
                            const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& u,
                            const S* f_ext = nullptr);

extern template struct DynamicsDerivativesTpl<double>;
extern template struct DynamicsDerivativesTpl<float>;

}  // namespace soadyn
