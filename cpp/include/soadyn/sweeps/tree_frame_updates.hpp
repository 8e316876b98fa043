// Per-body updates of the rigid-model sweeps in tree frames.
//
// The recursions of Jain & Rodriguez 1993 (Eqs. 1, 14, 28, 29) hold in any frame. For rigid
// models, forward and hybrid dynamics express every spatial quantity of a
// body in its *tree frame*: the world's orientation, origin at the tree's
// root body origin. In one common frame the inter-body operator phi(k+1, k)
// is the identity, so
//   - the inward sweep adds P+ and z+ to the parent without the 6x6
//     congruence phi P+ phi* (Eq. 14), the most expensive update of the
//     body-frame recursion (~220 multiplications per body);
//   - the outward sweeps add the parent's velocity and acceleration without a
//     transform (Eqs. 1, 29).
// The price is one inertia per body carried to the tree frame from its ten
// parameters (spatial_inertia_in_frame, ~80 multiplications) and the hinge
// subspace H* in that frame (a column of the body rotation for axis-aligned
// joints, joints/joint_fast_path.hpp). Featherstone (Rigid Body Dynamics
// Algorithms, 2008, Sec. 7.3) notes the same trade for the ABA in world
// coordinates. The origin at the root body rather than the world's keeps lever
// arms as short as in body frames: a spacecraft far from the world origin
// loses no precision, and every tree is independent of where it is.
//
// Velocity products: with H* constant in the body frame, its rate in the tree
// frame is V x H*, so the Coriolis term of Eq. 1 is a(k) = V(k) x (H* qdot),
// plus the joint's own bias for joints whose subspace varies (universal).
//
// Roots in their own frames (`RootBodyFrames`: the forward and hybrid
// dynamics sweeps; the CRBA likewise, crba.hxx): a tree whose root joint has
// a constant subspace in the root's body frame (free; revolute or prismatic
// about a coordinate axis, as every robot's first joint; fixed) takes the
// root's body frame at this instant as its tree frame instead of the world's
// orientation. The recursions hold in it as in any frame; the root's pose is
// the identity and its H* its constant body-frame subspace (a free root's
// is the identity: its velocity is its body-frame twist, the free joint's
// v), so the root has no joint update, its children's bases are their
// placements, and a body welded to the root, or turning about an axis of
// mass symmetry on a welded body, has a constant inertia there (formed once:
// constant_tree_inertia.hxx). The world's acceleration, -gravity, is carried
// into the root's frame once per call. The loops' and the derivatives'
// sweeps, which read tree-frame quantities as world-oriented, keep the
// world's orientation.
#pragma once
#include <type_traits>

#include "soadyn/sweeps/appendage_update.hpp"
#include "soadyn/sweeps/joint_angles.hpp"
#include "soadyn/joints/fast_path_updates.hpp"

namespace soadyn {

namespace detail {

// Whether scalar S gets the speed paths: the tree-frame sweeps and the
// hybrid dynamics' all-regular and all-prescribed shortcuts. Double, float
// and packets of doubles do (is_real_scalar_v). Any other scalar (the dual numbers of the parameter
// sensitivity) takes the body-frame sweeps under the model's flags, correct
// for every model and equal up to rounding: instantiated for such a scalar,
// the speed paths would only lengthen the build.
template <class S>
inline constexpr bool has_speed_paths = is_real_scalar_v<S>;

// Any joint: its body-frame pose, subspace and bias from JointModel, carried
// to the tree frame. Returns the bias (dS/dt v) in the tree frame.
template <class S>
inline Vec6<S> general_joint_tree_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Transform<S>& base,
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

// Universal joint: its tree-frame fast path (joints/universal.hpp).
template <class S>
inline Vec6<S> universal_tree_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Transform<S>& base,
                                   const S* q, const S* v, bool root) {
  const UniversalJoint<S>& joint = *std::get_if<UniversalJoint<S>>(&m.joints[i]);
  const S* joint_v = v ? v + m.v_index[i] : nullptr;
  const int slot = m.angle_slot[i];
  if (slot >= 0)  // both axes along coordinate axes: the angles' sines and cosines are tabulated
    return joint.aligned_tree_update(base, &d.sweep.tree_joint_cosine[slot], &d.sweep.tree_joint_sine[slot], joint_v,
                                   root, d.sweep.tree_pose[i], d.sweep.tree_subspace[i]);
  return joint.tree_update(base, q + m.q_index[i], joint_v, root, d.sweep.tree_pose[i], d.sweep.tree_subspace[i]);
}

// base = parent * placement, written column by column as the joint fast paths
// read it (whole-matrix copies and products leave stores that the fast paths'
// column loads cannot forward from). The rotation product is skipped when the
// placement's rotation is the identity or a quarter-turn permutation of the
// axes (`axes`: the model's placement_axes, refreshed with every placement
// change; spatial/placement_axes.hpp), as it is for most URDF joints.
template <class S>
SOADYN_ALWAYS_INLINE void compose_with_placement(const Transform<S>& parent, const Transform<S>& placement,
                                                 const PlacementAxes<S>& axes, Transform<S>& base) {
  using Kind = typename PlacementAxes<S>::Kind;
  const Mat3<S>& R = parent.rotation;
  const Mat3<S>& P = placement.rotation;
  const Vec3<S>& t = placement.translation;
  base.translation = parent.translation + R.col(0) * t.x() + R.col(1) * t.y() + R.col(2) * t.z();
  if (axes.kind == Kind::identity) {
    for (int c = 0; c < 3; ++c) base.rotation.col(c) = R.col(c);
  } else if (axes.kind == Kind::signed_permutation) {
    for (std::size_t c = 0; c < 3; ++c) base.rotation.col(static_cast<int>(c)) = R.col(axes.source[c]) * axes.sign[c];
  } else {
    for (int c = 0; c < 3; ++c) base.rotation.col(c) = R.col(0) * P(0, c) + R.col(1) * P(1, c) + R.col(2) * P(2, c);
  }
}

}  // namespace detail

// Whether body i is a root with a free joint.
template <class S>
SOADYN_ALWAYS_INLINE bool is_free_root(const ModelTpl<S>& m, int i) {
  const std::size_t b = static_cast<std::size_t>(i);
  return m.parent[b] < 0 && joint_is_free(m.joint_fast_path[b]);
}

// Whether body i is a root whose tree frame is its own body frame under
// RootBodyFrames (above): its joint's subspace is constant in that frame.
template <class S>
SOADYN_ALWAYS_INLINE bool is_body_frame_root(const ModelTpl<S>& m, int i) {
  const std::size_t b = static_cast<std::size_t>(i);
  return m.parent[b] < 0 && joint_has_constant_body_subspace(m.joint_fast_path[b]);
}

// Whether appendage i's modes are eliminated in its tree frame, with its
// integrals held there (RootBodyFrames: an appendage welded to a
// body-frame root, ModelTpl::appendage_in_root_frame), not in its body frame.
template <bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE bool appendage_eliminated_in_tree_frame(const ModelTpl<S>& m, std::size_t i) {
  return RootBodyFrames && m.derived.appendage_in_root_frame[i];
}

// Pose of body i in its tree frame and its motion subspace there; returns the
// joint's velocity-product acceleration in the tree frame (zero for every
// joint but the universal one). A root body's tree pose has no translation.
// The fast paths' code lives with their joints (joints/revolute.hpp,
// prismatic.hpp, free.hpp, universal.hpp, spherical.hpp). Every sweep calls
// tabulate_joint_angles with the same q before its first body.
// RootBodyFrames: such a root's tree frame is its body frame (above), so its
// children have their placements for bases.
template <bool RootBodyFrames = false, class S>
inline Vec6<S> tree_joint_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  const int p = m.parent[i];
  const bool root = p < 0;
  Transform<S> base;
  if (root)
    base.rotation = m.placement[i].rotation;
  else if (RootBodyFrames && is_body_frame_root(m, p))
    base = m.placement[i];
  else
    detail::compose_with_placement(d.sweep.tree_pose[static_cast<std::size_t>(p)], m.placement[i], m.derived.placement_axes[i],
                                   base);
  Transform<S>& pose = d.sweep.tree_pose[i];
  Mat6N<S>& s = d.sweep.tree_subspace[i];
  if (fast_path_tree_update(m.joint_fast_path[i], m.joints[i], base, q + m.q_index[i], m.axis_sign[i],
                       d.sweep.tree_joint_cosine.data(), d.sweep.tree_joint_sine.data(), m.angle_slot[i], root, pose, s))
    return Vec6<S>::Zero();
  if (joint_axes_coupled(m.joint_fast_path[i])) return detail::universal_tree_update(m, d, i, base, q, v, root);
  return detail::general_joint_tree_update(m, d, i, base, q, v, root);
}

// Tree-frame kinematics of body i (Jain & Rodriguez 1993, Eq. 1): pose and subspace,
// V(i) = V(parent) + H* qdot and a(i) = V(i) x (H* qdot) + joint bias.
// `v` null: zero velocity (impulse problems).
// RootBodyFrames without `pose_wanted`: a leaf with constant hinge terms
// (model.constant_leaf_hinge: a wheel turning about its axis of symmetry)
// has its constant subspace and origin read, and its pose's rotation is
// left unformed; nothing in the dynamics sweeps reads it but an external
// wrench or the hinge forces' output.
template <bool RootBodyFrames = false, class S>
SOADYN_ALWAYS_INLINE void tree_velocity_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                                             bool pose_wanted = true) {
  Vec6<S> joint_rate;  // revolute leaves have none (joint_has_rate_term)
  if (RootBodyFrames && !pose_wanted && m.derived.constant_leaf_hinge[i]) {
    d.sweep.tree_pose[i].translation = m.derived.leaf_hinge_terms[i].origin;  // for beyond_tree_frame_reach
    d.sweep.tree_subspace[i] = m.derived.leaf_hinge_terms[i].subspace;
  } else {
    joint_rate = tree_joint_update<RootBodyFrames>(m, d, i, q, v);
  }
  if (!v) {
    d.sweep.tree_velocity[i].setZero();
    d.sweep.tree_coriolis[i].setZero();
    return;
  }
  const int p = m.parent[i];
  if (d.sweep.tree_subspace[i].cols() == 0) {  // no DOF (a welded appendage): V = V(parent), a = 0
    if (p >= 0)
      d.sweep.tree_velocity[i] = d.sweep.tree_velocity[static_cast<std::size_t>(p)];
    else
      d.sweep.tree_velocity[i].setZero();
    d.sweep.tree_coriolis[i].setZero();
    return;
  }
  const Vec6<S> joint_velocity = detail::subspace_times(d.sweep.tree_subspace[i], v + m.v_index[i]);
  d.sweep.tree_velocity[i] =
      p >= 0 ? Vec6<S>(d.sweep.tree_velocity[static_cast<std::size_t>(p)] + joint_velocity) : joint_velocity;
  motion_cross_into(d.sweep.tree_velocity[i], joint_velocity, d.sweep.tree_coriolis[i]);
  if (joint_has_rate_term(m.joint_fast_path[i])) d.sweep.tree_coriolis[i] += joint_rate;
}

// Kinematics of root i in its own body frame (RootBodyFrames): pose the
// identity, H* the joint's constant body-frame subspace, V(i) = H* v_i and
// a(i) = V x (H* v) = 0, and the world's acceleration [0; -g] carried into
// the body frame by the root's world rotation R (placement times the
// joint's): [0; -R' g].
template <class S>
inline void root_body_frame_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                                 const Vec6<S>& world_acc) {
  SweepData<S>& w = d.sweep;
  w.tree_pose[i] = Transform<S>();
  w.tree_subspace[i] = w.body_subspace[i];
  if (v && joint_is_free(m.joint_fast_path[i]))  // H* = 1: the twist is the joint's v
    w.tree_velocity[i] = Eigen::Map<const Vec6<S>>(v + m.v_index[i]);
  else if (v)
    w.tree_velocity[i] = detail::subspace_times(w.body_subspace[i], v + m.v_index[i]);
  else
    w.tree_velocity[i].setZero();
  w.tree_coriolis[i].setZero();
  Vec6<S>& a = w.tree_world_acceleration[i];
  if (exactly_zero(world_acc)) {  // exactly no gravity (a spacecraft, an impulse): no rotation
    a.setZero();
    return;
  }
  Transform<S> world_pose = m.placement[i];
  const JointFastPath path = m.joint_fast_path[i];
  if (joint_is_free(path)) {
    world_pose.rotation = m.placement[i].rotation * quaternion_rotation(q + m.q_index[i] + 3);
  } else if (const int axis = joint_turning_axis(path); axis >= 0) {  // cosine and sine from the sweep's table
    const std::size_t slot = static_cast<std::size_t>(m.angle_slot[i]);
    rotate_about_coordinate_axis(axis, m.placement[i], w.tree_joint_cosine[slot], w.tree_joint_sine[slot], world_pose);
  }  // prismatic and fixed joints do not turn the body
  const Mat3<S>& R = world_pose.rotation;
  a << R.transpose() * world_acc.template head<3>(), R.transpose() * world_acc.template tail<3>();
}

// Whether body i sits beyond the distance from its tree origin at which tree
// frames keep their precision (tree_frame_reach.hxx); checked only for
// bodies whose geometry does not bound that distance below the reach.
template <class S>
SOADYN_ALWAYS_INLINE bool beyond_tree_frame_reach(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i) {
  if (!(m.derived.reach_checks_needed && m.derived.check_tree_frame_reach[i])) return false;
  const Vec3<S>& t = d.sweep.tree_pose[i].translation;  // just stored: read entry by entry (in_register)
  const S x = in_register(t[0]), y = in_register(t[1]), z = in_register(t[2]);
  return x * x + y * y + z * z > m.derived.tree_frame_reach_squared[i];
}

// Body terms of rigid body i in its tree frame: M(i)'s ten parameters into
// `parameters` and b(i) = V x* (M V) - f_ext into tree_bias_force[i] and
// tree_bias_and_children_z[i]; `f_ext` as in body_updates.hpp. The articulated-body
// sweeps start P from M (tree_frame_sweeps.hxx); the mass matrix's sweep
// needs only the parameters (crba.hxx).
// RootBodyFrames: a body with a constant inertia in its root's frame
// (model.constant_tree_inertia) reads it.
template <bool RootBodyFrames = false, class S>
SOADYN_ALWAYS_INLINE void tree_rigid_body_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* v,
                                               const S* f_ext, InertiaParameters<S>& parameters) {
  const Transform<S>& pose = d.sweep.tree_pose[i];
  if (RootBodyFrames && m.derived.constant_tree_inertia[i])
    parameters = m.derived.tree_inertia_parameters[i];
  else
    inertia_parameters_in_frame(pose, m.mass[i], m.com[i], m.inertia_com[i], m.derived.diagonal_inertia_com[i] != 0, parameters);
  // b is stored entry by entry in both places: a copy read back from memory
  // right after scalar stores would stall store forwarding.
  Vec6<S>& b = d.sweep.tree_bias_force[i];
  Vec6<S>& z = d.sweep.tree_bias_and_children_z[i];
  const Vec6<S> external = f_ext ? pose.force_to_parent(Eigen::Map<const Vec6<S>>(f_ext + 6 * i)) : Vec6<S>::Zero();
  if (v) {
    const Vec6<S>& V = d.sweep.tree_velocity[i];
    force_cross_each(V, momentum(parameters, V), [&](int k, const S& x) { z[k] = b[k] = x - external[k]; });
  } else {
    b = -external;
    z = b;
  }
}

// Body terms of flexible appendage i (appendage_update.hpp) in its tree frame:
// its modal DOFs are eliminated in the body frame, and P^ and z^ are carried
// to the tree frame by one congruence. Children add their P+ and z+ to them;
// once alpha(i) is known, eta_ddot = nu - G' alpha (modal_accelerations,
// flexible_updates.hpp, with alpha carried to the body frame).
// RootBodyFrames, for an appendage welded to a body-frame root: the modes
// are eliminated in the tree frame itself, with the integrals held there
// (ModelTpl::root_frame_integrals), and alpha is read as it is
// (appendage_eliminated_in_tree_frame).
template <bool RootBodyFrames, class S>
inline void tree_flexible_body_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                                    const S* u, const S* f_ext) {
  const Transform<S>& pose = d.sweep.tree_pose[i];
  Vec6<S> external;
  if (f_ext) external = Eigen::Map<const Vec6<S>>(f_ext + 6 * i);
  if (appendage_eliminated_in_tree_frame<RootBodyFrames>(m, i)) {
    if (f_ext) external = pose.force_to_parent(external);
    const std::size_t f = static_cast<std::size_t>(m.flexible_index[i]);
    appendage_update(m, d, i, m.derived.root_frame_integrals[f], q, v, u, f_ext ? &external : nullptr,
                   d.sweep.tree_velocity[i], d.sweep.tree_articulated_inertia[i], d.sweep.tree_bias_and_children_z[i]);
    return;
  }
  Mat6<S> P;
  Vec6<S> z;
  appendage_update(m, d, i, m.flexible_body(static_cast<int>(i)).modal_integrals(), q, v, u, f_ext ? &external : nullptr,
                 Vec6<S>(pose.motion_to_child(d.sweep.tree_velocity[i])), P, z);
  pose.inertia_to_parent_into(P, d.sweep.tree_articulated_inertia[i]);
  d.sweep.tree_bias_and_children_z[i] = pose.force_to_parent(z);
}

}  // namespace soadyn
