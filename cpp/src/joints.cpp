// Joint integration on manifolds, joint naming; explicit instantiations.
#include "soadyn/joints/joint.hpp"

namespace soadyn {

namespace {
template <class S>
void integrate_planar(const S* q, const S* v, const S& dt, S* out) {
  using std::cos;
  using std::sin;
  const Eigen::Matrix<S, 2, 1> d = se2_exp_translation(v[0] * dt, v[1] * dt, v[2] * dt);
  const S c = cos(q[2]), s = sin(q[2]);
  out[0] = q[0] + c * d[0] - s * d[1];
  out[1] = q[1] + s * d[0] + c * d[1];
  out[2] = q[2] + v[2] * dt;
}

template <class S>
void integrate_quaternion(const S* quat, const Vec3<S>& phi, S* out) {
  const Eigen::Matrix<S, 4, 1> e = quaternion_exp(phi);
  const Eigen::Matrix<S, 4, 1> r = quaternion_multiply(quat, e.data());
  for (int i = 0; i < 4; ++i) out[i] = r[i];
}

// Body-frame twist (w, u) * dt applied on SE(3): p += R V(phi) u dt.
template <class S>
void integrate_free(const S* q, const S* v, const S& dt, S* out) {
  const Vec3<S> phi = Vec3<S>(v[0], v[1], v[2]) * dt;
  const Vec3<S> u = Vec3<S>(v[3], v[4], v[5]) * dt;
  const Vec3<S> dp = quaternion_rotation(q + 3) * (so3_left_jacobian(phi) * u);
  for (int i = 0; i < 3; ++i) out[i] = q[i] + dp[i];
  integrate_quaternion(q + 3, phi, out + 3);
}
}  // namespace

template <class S>
void joint_integrate(const JointModel<S>& j, const S* q, const S* v, const S& dt, S* q_out) {
  std::visit(
      [&](const auto& jj) {
        using J = std::decay_t<decltype(jj)>;
        if constexpr (std::is_same_v<J, PlanarJoint<S>>) {
          integrate_planar(q, v, dt, q_out);
        } else if constexpr (std::is_same_v<J, SphericalJoint<S>>) {
          integrate_quaternion(q, Vec3<S>(Vec3<S>(v[0], v[1], v[2]) * dt), q_out);
        } else if constexpr (std::is_same_v<J, FreeJoint<S>>) {
          integrate_free(q, v, dt, q_out);
        } else {
          for (int i = 0; i < J::nq; ++i) q_out[i] = q[i] + v[i] * dt;
        }
      },
      j);
}

namespace {
const char* const kNone[] = {""};
const char* const kUniversal[] = {"1", "2"};
const char* const kCylindricalQ[] = {"angle", "offset"};
const char* const kPlanarQ[] = {"x", "y", "theta"};
const char* const kPlanarV[] = {"vx", "vy", "wz"};
const char* const kQuatQ[] = {"qx", "qy", "qz", "qw"};
const char* const kAngularV[] = {"wx", "wy", "wz"};
const char* const kFreeQ[] = {"px", "py", "pz", "qx", "qy", "qz", "qw"};
const char* const kFreeV[] = {"wx", "wy", "wz", "vx", "vy", "vz"};
}  // namespace

template <class S>
const char* const* joint_coordinate_suffixes(const JointModel<S>& j) {
  switch (j.index()) {
    case 3: return kUniversal;
    case 4: return kCylindricalQ;
    case 5: return kPlanarQ;
    case 6: return kQuatQ;
    case 7: return kFreeQ;
    default: return kNone;
  }
}

template <class S>
const char* const* joint_velocity_suffixes(const JointModel<S>& j) {
  switch (j.index()) {
    case 3: return kUniversal;
    case 4: return kCylindricalQ;
    case 5: return kPlanarV;
    case 6: return kAngularV;
    case 7: return kFreeV;
    default: return kNone;
  }
}

template <class S>
const char* joint_type_name(const JointModel<S>& j) {
  static const char* const names[] = {"revolute",  "prismatic", "helical", "universal", "cylindrical",
                                      "planar",    "spherical", "free",    "fixed"};
  return names[j.index()];
}

#define SOADYN_INSTANTIATE_JOINTS(S)                                                              \
  template void joint_integrate<S>(const JointModel<S>&, const S*, const S*, const S&, S*);      \
  template const char* const* joint_coordinate_suffixes<S>(const JointModel<S>&);                \
  template const char* const* joint_velocity_suffixes<S>(const JointModel<S>&);                  \
  template const char* joint_type_name<S>(const JointModel<S>&);
SOADYN_INSTANTIATE_JOINTS(double)
SOADYN_INSTANTIATE_JOINTS(float)

}  // namespace soadyn
