// Rigid transforms and their Pluecker actions on motion and force vectors.
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// Pose of a frame B in a frame A: `rotation` maps B coordinates to A
// coordinates and `translation` is B's origin in A. As a Pluecker transform
// it carries motion and force vectors from B coordinates to A coordinates.
template <class S>
struct Transform {
  Mat3<S> rotation = Mat3<S>::Identity();
  Vec3<S> translation = Vec3<S>::Zero();

  static Transform Identity() { return Transform(); }

  Transform operator*(const Transform& b) const {
    Transform r;
    r.rotation = rotation * b.rotation;
    r.translation = translation + rotation * b.translation;
    return r;
  }
  Transform inverse() const {
    Transform r;
    r.rotation = rotation.transpose();
    r.translation = -(r.rotation * translation);
    return r;
  }
  Vec3<S> apply_point(const Vec3<S>& x) const { return rotation * x + translation; }

  // Motion vector from B coordinates to A coordinates.
  Vec6<S> motion_to_parent(const Vec6<S>& m) const {
    Vec6<S> r;
    r.template head<3>() = rotation * m.template head<3>();
    r.template tail<3>() = rotation * m.template tail<3>() + translation.cross(r.template head<3>());
    return r;
  }
  // Motion vector from A coordinates to B coordinates.
  Vec6<S> motion_to_child(const Vec6<S>& m) const {
    Vec6<S> r;
    r.template head<3>() = rotation.transpose() * m.template head<3>();
    r.template tail<3>() = rotation.transpose() * (m.template tail<3>() - translation.cross(m.template head<3>()));
    return r;
  }
  // Force vector from B coordinates to A coordinates (the dual of motion_to_child).
  Vec6<S> force_to_parent(const Vec6<S>& f) const {
    Vec6<S> r;
    r.template tail<3>() = rotation * f.template tail<3>();
    r.template head<3>() = rotation * f.template head<3>() + translation.cross(r.template tail<3>());
    return r;
  }
  // Force vector from A coordinates to B coordinates.
  Vec6<S> force_to_child(const Vec6<S>& f) const {
    Vec6<S> r;
    r.template tail<3>() = rotation.transpose() * f.template tail<3>();
    r.template head<3>() = rotation.transpose() * (f.template head<3>() - translation.cross(f.template tail<3>()));
    return r;
  }
  // Columns of a 6xN force matrix from B to A coordinates.
  template <class Derived>
  void forces_to_parent_inplace(Eigen::MatrixBase<Derived>& F) const {
    for (Eigen::Index c = 0; c < F.cols(); ++c) {
      const Vec6<S> f = F.col(c);
      F.col(c) = force_to_parent(f);
    }
  }

  // Congruence X* I X that carries a symmetric 6x6 inertia (rigid or
  // articulated) from B coordinates to A coordinates, done blockwise:
  // rotate each 3x3 block, then shift the reference point by `translation`.
  Mat6<S> inertia_to_parent(const Mat6<S>& I) const {
    Mat6<S> r;
    inertia_to_parent_into(I, r);
    return r;
  }
  // The same written into r (no 6x6 temporary to copy; r must not alias I).
  void inertia_to_parent_into(const Mat6<S>& I, Mat6<S>& r) const {
    const Mat3<S>& R = rotation;
    const Mat3<S> A = R * I.template topLeftCorner<3, 3>() * R.transpose();
    const Mat3<S> B = R * I.template topRightCorner<3, 3>() * R.transpose();
    const Mat3<S> C = R * I.template bottomRightCorner<3, 3>() * R.transpose();
    // With p = translation: [p]x M is a column-wise cross product, and
    // M [p]x = -([p]x M')' , so the shift needs X = [p]x B' and Y = [p]x C
    // only: top-left A + X + X' - [p]x C [p]x = A + X + X' + ([p]x Y')'.
    const Vec3<S>& p = translation;
    Mat3<S> X, Y, Z;
    for (int c = 0; c < 3; ++c) {
      X.col(c) = p.cross(Vec3<S>(B.row(c).transpose()));
      Y.col(c) = p.cross(Vec3<S>(C.col(c)));
    }
    for (int c = 0; c < 3; ++c) Z.col(c) = p.cross(Vec3<S>(Y.row(c).transpose()));  // Z = [p]x Y'
    r.template topLeftCorner<3, 3>() = A + X + X.transpose() + Z.transpose();
    r.template topRightCorner<3, 3>() = B + Y;
    r.template bottomLeftCorner<3, 3>() = (B + Y).transpose();
    r.template bottomRightCorner<3, 3>() = C;
  }

  template <class T>
  Transform<T> cast() const {
    Transform<T> r;
    r.rotation = rotation.template cast<T>();
    r.translation = translation.template cast<T>();
    return r;
  }
};

// Rotation by `angle` about the unit vector `axis` (Rodrigues' formula).
template <class S>
Mat3<S> axis_angle_rotation(const Vec3<S>& axis, const S& angle) {
  using std::cos;
  using std::sin;
  const Mat3<S> k = skew(axis);
  return Mat3<S>::Identity() + sin(angle) * k + (S(1) - cos(angle)) * (k * k);
}

// Rotation of the quaternion stored (x, y, z, w). Scaling by 2/|q|^2 makes it
// the rotation of q/|q|, so a quaternion within the accepted tolerance of
// unit norm gives an exactly orthonormal matrix.
template <class S>
Mat3<S> quaternion_rotation(const S* q) {
  const S x = q[0], y = q[1], z = q[2], w = q[3];
  const S s = S(2) / (x * x + y * y + z * z + w * w);
  Mat3<S> R;
  R << S(1) - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w),
      s * (x * y + z * w), S(1) - s * (x * x + z * z), s * (y * z - x * w),
      s * (x * z - y * w), s * (y * z + x * w), S(1) - s * (x * x + y * y);
  return R;
}

}  // namespace soadyn
