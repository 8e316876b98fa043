// Force elements: springs and dampers that act between bodies, stored in the
// model as plain fields so their parameters can be read and changed in place.
//
// A joint spring acts on one DOF whose coordinate is a scalar with q' = v
// (revolute, prismatic, helical, cylindrical, universal, translation joints):
// generalized force Q = -stiffness (q - rest) - damping v. DOFs of planar,
// spherical and free joints (rotation coordinates are not scalars) and modal
// DOFs are refused.
//
// A point spring acts along the line between point A (fixed in frame_a's
// body) and point B (fixed in frame_b's body, or in the world). With length L
// and length rate L', its tension is
//   T = stiffness (L - rest_length) + F(L) + damping L',
// F the optional force law (force_law.hpp; zero without one); A is pulled
// towards B by T and B towards A by T (equal and opposite forces at the two
// points). At L = 0 the line is undefined and the element exerts no force.
// Its potential is 1/2 stiffness (L - rest_length)^2 + int_{l_0}^{L} F, l_0
// the force law's first length.
#pragma once
#include <string>
#include <vector>
#include "soadyn/model/force_law.hpp"
#include "soadyn/spatial/types.hpp"

namespace soadyn {

template <class S>
struct JointSpringTpl {
  std::string name;
  int dof = -1;         // velocity index
  int coordinate = -1;  // its coordinate index (q' = v)
  S stiffness = S(0), damping = S(0), rest = S(0);
};

template <class S>
struct PointSpringTpl {
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  std::string name;
  int body_a = -1, body_b = -1;  // -1: the world
  Vec3<S> point_a = Vec3<S>::Zero(), point_b = Vec3<S>::Zero();  // in the body frame (world frame for the world)
  S stiffness = S(0), damping = S(0), rest_length = S(0);
  ForceLawTpl<S> force_law;  // empty: linear spring only
};

template <class S>
struct ForceElementsTpl {
  std::vector<JointSpringTpl<S>> joint_springs;
  aligned_vector<PointSpringTpl<S>> point_springs;

  bool empty() const { return joint_springs.empty() && point_springs.empty(); }
  bool has_name(const std::string& name) const {
    for (const auto& e : joint_springs)
      if (e.name == name) return true;
    for (const auto& e : point_springs)
      if (e.name == name) return true;
    return false;
  }
};

// Per-call values of the force elements (Data::force_elements), sized once.
template <class S>
struct ForceElementDataTpl {
  VecX<S> joint_force;     // Q of each joint spring
  VecX<S> length, length_rate, tension;  // per point spring
  VecX<S> body_wrench;     // nbodies x 6: the caller's f_ext plus the point springs', body frames
  VecX<S> input;           // the caller's u with the joint springs added on regular rows
};

}  // namespace soadyn
