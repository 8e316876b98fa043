// Per-body steps of the rigid-model sweeps in tree frames.
//
// The recursions of Jain & Rodriguez 1993 (Eqs. 1, 14, 28, 29) hold in any frame. For rigid
// models, forward and hybrid dynamics express every spatial quantity of a
// body in its *tree frame*: the world's orientation, origin at the tree's
// root body origin. In one common frame the inter-body operator phi(k+1, k)
// is the identity, so
//   - the inward sweep adds P+ and z+ to the parent without the 6x6
//     congruence phi P+ phi* (Eq. 14), the most expensive step of the
//     body-frame recursion (~220 multiplications per body);
//   - the outward sweeps add the parent's velocity and acceleration without a
//     transform (Eqs. 1, 29).
// The price is one inertia per body carried to the tree frame from its ten
// parameters (spatial_inertia_in_frame, ~80 multiplications) and the hinge
// subspace H* in that frame (a column of the body rotation for axis-aligned
// joints, joints/joint_kernel.hpp). Featherstone (Rigid Body Dynamics
// Algorithms, 2008, Sec. 7.3) notes the same trade for the ABA in world
// coordinates. The origin at the root body rather than the world's keeps lever
// arms as short as in body frames: a spacecraft far from the world origin
// loses no precision, and every tree is independent of where it is.
//
// Velocity products: with H* constant in the body frame, its rate in the tree
// frame is V x H*, so the Coriolis term of Eq. 1 is a(k) = V(k) x (H* qdot),
// plus the joint's own bias for joints whose subspace varies (universal).
#pragma once
#include "soadyn/algorithms/appendage_step.hpp"
#include "soadyn/joints/joint_kernel.hpp"

namespace soadyn {

namespace detail {

// Motion subspace of a unit-axis hinge: [w; t x w] for a rotation axis w
// through the body origin t, [0; w] for a translation along w.
template <class S>
inline void rotation_subspace(const Transform<S>& pose, const Vec3<S>& w, Mat6N<S>& s) {
  s.col(0) << w, pose.translation.cross(w);
}
template <class S>
inline void translation_subspace(const Vec3<S>& w, Mat6N<S>& s) {
  s.col(0) << Vec3<S>::Zero(), w;
}

// Free joint: H* = X(pose) (body twists to tree-frame twists).
template <class S>
inline void free_subspace(const Transform<S>& pose, Mat6N<S>& s) {
  for (int c = 0; c < 3; ++c) {
    s.col(c) << pose.rotation.col(c), pose.translation.cross(Vec3<S>(pose.rotation.col(c)));
    s.col(c + 3) << Vec3<S>::Zero(), pose.rotation.col(c);
  }
}

// Any joint: its body-frame pose, subspace and bias from JointModel, carried
// to the tree frame. Returns the bias (dS/dt v) in the tree frame.
template <class S>
inline Vec6<S> general_joint_tree_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Transform<S>& base,
                                       const S* q, const S* v, bool root) {
  Transform<S> joint_pose;
  joint_calc(m.joints[i], q + m.q_index[i], v ? v + m.v_index[i] : nullptr, joint_pose, d.sweep.body_subspace[i],
             d.sweep.body_joint_bias[i]);
  Transform<S>& pose = d.sweep.tree_pose[i];
  pose = base * joint_pose;
  if (root) pose.translation.setZero();
  Mat6N<S>& s = d.sweep.tree_subspace[i];
  for (Eigen::Index c = 0; c < s.cols(); ++c) s.col(c) = pose.motion_to_parent(Vec6<S>(d.sweep.body_subspace[i].col(c)));
  return pose.motion_to_parent(d.sweep.body_joint_bias[i]);
}

// Universal joint (joints/joint.hpp): rotation R1 about a1, then R2 about a2.
// In the tree frame its axes are w1 = R_base a1 and w2 = R_base R1 a2 = R a2,
// both through the body origin t, so H* = [w1 w2; t x w1  t x w2]. The body-
// frame velocity product (qd1 qd2) (R2' a1) x a2 is, carried by R,
// (qd1 qd2) w1 x w2 (R2 a2 = a2, R1 a1 = a1): the bias [c; t x c].
template <class S>
inline Vec6<S> universal_tree_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Transform<S>& base,
                                   const S* q, const S* v, bool root) {
  const UniversalJoint<S>& joint = *std::get_if<UniversalJoint<S>>(&m.joints[i]);
  const S* qi = q + m.q_index[i];
  Transform<S>& pose = d.sweep.tree_pose[i];
  S sign1, sign2;
  const int k1 = coordinate_axis(joint.axis1, sign1), k2 = coordinate_axis(joint.axis2, sign2);
  if (k1 >= 0 && k2 >= 0) {  // both axes along coordinate axes: two column rotations
    Transform<S> first;
    rotate_about_coordinate_axis(k1, base, sign1 * qi[0], first);
    rotate_about_coordinate_axis(k2, first, sign2 * qi[1], pose);
  } else {
    pose.rotation.noalias() =
        base.rotation * (axis_angle_rotation(joint.axis1, qi[0]) * axis_angle_rotation(joint.axis2, qi[1]));
  }
  pose.translation = root ? Vec3<S>::Zero() : base.translation;
  const Vec3<S> w1 = base.rotation * joint.axis1, w2 = pose.rotation * joint.axis2;
  Mat6N<S>& s = d.sweep.tree_subspace[i];
  s.col(0) << w1, pose.translation.cross(w1);
  s.col(1) << w2, pose.translation.cross(w2);
  if (!v) return Vec6<S>::Zero();
  const S* vi = v + m.v_index[i];
  const Vec3<S> c = (vi[0] * vi[1]) * w1.cross(w2);
  Vec6<S> bias;
  bias << c, pose.translation.cross(c);
  return bias;
}

}  // namespace detail

// Pose of body i in its tree frame and its motion subspace there; returns the
// joint's velocity-product acceleration in the tree frame (zero for every
// joint but the universal one). A root body's tree pose has no translation.
template <class S>
inline Vec6<S> tree_joint_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  const int p = m.parent[i];
  const bool root = p < 0;
  Transform<S> base;
  if (root)
    base.rotation = m.placement[i].rotation;
  else
    base = d.sweep.tree_pose[static_cast<std::size_t>(p)] * m.placement[i];
  Transform<S>& pose = d.sweep.tree_pose[i];
  Mat6N<S>& s = d.sweep.tree_subspace[i];
  // The 1-DOF kernels' coordinate along +e_k.
  const auto x = [&] { return q[m.q_index[i]] * m.axis_sign[i]; };
  switch (m.joint_kernel[i]) {
    case JointKernel::revolute_x: rotate_about_coordinate_axis<0>(base, x(), pose); break;
    case JointKernel::revolute_y: rotate_about_coordinate_axis<1>(base, x(), pose); break;
    case JointKernel::revolute_z: rotate_about_coordinate_axis<2>(base, x(), pose); break;
    case JointKernel::prismatic_x:
    case JointKernel::prismatic_y:
    case JointKernel::prismatic_z: {
      const int k = static_cast<int>(m.joint_kernel[i]) - static_cast<int>(JointKernel::prismatic_x);
      pose.rotation = base.rotation;
      pose.translation = root ? Vec3<S>::Zero() : Vec3<S>(base.translation + base.rotation.col(k) * x());
      detail::translation_subspace(Vec3<S>(pose.rotation.col(k) * m.axis_sign[i]), s);
      return Vec6<S>::Zero();
    }
    case JointKernel::free: {
      const S* qi = q + m.q_index[i];
      Transform<S> joint_pose;
      joint_pose.rotation = quaternion_rotation(qi + 3);
      joint_pose.translation << qi[0], qi[1], qi[2];
      pose = base * joint_pose;
      if (root) pose.translation.setZero();
      detail::free_subspace(pose, s);
      return Vec6<S>::Zero();
    }
    case JointKernel::fixed:
      pose = base;
      return Vec6<S>::Zero();
    case JointKernel::universal: return detail::universal_tree_step(m, d, i, base, q, v, root);
    default: return detail::general_joint_tree_step(m, d, i, base, q, v, root);
  }
  // the revolute kernels
  const int k = static_cast<int>(m.joint_kernel[i]) - static_cast<int>(JointKernel::revolute_x);
  detail::rotation_subspace(pose, Vec3<S>(pose.rotation.col(k) * m.axis_sign[i]), s);
  return Vec6<S>::Zero();
}

// Tree-frame kinematics of body i (Jain & Rodriguez 1993, Eq. 1): pose and subspace,
// V(i) = V(parent) + H* qdot and a(i) = V(i) x (H* qdot) + joint bias.
// `v` null: zero velocity (impulse problems).
template <class S>
SOADYN_ALWAYS_INLINE void tree_velocity_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  const Vec6<S> joint_rate = tree_joint_step(m, d, i, q, v);
  if (!v) {
    d.sweep.tree_velocity[i].setZero();
    d.sweep.tree_coriolis[i].setZero();
    return;
  }
  const int p = m.parent[i];
  const Vec6<S> joint_velocity = subspace_times(d.sweep.tree_subspace[i], v + m.v_index[i]);
  d.sweep.tree_velocity[i] =
      p >= 0 ? Vec6<S>(d.sweep.tree_velocity[static_cast<std::size_t>(p)] + joint_velocity) : joint_velocity;
  d.sweep.tree_coriolis[i] = motion_cross(d.sweep.tree_velocity[i], joint_velocity) + joint_rate;
}

// Whether body i sits beyond the distance from its tree origin at which tree
// frames keep their precision (tree_frame_reach.hxx); checked only for
// bodies whose geometry does not bound that distance below the reach.
template <class S>
SOADYN_ALWAYS_INLINE bool beyond_tree_frame_reach(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i) {
  return m.reach_checks_needed && m.check_tree_frame_reach[i] &&
         d.sweep.tree_pose[i].translation.squaredNorm() > m.tree_frame_reach_squared[i];
}

// Body terms of rigid body i in its tree frame: M(i) into
// tree_articulated_inertia[i] (the start of P) and b(i) = V x* (M V) - f_ext
// into tree_bias_force[i] and tree_bias_and_children_z[i]; `f_ext` as in steps.hpp.
template <class S>
SOADYN_ALWAYS_INLINE void tree_rigid_body_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* v, const S* f_ext) {
  const Transform<S>& pose = d.sweep.tree_pose[i];
  Mat6<S>& inertia = d.sweep.tree_articulated_inertia[i];
  spatial_inertia_in_frame(pose, m.mass[i], m.com[i], m.inertia_com[i], inertia);
  Vec6<S>& b = d.sweep.tree_bias_force[i];
  if (v)
    b = force_cross(d.sweep.tree_velocity[i], Vec6<S>(inertia * d.sweep.tree_velocity[i]));
  else
    b.setZero();
  if (f_ext) b -= pose.force_to_parent(Eigen::Map<const Vec6<S>>(f_ext + 6 * i));
  d.sweep.tree_bias_and_children_z[i] = b;
}

// Body terms of flexible appendage i (appendage_step.hpp) in its tree frame:
// its modal DOFs are eliminated in the body frame, and P^ and z^ are carried
// to the tree frame by one congruence. Children add their P+ and z+ to them;
// once alpha(i) is known, eta_ddot = nu - G' alpha (modal_accelerations,
// flexible_steps.hpp, with alpha carried to the body frame).
template <class S>
inline void tree_flexible_body_step(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                                    const S* u, const S* f_ext) {
  const Transform<S>& pose = d.sweep.tree_pose[i];
  Mat6<S> P;
  Vec6<S> z;
  appendage_step(m, d, i, q, v, u, f_ext, Vec6<S>(pose.motion_to_child(d.sweep.tree_velocity[i])), P, z);
  d.sweep.tree_articulated_inertia[i] = pose.inertia_to_parent(P);
  d.sweep.tree_bias_and_children_z[i] = pose.force_to_parent(z);
}

}  // namespace soadyn
