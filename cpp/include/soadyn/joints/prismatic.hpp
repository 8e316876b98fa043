// Prismatic joint: translation q along a unit axis of the joint frame.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

template <class S>
struct PrismaticJoint {
  static constexpr const char* name = "prismatic";
  static constexpr const char* description = "Translation along `axis`. One DOF.";
  using Parameters = std::tuple<Vec3<S>>;
  static constexpr std::array<const char*, 1> parameter_names{"axis"};
  using Space = VectorSpace<S, 1>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 1> coordinate_suffixes{""}, velocity_suffixes{""};

  Vec3<S> axis;

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation.setIdentity();
    pose.translation = axis * q[0];
  }
  void fill_subspace(Mat6N<S>& s) const { s.col(0) << Vec3<S>::Zero(), axis; }
  void random(CoordinateSampler& draw, S* q) const { q[0] = S(draw.offset()); }
  void check(const std::string& joint_name) { axis = checked_joint_axis(axis, joint_name, "axis"); }

  // Axis along +-e_k: the fast paths below, with `sign` the axis' sign; any
  // other axis: tree_update.
  JointFastPath fast_path(S& sign) const {
    const int k = coordinate_axis(axis, sign);
    return k >= 0 ? fast_path_along(JointFastPath::prismatic_x, k) : JointFastPath::prismatic_axis;
  }
  // Tree frame, any axis: base moved along w = R_base axis (a root body's
  // origin kept at the tree origin), H* = [0; w].
  SOADYN_ALWAYS_INLINE void tree_update(const Transform<S>& base, const S& offset, bool root, Transform<S>& pose,
                                      Mat6N<S>& s) const {
    const Vec3<S> w = base.rotation * axis;
    pose.rotation = base.rotation;
    pose.translation = root ? Vec3<S>::Zero() : Vec3<S>(base.translation + w * offset);
    s.col(0) << Vec3<S>::Zero(), w;
  }
  // Fast paths of an axis along sign * e_k; `offset` = sign * q. Body frame:
  // the placement moved along its k-th column; subspace and zero bias stay
  // as Data was built.
  static SOADYN_ALWAYS_INLINE void aligned_pose(int k, const Transform<S>& placement, const S& offset,
                                                Transform<S>& pose) {
    pose.rotation = placement.rotation;
    pose.translation = placement.translation + placement.rotation.col(k) * offset;
  }
  // Tree frame (sweeps/tree_frame_updates.hpp): the same motion from
  // `base`, a root body's origin kept at the tree origin, and H* = [0; w]
  // for the axis w = sign R e_k.
  static SOADYN_ALWAYS_INLINE void aligned_tree_update(int k, const Transform<S>& base, const S& offset, const S& sign,
                                                     bool root, Transform<S>& pose, Mat6N<S>& s) {
    pose.rotation = base.rotation;
    pose.translation = root ? Vec3<S>::Zero() : Vec3<S>(base.translation + base.rotation.col(k) * offset);
    s.col(0) << Vec3<S>::Zero(), pose.rotation.col(k) * sign;
  }
};

}  // namespace soadyn
