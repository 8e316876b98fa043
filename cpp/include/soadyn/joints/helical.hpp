// Helical (screw) joint: rotation q about a unit axis and translation
// pitch * q along it (pitch in metres of travel per radian).
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

template <class S>
struct HelicalJoint {
  static constexpr const char* name = "helical";
  static constexpr const char* description = "Screw about `axis`: `pitch` metres of travel per radian. One DOF.";
  using Parameters = std::tuple<Vec3<S>, S>;
  static constexpr std::array<const char*, 2> parameter_names{"axis", "pitch"};
  using Space = VectorSpace<S, 1>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 1> coordinate_suffixes{""}, velocity_suffixes{""};

  Vec3<S> axis;
  S pitch;

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation = axis * (pitch * q[0]);
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << axis, pitch * axis; }
  void random(CoordinateSampler& draw, S* q) const { q[0] = S(draw.angle()); }
  void check(const std::string& joint_name) {
    axis = checked_joint_axis(axis, joint_name, "axis");
    if (!std::isfinite(static_cast<double>(pitch)))
      throw std::invalid_argument("joint '" + joint_name + "': pitch is not finite");
  }
};

}  // namespace soadyn
