// Data: every buffer the algorithms use, sized once from a Model. No
// algorithm allocates; results are read from the members named below.
// Memory policy: all allocation happens in the constructor. A Data belongs to
// the Model it was built from (same `model_version`); rebuild it after adding
// bodies. Flipping prescribed/regular flags needs no rebuild.
//
// Layout: the outputs users read sit at the top level of DataTpl; every
// intermediate quantity of the sweeps sits in `sweep` (SweepData). Each
// spatial quantity has one frame, named in its name: `body_` quantities are in
// body i's own frame about its origin (the recursion of Jain & Rodriguez,
// "Recursive Dynamics Algorithm for Multibody Systems with Prescribed Motion",
// ASME J. Mechanical Design 115(3), 1993, as written), `tree_` quantities in
// body i's tree frame (world orientation, origin at its tree's root body
// origin; sweeps/tree_frame_updates.hpp). Which algorithm fills which is
// said per member; docs/design/layout.md says which sweep runs when.
#pragma once
#include <Eigen/Cholesky>
#include "soadyn/model/loop_data.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {


// Scratch of one flexible body (n_m modal coordinates), flex/flexible_body.hpp,
// all in the body frame: its augmented mass matrix and the modal blocks of its
// articulated inertia.
template <class S>
struct FlexibleBodyData {
  explicit FlexibleBodyData(int n_modes);

  MatX<S> mass;                        // M(eta), (6 + n_m) square
  MatX<S> second_moment_rates;         // [sym D_0 ... sym D_{n_m-1}], packed (modal_integrals.hpp, Eq. 7)
  VecX<S> bias;                        // inertial bias (6 + n_m), modal_integrals.hpp
  VecX<S> modal_bias;                  // b_e + K eta + C eta_dot: modal rows of the body's own bias
  VecX<S> modal_bias_and_children_z;   // modal_bias + sum over bodies on nodes of Psi' z+ (articulated sweeps)
  VecX<S> modal_force;                 // generalized modal force of the Newton-Euler sweeps (RNEA)
  Mat6X<S> coupling;                   // P_Ve: rigid-modal block of the articulated inertia (6 x n_m)
  Eigen::Matrix<S, 3, Eigen::Dynamic> deformed_angular_coupling;  // M_we(eta) (3 x n_m): appendage_update.hpp, mode counts it has no compiled update for
  MatX<S> modal_inertia;               // P_ee (n_m x n_m), factored in place (Cholesky L) by the elimination
  MatX<S> gain_transpose;              // P_ee^-1 P_eV (n_m x 6)
  VecX<S> innovation;                  // P_ee^-1 (u_modal - modal rows of z)
};

// Intermediate quantities of the sweeps (see the top of this file for the
// frames). Read them only to debug an algorithm: which call last wrote a
// member, and whether it did at all, depends on the model's dynamics path.
template <class S>
struct SweepData {
  // Body frames: body-frame sweeps (aba.hxx), inverse dynamics, kinematics.
  aligned_vector<Mat6N<S>> body_subspace;              // H*(i)
  aligned_vector<Vec6<S>> body_joint_bias;             // dH*/dt qdot of the joint
  aligned_vector<Vec6<S>> body_coriolis;               // a(i) (Eq. 1)
  aligned_vector<Vec6<S>> body_bias_force;             // b(i) (Eq. 1): gyroscopic force minus external wrench
  aligned_vector<Mat6<S>> body_articulated_inertia;    // P(i) (Eq. 14)
  aligned_vector<Vec6<S>> body_bias_and_children_z;    // b(i) + sum of the children's z+: z(i) without P(i) a(i) (Eq. 28)
  aligned_vector<Mat6N<S>> body_regular_subspace;      // the regular columns of H*(i) (mixed hinges)
  aligned_vector<Mat6N<S>> body_gain;                  // G(i) = P H*_r D^-1 (Eq. 28)
  // Per body placed on a node of a flexible parent: the node's deformation
  // motion subspace Psi (6 x n_m of the parent) and the velocity-product part
  // of the node's motion relative to the parent's body frame, both in this
  // body's frame (flexible_updates.hpp).
  aligned_vector<Mat6X<S>> attachment_subspace;
  aligned_vector<Vec6<S>> attachment_bias;

  // Tree frames: tree-frame sweeps (tree_frame_sweeps.hxx), the composite-rigid-body mass matrix.
  aligned_vector<Transform<S>> tree_pose;              // body i in its tree frame; a constant leaf's rotation is left as it was by dynamics sweeps with neither f_ext nor joint wrenches (tree_velocity_update)
  aligned_vector<Mat6N<S>> tree_subspace;              // H*(i)
  aligned_vector<Vec6<S>> tree_velocity;               // V(i)
  aligned_vector<Vec6<S>> tree_coriolis;               // a(i)
  aligned_vector<Vec6<S>> tree_bias_force;             // b(i) of a rigid body (an appendage's is in body_bias_force)
  aligned_vector<Vec6<S>> tree_acceleration;           // alpha(i), including the -gravity base acceleration
  aligned_vector<Vec6<S>> tree_world_acceleration;     // of a root in its body frame: -gravity there
  aligned_vector<Vec6<S>> tree_hinge_force;            // f(i) (Eq. 29)
  aligned_vector<Mat6<S>> tree_articulated_inertia;    // P(i); the composite inertia in the mass matrix
  aligned_vector<Vec6<S>> tree_bias_and_children_z;    // b(i) + sum of the children's z+ (Eq. 28)
  aligned_vector<Mat6N<S>> tree_regular_subspace;      // the regular columns of H*(i) (mixed hinges)
  aligned_vector<Mat6N<S>> tree_gain;                  // G(i) = P H*_r D^-1
  Mat6X<S> tree_subspace_columns;  // H*(i) of every body side by side, 6 x nv: the mass matrix's columns (crba.hxx)
  aligned_vector<InertiaParameters<S>> tree_composite_inertia;  // the composite inertia's ten parameters (crba.hxx)
  // Per slot of model.angle_coordinates, zero-padded to a multiple of four: the
  // joint angle (sign times coordinate), its sine and its cosine
  // (sweeps/joint_angles.hpp).
  VecX<S> tree_joint_angle, tree_joint_sine, tree_joint_cosine;

  // Hinge coordinates (no frame).
  aligned_vector<VecN<S>> innovation;                  // nu(i) = D^-1 eps(i) (Eq. 28)
  // D(i) = H_r P H*_r + armature of the last tip-to-base hinge update, for
  // later solves with it: one regular DOF, D itself in (0, 0); more, its
  // Cholesky factor L (D = L L') in the lower triangle of the top-left
  // n_r x n_r block. A regular free root solved outright (free_root_inward):
  // P = L D L' (spd_factor6.hpp): L below the diagonal, 1/d_j on it.
  aligned_vector<Mat6<S>> hinge_factor;
  VecX<S> unit_acceleration;  // mass-matrix columns (flexible models, bodies beyond tree-frame reach)

  // Flexible bodies (empty without them), in the order of model.flexible_bodies.
  aligned_vector<FlexibleBodyData<S>> flexible;
};

template <class S>
struct DataTpl {
  explicit DataTpl(const ModelTpl<S>& model);

  std::uint64_t model_version;

  // Outputs.
  VecX<S> qdd;          // generalized accelerations (nv)
  VecX<S> tau;          // generalized forces (nv)
  MatX<S> mass_matrix;  // (nv x nv)
  // Spatial force across hinge i, exerted by the parent on body i, in body
  // i's frame about its origin (Eq. 29, f(i)): the joint reaction wrench.
  // Filled by inverse dynamics, and by hybrid dynamics when asked for.
  aligned_vector<Vec6<S>> hinge_force;
  // Kinematics (see model.hpp for conventions).
  aligned_vector<Transform<S>> pose_in_parent;  // body i in its parent body frame (or the world)
  aligned_vector<Transform<S>> pose_in_world;   // filled by forward_kinematics and the energy functions
  // Body velocity V(i), body frame: forward_kinematics (with v), the energy
  // functions, inverse dynamics, bias_forces and the body-frame sweeps.
  aligned_vector<Vec6<S>> body_velocity;
  // Body acceleration alpha(i), body frame, including the -gravity base
  // acceleration: inverse dynamics and the body-frame sweeps.
  aligned_vector<Vec6<S>> body_acceleration;

  SweepData<S> sweep;
  // Closed loops (model/loop_data.hpp): closure equations, multipliers, loop wrenches.
  LoopData<S> loops;
  // Force elements' values of the last dynamics call (model/force_element.hpp).
  ForceElementDataTpl<S> force_elements;
};

using Data = DataTpl<double>;
using DataF = DataTpl<float>;
extern template struct DataTpl<double>;
extern template struct DataTpl<float>;

}  // namespace soadyn
