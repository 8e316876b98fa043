// Joint types. Each joint maps its coordinates q (nq) and velocities v (nv)
// to the pose of the body frame in the joint frame, the motion subspace S
// (seed H*(k), body frame, 6 x nv) and the bias S' v (velocity-product part
// of the hinge acceleration). Velocities of multi-DOF joints on a Lie group
// (planar, spherical, free) are body-frame twists, so S is constant and their
// coordinates are integrated with the group's exponential map.
//
// Dispatch is a std::variant visited once per body per sweep: the joint type
// is resolved at compile time inside each alternative, with no virtual call.
#pragma once
#include <string>
#include <variant>
#include "soadyn/spatial/lie.hpp"

namespace soadyn {


// Rotation about a unit axis.
template <class S>
struct RevoluteJoint {
  static constexpr int nq = 1, nv = 1;
  Vec3<S> axis;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation.setZero();
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << axis, Vec3<S>::Zero(); }
};

// Translation along a unit axis.
template <class S>
struct PrismaticJoint {
  static constexpr int nq = 1, nv = 1;
  Vec3<S> axis;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation.setIdentity();
    pose.translation = axis * q[0];
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << Vec3<S>::Zero(), axis; }
};

// Screw motion: rotation q about the axis and translation pitch * q along it
// (pitch in metres of travel per radian).
template <class S>
struct HelicalJoint {
  static constexpr int nq = 1, nv = 1;
  Vec3<S> axis;
  S pitch;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation = axis * (pitch * q[0]);
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << axis, pitch * axis; }
};

// Rotation q0 about axis1, then q1 about axis2 (axis2 given in the frame
// rotated by q0). S depends on q1, hence a nonzero bias.
template <class S>
struct UniversalJoint {
  static constexpr int nq = 2, nv = 2;
  Vec3<S> axis1, axis2;
  void calc(const S* q, const S* v, Transform<S>& pose, Mat6N<S>& subspace, Vec6<S>& bias) const {
    const Mat3<S> r2 = axis_angle_rotation(axis2, q[1]);
    pose.rotation = axis_angle_rotation(axis1, q[0]) * r2;
    pose.translation.setZero();
    const Vec3<S> a1_body = r2.transpose() * axis1;
    subspace.col(0) << a1_body, Vec3<S>::Zero();
    subspace.col(1) << axis2, Vec3<S>::Zero();
    // d/dt (R2' a1) = -v1 [a2]x R2' a1, times v0.
    if (v)
      bias << (v[0] * v[1]) * a1_body.cross(axis2), Vec3<S>::Zero();
    else
      bias.setZero();
  }
  void fill_subspace(Mat6N<S>&) const {}  // configuration dependent, set in calc
};

// Rotation q0 about the axis and translation q1 along it.
template <class S>
struct CylindricalJoint {
  static constexpr int nq = 2, nv = 2;
  Vec3<S> axis;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation = axis * q[1];
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.col(0) << axis, Vec3<S>::Zero();
    s.col(1) << Vec3<S>::Zero(), axis;
  }
};

// Motion in the joint frame's x-y plane: q = (x, y, theta about z),
// v = (vx, vy, wz) in the body frame.
template <class S>
struct PlanarJoint {
  static constexpr int nq = 3, nv = 3;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(Vec3<S>(Vec3<S>::UnitZ()), q[2]);
    pose.translation << q[0], q[1], S(0);
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.setZero();
    s(3, 0) = S(1);
    s(4, 1) = S(1);
    s(2, 2) = S(1);
  }
};

// Ball joint: q = unit quaternion (x, y, z, w), v = body-frame angular velocity.
template <class S>
struct SphericalJoint {
  static constexpr int nq = 4, nv = 3;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = quaternion_rotation(q);
    pose.translation.setZero();
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.setZero();
    s.template topRows<3>().setIdentity();
  }
};

// Six DOF: q = (origin in the joint frame, unit quaternion (x, y, z, w)),
// v = (angular velocity, linear velocity of the origin), both in the body frame.
template <class S>
struct FreeJoint {
  static constexpr int nq = 7, nv = 6;
  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = quaternion_rotation(q + 3);
    pose.translation << q[0], q[1], q[2];
  }
  void fill_subspace(Mat6N<S>& s) const { s.setIdentity(); }
};

// Welds the body to its parent. Model::add_body merges a rigid body so
// welded into its parent; only a clamped flexible body reaches the dynamics
// sweeps with it (no hinge DOF, modal DOFs only).
template <class S>
struct FixedJoint {
  static constexpr int nq = 0, nv = 0;
  void calc(const S*, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const { pose = Transform<S>(); }
  void fill_subspace(Mat6N<S>&) const {}
};

template <class S>
using JointModel = std::variant<RevoluteJoint<S>, PrismaticJoint<S>, HelicalJoint<S>,
                                UniversalJoint<S>, CylindricalJoint<S>, PlanarJoint<S>,
                                SphericalJoint<S>, FreeJoint<S>, FixedJoint<S>>;

template <class S>
int joint_nq(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return std::decay_t<decltype(jj)>::nq; }, j);
}
template <class S>
int joint_nv(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return std::decay_t<decltype(jj)>::nv; }, j);
}
template <class S>
bool joint_is_fixed(const JointModel<S>& j) {
  return std::holds_alternative<FixedJoint<S>>(j);
}

// Offset of the unit quaternion inside the joint's q block, or -1.
template <class S>
int joint_quaternion_offset(const JointModel<S>& j) {
  if (std::holds_alternative<SphericalJoint<S>>(j)) return 0;
  if (std::holds_alternative<FreeJoint<S>>(j)) return 3;
  return -1;
}

// Pose, subspace and bias at (q, v); q and v point at the joint's blocks.
// Joints with a constant subspace and no bias leave `subspace` and `bias` as
// joint_init_subspace and Data's construction set them.
template <class S>
void joint_calc(const JointModel<S>& j, const S* q, const S* v, Transform<S>& pose, Mat6N<S>& subspace,
                Vec6<S>& bias) {
  std::visit([&](const auto& jj) { jj.calc(q, v, pose, subspace, bias); }, j);
}

// Sizes and fills the constant part of the motion subspace (once, at Data creation).
template <class S>
void joint_init_subspace(const JointModel<S>& j, Mat6N<S>& s) {
  s.setZero(6, joint_nv(j));
  std::visit([&](const auto& jj) { jj.fill_subspace(s); }, j);
}

// Neutral configuration: zeros, identity quaternions.
template <class S>
void joint_neutral(const JointModel<S>& j, S* q) {
  for (int i = 0; i < joint_nq(j); ++i) q[i] = S(0);
  const int qo = joint_quaternion_offset(j);
  if (qo >= 0) q[qo + 3] = S(1);
}

// q_out = q (+) v dt on the joint's manifold (may alias q).
template <class S>
void joint_integrate(const JointModel<S>& j, const S* q, const S* v, const S& dt, S* q_out);

// Suffixes naming the joint's coordinates and velocities ("" for 1-DOF joints).
template <class S>
const char* const* joint_coordinate_suffixes(const JointModel<S>& j);
template <class S>
const char* const* joint_velocity_suffixes(const JointModel<S>& j);
template <class S>
const char* joint_type_name(const JointModel<S>& j);

}  // namespace soadyn
