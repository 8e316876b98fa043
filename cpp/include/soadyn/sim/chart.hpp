// Local coordinates for integrating q on the joint manifolds (Runge-Kutta-
// Munthe-Kaas). Around a base configuration q0 every joint has a chart of
// dimension nv: q = retract(q0, xi). Classical Runge-Kutta on xi and v is
// then of full order and keeps every quaternion exactly on the unit sphere
// (it only ever multiplies by exact exponentials).
//   scalar joints: q = q0 + xi, dxi/dt = v
//   planar (x, y, theta): q = q0 + xi, dxi/dt = (R(theta) (vx, vy), wz)
//   spherical: quat = quat0 * exp(xi), dxi/dt = Jr^-1(xi) w
//   free: p = p0 + xi_p, quat = quat0 * exp(xi_r),
//         dxi_r/dt = Jr^-1(xi_r) w, dxi_p/dt = R(quat) v
// with Jr^-1 the inverse right Jacobian of SO(3) (spatial/lie.hpp).
#pragma once
#include "soadyn/joints/joint.hpp"

namespace soadyn {

template <class S>
void chart_retract(const JointModel<S>& j, const S* q0, const S* xi, S* q) {
  std::visit(
      [&](const auto& jj) {
        using J = std::decay_t<decltype(jj)>;
        if constexpr (std::is_same_v<J, SphericalJoint<S>>) {
          const Eigen::Matrix<S, 4, 1> e = quaternion_exp(Vec3<S>(xi[0], xi[1], xi[2]));
          Eigen::Map<Eigen::Matrix<S, 4, 1>>{q} = quaternion_multiply(q0, e.data());
        } else if constexpr (std::is_same_v<J, FreeJoint<S>>) {
          for (int k = 0; k < 3; ++k) q[k] = q0[k] + xi[3 + k];
          const Eigen::Matrix<S, 4, 1> e = quaternion_exp(Vec3<S>(xi[0], xi[1], xi[2]));
          Eigen::Map<Eigen::Matrix<S, 4, 1>>{q + 3} = quaternion_multiply(q0 + 3, e.data());
        } else {
          for (int k = 0; k < J::nq; ++k) q[k] = q0[k] + xi[k];
        }
      },
      j);
}

// dxi/dt at the configuration q = retract(q0, xi) for velocity v.
template <class S>
void chart_rate(const JointModel<S>& j, const S* q, const S* xi, const S* v, S* rate) {
  std::visit(
      [&](const auto& jj) {
        using J = std::decay_t<decltype(jj)>;
        if constexpr (std::is_same_v<J, SphericalJoint<S>>) {
          Eigen::Map<Vec3<S>>{rate} = so3_right_jacobian_inverse(Vec3<S>(xi[0], xi[1], xi[2])) * Vec3<S>(v[0], v[1], v[2]);
        } else if constexpr (std::is_same_v<J, FreeJoint<S>>) {
          Eigen::Map<Vec3<S>>{rate} = so3_right_jacobian_inverse(Vec3<S>(xi[0], xi[1], xi[2])) * Vec3<S>(v[0], v[1], v[2]);
          Eigen::Map<Vec3<S>>{rate + 3} = quaternion_rotation(q + 3) * Vec3<S>(v[3], v[4], v[5]);
        } else if constexpr (std::is_same_v<J, PlanarJoint<S>>) {
          using std::cos;
          using std::sin;
          const S c = cos(q[2]), s = sin(q[2]);
          rate[0] = c * v[0] - s * v[1];
          rate[1] = s * v[0] + c * v[1];
          rate[2] = v[2];
        } else {
          for (int k = 0; k < J::nv; ++k) rate[k] = v[k];
        }
      },
      j);
}

// Whether the DOF's coordinate is its velocity's integral (q' = v), so a
// motion source can set the coordinate directly.
template <class S>
bool joint_has_scalar_coordinates(const JointModel<S>& j) {
  return !(std::holds_alternative<PlanarJoint<S>>(j) || std::holds_alternative<SphericalJoint<S>>(j) ||
           std::holds_alternative<FreeJoint<S>>(j));
}

}  // namespace soadyn
