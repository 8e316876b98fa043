// Planar joint: motion in the joint frame's x-y plane, q = (x, y, theta about
// z), v = (vx, vy, wz) in the body frame.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

// SE(2) with coordinates (x, y, theta) and body-frame velocities. The chart
// around q0 is q = q0 + xi with dxi/dt = (R(theta) (vx, vy), wz).
template <class S>
struct PlanarSpace {
  static constexpr int nq = 3, nv = 3;
  static constexpr int quaternion_offset = -1;
  static constexpr bool scalar_coordinates = false;

  static void neutral(S* q) { q[0] = q[1] = q[2] = S(0); }
  // The body-frame twist v dt applied on SE(2) (exact exponential).
  static void integrate(const S* q, const S* v, const S& dt, S* out) {
    using std::cos;
    using std::sin;
    const Eigen::Matrix<S, 2, 1> d = se2_exp_translation<S>(S(v[0] * dt), S(v[1] * dt), S(v[2] * dt));
    const S c = cos(q[2]), s = sin(q[2]);
    out[0] = q[0] + c * d[0] - s * d[1];
    out[1] = q[1] + s * d[0] + c * d[1];
    out[2] = q[2] + v[2] * dt;
  }
  static void retract(const S* q0, const S* xi, S* q) {
    for (int k = 0; k < 3; ++k) q[k] = q0[k] + xi[k];
  }
  static void chart_rate(const S* q, const S*, const S* v, S* rate) {
    using std::cos;
    using std::sin;
    const S c = cos(q[2]), s = sin(q[2]);
    rate[0] = c * v[0] - s * v[1];
    rate[1] = s * v[0] + c * v[1];
    rate[2] = v[2];
  }
  // The chart's first-order maps (joints/vector_space.hpp): q = q0 + xi; the
  // body-frame tangent of (x, y) at q is R(theta)' d(x, y), and the rate of
  // (x, y) is R(theta) (vx, vy).
  static Eigen::Matrix<S, 2, 2> rotation(const S& theta) {
    using std::cos;
    using std::sin;
    Eigen::Matrix<S, 2, 2> r;
    r << cos(theta), -sin(theta), sin(theta), cos(theta);
    return r;
  }
  static void base_transport(const S* q0, const S* q, const S*, MatX<S>& T, int o) {
    T.template block<2, 2>(o, o) = rotation(q[2]).transpose() * rotation(q0[2]);
  }
  static void chart_transport(const S*, const S* q, const S*, MatX<S>& T, int o) {
    T.template block<2, 2>(o, o) = rotation(q[2]).transpose();
  }
  static void rate_jacobians(const S*, const S* q, const S*, const S* v, MatX<S>& d_base, MatX<S>& d_xi, MatX<S>& d_v,
                             int o) {
    const Eigen::Matrix<S, 2, 2> r = rotation(q[2]);
    d_v.template block<2, 2>(o, o) = r;
    const Eigen::Matrix<S, 2, 1> turned = rotation(q[2] + S(EIGEN_PI) / S(2)) * Eigen::Matrix<S, 2, 1>(v[0], v[1]);
    d_xi.template block<2, 1>(o, o + 2) = turned;
    d_base.template block<2, 1>(o, o + 2) = turned;
  }
  static void bracket(const S* v, MatX<S>& ad, int o) {  // se(2), v = (vx, vy, w)
    ad(o, o + 1) = -v[2];
    ad(o, o + 2) = v[1];
    ad(o + 1, o) = v[2];
    ad(o + 1, o + 2) = -v[0];
  }
};

template <class S>
struct PlanarJoint {
  static constexpr const char* name = "planar";
  static constexpr const char* description =
      "x-y translation and z rotation: q = (x, y, theta), v = body-frame (vx, vy, wz).";
  using Parameters = std::tuple<>;
  static constexpr std::array<const char*, 0> parameter_names{};
  using Space = PlanarSpace<S>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 3> coordinate_suffixes{"x", "y", "theta"},
      velocity_suffixes{"vx", "vy", "wz"};

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
  void random(CoordinateSampler& draw, S* q) const {
    draw.skip(2);
    q[2] = S(draw.angle());
    q[0] = S(draw.offset());
    q[1] = S(draw.offset());
  }
  void check(const std::string&) {}
};

}  // namespace soadyn
