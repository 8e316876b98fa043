// Cylindrical joint: rotation q0 about a unit axis and translation q1 along it.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

template <class S>
struct CylindricalJoint {
  static constexpr const char* name = "cylindrical";
  static constexpr const char* description = "Rotation about and translation along `axis`: ':angle', ':offset'.";
  using Parameters = std::tuple<Vec3<S>>;
  static constexpr std::array<const char*, 1> parameter_names{"axis"};
  using Space = VectorSpace<S, 2>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 2> coordinate_suffixes{"angle", "offset"},
      velocity_suffixes{"angle", "offset"};

  Vec3<S> axis;

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation = axis * q[1];
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.col(0) << axis, Vec3<S>::Zero();
    s.col(1) << Vec3<S>::Zero(), axis;
  }
  void random(CoordinateSampler& draw, S* q) const {
    q[0] = S(draw.angle());
    draw.skip(1);
    q[1] = S(draw.offset());
  }
  void check(const std::string& joint_name) { axis = checked_joint_axis(axis, joint_name, "axis"); }
};

}  // namespace soadyn
