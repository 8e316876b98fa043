// Data: every buffer the algorithms use, sized once from a Model. No
// algorithm allocates; results are read from the members named below.
// Memory policy: all allocation happens in the constructor. A Data belongs to
// the Model it was built from (same `model_version`); rebuild it after adding
// bodies. Flipping prescribed/regular flags needs no rebuild.
#pragma once
#include <Eigen/Cholesky>
#include "soadyn/model.hpp"

namespace soadyn {

template <class S> using Mat6X = Eigen::Matrix<S, 6, Eigen::Dynamic>;

// Scratch of one flexible body (n_m modal coordinates), flex/flexible_body.hpp:
// its augmented mass matrix and the modal blocks of its articulated inertia.
template <class S>
struct FlexibleBodyData {
  explicit FlexibleBodyData(int n_modes);

  MatX<S> mass;                   // M(eta), (6 + n_m) square
  MatX<S> second_moment_rates;    // [D_0 ... D_{n_m-1}] (modal_integrals.hpp, Eq. 7)
  VecX<S> bias;                   // inertial bias (6 + n_m), modal_integrals.hpp
  VecX<S> modal_bias;             // modal rows of the body's bias; then of z (articulated) or the modal force (RNEA)
  Mat6X<S> coupling;              // rigid-modal block of the articulated inertia (6 x n_m)
  MatX<S> modal_inertia;          // modal block of the articulated inertia (n_m x n_m); its Cholesky factor after elimination
  MatX<S> gain_transpose;         // modal_inertia^-1 coupling' (n_m x 6); tree frames: M_ee^-1 M_eV, body frame
  VecX<S> innovation;             // modal_inertia^-1 (u_modal - modal rows of z)
};

template <class S>
struct DataTpl {
  explicit DataTpl(const ModelTpl<S>& model);

  std::uint64_t model_version;

  // Kinematics (body frames; see model.hpp for conventions).
  aligned_vector<Transform<S>> pose_in_parent;  // body i in its parent body frame (or the world)
  aligned_vector<Transform<S>> pose_in_world;   // filled by forward_kinematics and the energy functions
  aligned_vector<Mat6N<S>> subspace;            // S(i) = seed H*(i), body frame
  aligned_vector<Vec6<S>> joint_bias;           // dS/dt v of the joint
  aligned_vector<Vec6<S>> velocity;             // seed V(i)
  aligned_vector<Vec6<S>> coriolis;             // seed a(i)
  aligned_vector<Vec6<S>> bias_force;           // seed b(i): gyroscopic force minus external wrench
  aligned_vector<Vec6<S>> acceleration;         // seed alpha(i), including the -gravity base acceleration
  // Spatial force across hinge i, exerted by the parent on body i, in body
  // i's frame about its origin (seed f(i)): the joint reaction wrench.
  aligned_vector<Vec6<S>> hinge_force;

  // Rigid models, and flexible models with no body on a node: forward and
  // hybrid dynamics work in tree frames (algorithms/tree_frame_steps.hpp) and
  // leave velocity, coriolis, bias_force (a flexible body's stays in its body
  // frame), acceleration and the articulated quantities in tree-frame
  // coordinates; every other algorithm leaves them in body frames.
  aligned_vector<Transform<S>> tree_pose;  // body i in its tree frame
  aligned_vector<Mat6N<S>> tree_subspace;  // S(i) in the tree frame

  // Articulated-body quantities (seed Eq. 14, 28). Also used as composite
  // inertia scratch by the mass matrix.
  aligned_vector<Mat6<S>> articulated_inertia;  // P(i)
  aligned_vector<Vec6<S>> articulated_bias;     // z(i) before the hinge's own terms
  aligned_vector<Mat6N<S>> regular_subspace;    // S columns of the regular DOFs (mixed hinges)
  aligned_vector<Mat6N<S>> gain;                // G(i) = P S_r D^-1
  aligned_vector<VecN<S>> innovation;           // nu(i) = D^-1 eps(i)

  // Flexible bodies (empty without them). Per flexible body, in the order of
  // model.flexible_bodies:
  std::vector<FlexibleBodyData<S>, Eigen::aligned_allocator<FlexibleBodyData<S>>> flexible;
  // Per body placed on a node of a flexible parent: the node's deformation
  // motion subspace in this body's frame (6 x n_m of the parent) and the
  // velocity-product part of the node's motion relative to the parent's
  // body frame, also in this body's frame (flexible_steps.hpp).
  aligned_vector<Mat6X<S>> attachment_subspace;
  aligned_vector<Vec6<S>> attachment_bias;
  VecX<S> unit_acceleration;  // mass-matrix columns (flexible models, bodies beyond tree-frame reach)

  // Outputs.
  VecX<S> qdd;          // generalized accelerations (nv)
  VecX<S> tau;          // generalized forces (nv)
  MatX<S> mass_matrix;  // (nv x nv)
};

using Data = DataTpl<double>;
using DataF = DataTpl<float>;
extern template struct DataTpl<double>;
extern template struct DataTpl<float>;

}  // namespace soadyn
