// Revolute joint: rotation q about a unit axis of the joint frame.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

// pose = base * Rot(e_Axis, angle): the rotation about a coordinate axis
// mixes two columns of base's rotation (cyclic order Axis, Axis+1, Axis+2):
// 12 multiplications instead of Rodrigues' formula and a 3x3 product.
// `c` and `s` are the angle's cosine and sine.
template <int Axis, class S>
SOADYN_ALWAYS_INLINE void rotate_about_coordinate_axis(const Transform<S>& base, const S& c, const S& s,
                                                       Transform<S>& pose) {
  constexpr int a1 = (Axis + 1) % 3, a2 = (Axis + 2) % 3;
  pose.translation = base.translation;
  pose.rotation.col(Axis) = base.rotation.col(Axis);
  pose.rotation.col(a1) = c * base.rotation.col(a1) + s * base.rotation.col(a2);
  pose.rotation.col(a2) = c * base.rotation.col(a2) - s * base.rotation.col(a1);
}

template <int Axis, class S>
SOADYN_ALWAYS_INLINE void rotate_about_coordinate_axis(const Transform<S>& base, const S& angle, Transform<S>& pose) {
  using std::cos;
  using std::sin;
  rotate_about_coordinate_axis<Axis>(base, S(cos(angle)), S(sin(angle)), pose);
}

// pose = base * Rot(e_axis, angle) for a run-time axis 0, 1 or 2, from the
// angle's cosine `c` and sine `s`.
template <class S>
inline void rotate_about_coordinate_axis(int axis, const Transform<S>& base, const S& c, const S& s,
                                         Transform<S>& pose) {
  switch (axis) {
    case 0: rotate_about_coordinate_axis<0>(base, c, s, pose); return;
    case 1: rotate_about_coordinate_axis<1>(base, c, s, pose); return;
    default: rotate_about_coordinate_axis<2>(base, c, s, pose); return;
  }
}

// The same from the angle itself.
template <class S>
inline void rotate_about_coordinate_axis(int axis, const Transform<S>& base, const S& angle, Transform<S>& pose) {
  using std::cos;
  using std::sin;
  rotate_about_coordinate_axis(axis, base, S(cos(angle)), S(sin(angle)), pose);
}

template <class S>
struct RevoluteJoint {
  static constexpr const char* name = "revolute";
  static constexpr const char* description = "Rotation about `axis` (joint frame). One DOF.";
  using Parameters = std::tuple<Vec3<S>>;
  static constexpr std::array<const char*, 1> parameter_names{"axis"};
  using Space = VectorSpace<S, 1>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = false;
  static constexpr std::array<const char*, 1> coordinate_suffixes{""}, velocity_suffixes{""};

  Vec3<S> axis;

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation = axis_angle_rotation(axis, q[0]);
    pose.translation.setZero();
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << axis, Vec3<S>::Zero(); }
  void random(CoordinateSampler& draw, S* q) const { q[0] = S(draw.angle()); }
  void check(const std::string& joint_name) { axis = checked_joint_axis(axis, joint_name, "axis"); }

  // Axis along +-e_k: the fast paths below, with `sign` the axis' sign; any
  // other axis: tree_update.
  JointFastPath fast_path(S& sign) const {
    const int k = coordinate_axis(axis, sign);
    return k >= 0 ? fast_path_along(JointFastPath::revolute_x, k) : JointFastPath::revolute_axis;
  }
  // Tree frame, any axis: pose = base * Rot(axis, angle) (Rodrigues), and
  // H* = [w; t x w] for w = R_base axis (the rotation leaves its axis fixed)
  // through the body origin t.
  SOADYN_ALWAYS_INLINE void tree_update(const Transform<S>& base, const S& angle, Transform<S>& pose,
                                      Mat6N<S>& s) const {
    pose.rotation.noalias() = base.rotation * axis_angle_rotation(axis, angle);
    pose.translation = base.translation;
    const Vec3<S> w = base.rotation * axis;
    store_as_pairs(w, Vec3<S>(pose.translation.cross(w)), s.col(0));
  }
  // Fast paths of an axis along sign * e_Axis; `angle` = sign * q. Body frame:
  // pose = placement * Rot; the subspace and zero bias stay as Data was built.
  template <int Axis>
  static SOADYN_ALWAYS_INLINE void aligned_pose(const Transform<S>& placement, const S& angle, Transform<S>& pose) {
    rotate_about_coordinate_axis<Axis>(placement, angle, pose);
  }
  // Tree frame (sweeps/tree_frame_updates.hpp): pose = base * Rot, and
  // H* = [w; t x w] for the axis w = sign R e_Axis through the body origin t;
  // the angle's cosine and sine come from the sweep's table (joint_angles.hpp).
  template <int Axis>
  static SOADYN_ALWAYS_INLINE void aligned_tree_update(const Transform<S>& base, const S& cosine, const S& sine,
                                                     const S& sign, Transform<S>& pose, Mat6N<S>& s) {
    rotate_about_coordinate_axis<Axis>(base, cosine, sine, pose);
    const Vec3<S> w = pose.rotation.col(Axis) * sign;
    store_as_pairs(w, Vec3<S>(pose.translation.cross(w)), s.col(0));
  }
};

}  // namespace soadyn
