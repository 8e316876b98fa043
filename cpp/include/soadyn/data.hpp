// Data: every buffer the algorithms use, sized once from a Model. No
// algorithm allocates; results are read from the members named below.
// Memory policy: all allocation happens in the constructor. A Data belongs to
// the Model it was built from (same `model_version`); rebuild it after adding
// bodies. Flipping prescribed/regular flags needs no rebuild.
#pragma once
#include "soadyn/model.hpp"

namespace soadyn {

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

  // Articulated-body quantities (seed Eq. 14, 28). Also used as composite
  // inertia scratch by the mass matrix.
  aligned_vector<Mat6<S>> articulated_inertia;  // P(i)
  aligned_vector<Vec6<S>> articulated_bias;     // z(i) before the hinge's own terms
  aligned_vector<Mat6N<S>> regular_subspace;    // S columns of the regular DOFs (mixed hinges)
  aligned_vector<Mat6N<S>> gain;                // G(i) = P S_r D^-1
  aligned_vector<VecN<S>> innovation;           // nu(i) = D^-1 eps(i)

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
