// Spherical (ball) joint: q = unit quaternion (x, y, z, w), v = body-frame
// angular velocity.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

// SO(3) as unit quaternions with body-frame angular velocities. The chart
// around quat0 is quat = quat0 * exp(xi) with dxi/dt = Jr^-1(xi) w, Jr^-1 the
// inverse right Jacobian of SO(3) (spatial/lie.hpp): integration only ever
// multiplies by exact exponentials, so quaternions stay on the unit sphere.
template <class S>
struct UnitQuaternionSpace {
  static constexpr int nq = 4, nv = 3;
  static constexpr int quaternion_offset = 0;
  static constexpr bool scalar_coordinates = false;

  static void neutral(S* q) {
    q[0] = q[1] = q[2] = S(0);
    q[3] = S(1);
  }
  // out = quat * exp(phi) (may alias quat).
  static void rotate(const S* quat, const Vec3<S>& phi, S* out) {
    const Eigen::Matrix<S, 4, 1> e = quaternion_exp(phi);
    const Eigen::Matrix<S, 4, 1> r = quaternion_multiply(quat, e.data());
    for (int i = 0; i < 4; ++i) out[i] = r[i];
  }
  static void integrate(const S* q, const S* v, const S& dt, S* out) {
    rotate(q, Vec3<S>(Vec3<S>(v[0], v[1], v[2]) * dt), out);
  }
  static void retract(const S* q0, const S* xi, S* q) { rotate(q0, Vec3<S>(xi[0], xi[1], xi[2]), q); }
  static void chart_rate(const S*, const S* xi, const S* w, S* rate) {
    Eigen::Map<Vec3<S>>{rate} = so3_right_jacobian_inverse_times(Vec3<S>(xi[0], xi[1], xi[2]), Vec3<S>(w[0], w[1], w[2]));
  }
  // The chart's first-order maps (joints/vector_space.hpp): q = q0 exp(xi), so
  // q0 exp(e) exp(xi) = q exp(exp(xi)' e) and q0 exp(xi + d) = q exp(Jr(xi) d).
  static Mat3<S> exp_rotation(const S* xi) {
    const Eigen::Matrix<S, 4, 1> e = quaternion_exp(Vec3<S>(xi[0], xi[1], xi[2]));
    return quaternion_rotation(e.data());
  }
  static void base_transport(const S*, const S*, const S* xi, MatX<S>& T, int o) {
    T.template block<3, 3>(o, o) = exp_rotation(xi).transpose();
  }
  static void chart_transport(const S*, const S*, const S* xi, MatX<S>& T, int o) {
    T.template block<3, 3>(o, o) = so3_right_jacobian(Vec3<S>(xi[0], xi[1], xi[2]));
  }
  static void rate_jacobians(const S*, const S*, const S* xi, const S* w, MatX<S>&, MatX<S>& d_xi, MatX<S>& d_v,
                             int o) {
    const Vec3<S> x(xi[0], xi[1], xi[2]);
    d_v.template block<3, 3>(o, o) = so3_right_jacobian_inverse(x);
    d_xi.template block<3, 3>(o, o) = so3_right_jacobian_inverse_derivative(x, Vec3<S>(w[0], w[1], w[2]));
  }
  static void bracket(const S* w, MatX<S>& ad, int o) {
    ad.template block<3, 3>(o, o) = skew(Vec3<S>(w[0], w[1], w[2]));
  }
};

template <class S>
struct SphericalJoint {
  static constexpr const char* name = "spherical";
  static constexpr const char* description = "Ball joint: q = quaternion (x, y, z, w), v = body-frame angular velocity.";
  using Parameters = std::tuple<>;
  static constexpr std::array<const char*, 0> parameter_names{};
  using Space = UnitQuaternionSpace<S>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = false;
  static constexpr std::array<const char*, 4> coordinate_suffixes{"qx", "qy", "qz", "qw"};
  static constexpr std::array<const char*, 3> velocity_suffixes{"wx", "wy", "wz"};

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = quaternion_rotation(q);
    pose.translation.setZero();
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.setZero();
    s.template topRows<3>().setIdentity();
  }
  void random(CoordinateSampler& draw, S* q) const {
    draw.skip(4);
    draw.unit_quaternion(q);
  }
  void check(const std::string&) {}

  JointFastPath fast_path(S& sign) const {
    sign = S(1);
    return JointFastPath::spherical;
  }
  // Tree-frame fast path (sweeps/tree_frame_updates.hpp): R = R_base R(q), and
  // the body-frame subspace [1; 0] carried to the tree frame is
  // H* = [R; t x R] (the body origin t does not move). Zero bias.
  static SOADYN_ALWAYS_INLINE void tree_update(const Transform<S>& base, const S* q, bool root, Transform<S>& pose,
                                             Mat6N<S>& s) {
    pose.rotation.noalias() = base.rotation * quaternion_rotation(q);
    pose.translation = root ? Vec3<S>::Zero() : base.translation;
    for (int c = 0; c < 3; ++c) s.col(c) << pose.rotation.col(c), pose.translation.cross(Vec3<S>(pose.rotation.col(c)));
  }
};

}  // namespace soadyn
