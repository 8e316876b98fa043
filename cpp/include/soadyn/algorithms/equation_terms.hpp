// The equations of motion term by term: M(q) qdd + C(q, v) v + g(q) = tau + J' f_ext.
//
//   gravity_forces                  g(q)                      (data.tau)
//   external_forces_to_generalized  J' f_ext                  (data.tau)
//   coriolis_matrix                 C(q, v), nv x nv          (caller's matrix)
//   mass_matrix_derivative          Mdot(q, v) = C + C'       (caller's matrix)
//   christoffel_symbols             Gamma, nv x nv x nv       (caller's matrix, nv x nv*nv)
//
// C is the one of Echeandia & Wensing, "Numerical Methods to Compute the
// Coriolis Matrix and Christoffel Symbols for Rigid-Body Systems", ASME J.
// Computational and Nonlinear Dynamics 16(9), 2021: C v = h(q, v) - g(q) and
// Mdot - 2 C is skew-symmetric. For joints whose coordinates are the
// velocities' integrals (every joint but spherical, planar and free) it is the
// Christoffel C, C(i, j) = sum_k Gamma(i, j, k) v_k with
// Gamma(i, j, k) = 1/2 (dM(i,j)/dq_k + dM(i,k)/dq_j - dM(j,k)/dq_i), symmetric
// in (j, k). For spherical, planar and free joints v is a body-frame (quasi-)velocity;
// derivatives along DOF k are then taken along q (+) eps e_k (the model's
// integrate), and Gamma(i, j, k) is the Levi-Civita connection in that moving
// frame, 2 Gamma(i,j,k) = dM(i,j)/dq_k + dM(i,k)/dq_j - dM(j,k)/dq_i
//   + <[e_k, e_j], e_i> - <[e_k, e_i], e_j> - <[e_j, e_i], e_k>  (<a, b> = a' M b),
// with the Lie bracket of the joint's body twists; Gamma(i, j, k) - Gamma(i, k, j)
// = <[e_k, e_j], e_i> is then its only departure from symmetry in (j, k).
//
// C, Mdot and Gamma are those of rigid bodies: a model with a flexible body
// is refused when the workspace is built (std::invalid_argument naming the
// body); the modal coordinates' velocity products come from the flexible
// body's own terms, which have no Christoffel form here. gravity_forces and
// external_forces_to_generalized take every model (flexible bodies included;
// g is gravity only, elastic forces are not part of it). On loop models every
// term is the spanning tree's; the loop forces enter through loop_jacobian.
//
// C is formed in tree frames (tree_frame_updates.hpp) for every body: unlike
// mass_matrix there is no body-frame fallback for a body beyond its
// tree-frame reach (tree_frame_reach.hxx), whose entries then lose relative
// precision as the tree-frame sweeps do there.
#pragma once
#include <stdexcept>
#include <string>

#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// Per-body scratch of coriolis_matrix, sized once from the model (the only
// allocation). Throws std::invalid_argument for a model with flexible bodies.
template <class S>
struct EquationTermsWorkspace {
  explicit EquationTermsWorkspace(const ModelTpl<S>& model);
  aligned_vector<Mat6<S>> composite_inertia;          // sum of the subtree's spatial inertias, tree frame
  aligned_vector<Mat6<S>> composite_coriolis_inertia;  // sum of the subtree's B(I, V), tree frame
  aligned_vector<Mat6N<S>> subspace_rate;              // dH*/dt of each hinge, tree frame
  VecX<S> unit_velocity;                               // e_k of christoffel_symbols
};

// data.tau = g(q), the generalized gravity forces (h at v = 0).
template <class S>
Status gravity_forces(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

// data.tau = J' f_ext; f_ext: nbodies x 6 body-frame wrenches [torque; force]
// about each body origin (the convention of forward_dynamics).
template <class S>
Status external_forces_to_generalized(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                                      const S* f_ext);

// coriolis = C(q, v) (nv x nv), O(N d) with d the tree depth (O(N^2) at worst).
template <class S>
Status coriolis_matrix(const ModelTpl<S>& model, DataTpl<S>& data, EquationTermsWorkspace<S>& workspace,
                       const ConstVecRef<S>& q, const ConstVecRef<S>& v, Eigen::Ref<MatX<S>> coriolis);

// mass_rate = dM/dt along v = C + C' (nv x nv); `coriolis` receives C.
template <class S>
Status mass_matrix_derivative(const ModelTpl<S>& model, DataTpl<S>& data, EquationTermsWorkspace<S>& workspace,
                              const ConstVecRef<S>& q, const ConstVecRef<S>& v, Eigen::Ref<MatX<S>> coriolis,
                              Eigen::Ref<MatX<S>> mass_rate);

// christoffel (nv x nv*nv): column block k is Gamma(:, :, k) = C(q, e_k), so
// C(q, v) = sum_k v_k Gamma(:, :, k). O(nv N d).
template <class S>
Status christoffel_symbols(const ModelTpl<S>& model, DataTpl<S>& data, EquationTermsWorkspace<S>& workspace,
                           const ConstVecRef<S>& q, Eigen::Ref<MatX<S>> christoffel);

}  // namespace soadyn
