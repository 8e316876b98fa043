// Free joint: six DOF, q = (origin in the joint frame, unit quaternion
// (x, y, z, w)), v = (angular velocity, linear velocity of the origin), both
// in the body frame.
#pragma once
#include "soadyn/joints/spherical.hpp"

namespace soadyn {

// SE(3) as (position, unit quaternion) with body-frame twists. The chart
// around q0 is p = p0 + xi_p, quat = quat0 * exp(xi_r) with
// dxi_r/dt = Jr^-1(xi_r) w and dxi_p/dt = R(quat) u.
template <class S>
struct FreeSpace {
  static constexpr int nq = 7, nv = 6;
  static constexpr int quaternion_offset = 3;
  static constexpr bool scalar_coordinates = false;
  using Rotation = UnitQuaternionSpace<S>;

  static void neutral(S* q) {
    q[0] = q[1] = q[2] = S(0);
    Rotation::neutral(q + 3);
  }
  // Body-frame twist (w, u) dt applied on SE(3): p += R V(phi) u dt, with
  // V the left Jacobian of SO(3), and quat *= exp(phi).
  static void integrate(const S* q, const S* v, const S& dt, S* out) {
    const Vec3<S> phi = Vec3<S>(v[0], v[1], v[2]) * dt;
    const Vec3<S> u = Vec3<S>(v[3], v[4], v[5]) * dt;
    const Vec3<S> dp = quaternion_rotation(q + 3) * (so3_left_jacobian(phi) * u);
    for (int i = 0; i < 3; ++i) out[i] = q[i] + dp[i];
    Rotation::rotate(q + 3, phi, out + 3);
  }
  static void retract(const S* q0, const S* xi, S* q) {
    for (int k = 0; k < 3; ++k) q[k] = q0[k] + xi[3 + k];
    Rotation::retract(q0 + 3, xi, q + 3);
  }
  static void chart_rate(const S* q, const S* xi, const S* v, S* rate) {
    Rotation::chart_rate(q + 3, xi, v, rate);
    Eigen::Map<Vec3<S>>{rate + 3} = quaternion_rotation(q + 3) * Vec3<S>(v[3], v[4], v[5]);
  }
  // The chart's first-order maps (joints/vector_space.hpp): the rotation's as
  // the spherical joint's; the position p = p0 + xi_p has body-frame tangent
  // R(q)' dp, and its rate R(q) u turns with the rotation.
  static void base_transport(const S* q0, const S* q, const S* xi, MatX<S>& T, int o) {
    Rotation::base_transport(q0 + 3, q + 3, xi, T, o);
    T.template block<3, 3>(o + 3, o + 3) = T.template block<3, 3>(o, o);  // R' R0 = exp(xi)'
  }
  static void chart_transport(const S* q0, const S* q, const S* xi, MatX<S>& T, int o) {
    Rotation::chart_transport(q0 + 3, q + 3, xi, T, o);
    T.template block<3, 3>(o + 3, o + 3) = quaternion_rotation(q + 3).transpose();
  }
  static void rate_jacobians(const S* q0, const S* q, const S* xi, const S* v, MatX<S>& d_base, MatX<S>& d_xi,
                             MatX<S>& d_v, int o) {
    Rotation::rate_jacobians(q0 + 3, q + 3, xi, v, d_base, d_xi, d_v, o);
    const Mat3<S> R = quaternion_rotation(q + 3);
    const Mat3<S> turn = -R * skew(Vec3<S>(v[3], v[4], v[5]));
    d_v.template block<3, 3>(o + 3, o + 3) = R;
    d_xi.template block<3, 3>(o + 3, o) = turn * so3_right_jacobian(Vec3<S>(xi[0], xi[1], xi[2]));
    d_base.template block<3, 3>(o + 3, o) = turn * Rotation::exp_rotation(xi).transpose();
  }
  static void bracket(const S* v, MatX<S>& ad, int o) {  // se(3): [(w, u), (w', u')] = (w x w', w x u' - w' x u)
    const Mat3<S> w = skew(Vec3<S>(v[0], v[1], v[2]));
    ad.template block<3, 3>(o, o) = w;
    ad.template block<3, 3>(o + 3, o + 3) = w;
    ad.template block<3, 3>(o + 3, o) = skew(Vec3<S>(v[3], v[4], v[5]));
  }
};

template <class S>
struct FreeJoint {
  static constexpr const char* name = "free";
  static constexpr const char* description =
      "Six DOF: q = (position, quaternion x y z w), v = body-frame (angular, linear velocity of the origin).";
  using Parameters = std::tuple<>;
  static constexpr std::array<const char*, 0> parameter_names{};
  using Space = FreeSpace<S>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 7> coordinate_suffixes{"px", "py", "pz", "qx", "qy", "qz", "qw"};
  static constexpr std::array<const char*, 6> velocity_suffixes{"wx", "wy", "wz", "vx", "vy", "vz"};

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = quaternion_rotation(q + 3);
    pose.translation << q[0], q[1], q[2];
  }
  void fill_subspace(Mat6N<S>& s) const { s.setIdentity(); }
  void random(CoordinateSampler& draw, S* q) const {
    draw.skip(7);
    for (int k = 0; k < 3; ++k) q[k] = S(draw.offset());
    draw.unit_quaternion(q + 3);
  }
  void check(const std::string&) {}

  JointFastPath fast_path(S& sign) const {
    sign = S(1);
    return JointFastPath::free;
  }
  // Tree-frame fast path (sweeps/tree_frame_updates.hpp): pose = base * joint
  // pose (a root body's origin at the tree origin) and H* = X(pose), which
  // carries body twists to tree-frame twists. No bias (S is constant).
  static SOADYN_ALWAYS_INLINE void tree_update(const Transform<S>& base, const S* q, bool root, Transform<S>& pose,
                                             Mat6N<S>& s) {
    Transform<S> joint_pose;
    joint_pose.rotation = quaternion_rotation(q + 3);
    joint_pose.translation << q[0], q[1], q[2];
    pose = base * joint_pose;
    if (root) pose.translation.setZero();
    for (int c = 0; c < 3; ++c) {
      s.col(c) << pose.rotation.col(c), pose.translation.cross(Vec3<S>(pose.rotation.col(c)));
      s.col(c + 3) << Vec3<S>::Zero(), pose.rotation.col(c);
    }
  }
};

}  // namespace soadyn
