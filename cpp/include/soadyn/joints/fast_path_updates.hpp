// The joints' fast paths, chosen by their fast-path tag (joint_fast_path.hpp): the
// one place that switches on a joint's fast path. Each case calls code of the
// joint's own header; the sweeps (sweeps/body_updates.hpp, tree_frame_updates.hpp)
// call these two functions once per body and take their general updates where
// they return false.
#pragma once
#include "soadyn/joints/joint.hpp"
#include "soadyn/joints/joint_fast_path.hpp"

namespace soadyn {

// Body frame: the pose of the body in its parent, `placement` composed with
// the joint's motion, for the axis-aligned revolute and prismatic joints and
// the fixed joint, whose subspace is constant and bias zero in the body
// frame (Data is built with them). `q` points at the joint's coordinates,
// `sign` is the model's axis_sign. False for every other joint: its calc
// gives the pose, subspace and bias.
template <class S>
SOADYN_ALWAYS_INLINE bool fast_path_body_pose(JointFastPath path, const Transform<S>& placement, const S* q, S sign,
                                           Transform<S>& pose) {
  switch (path) {  // the 1-DOF fast paths' coordinate along +e_k is q[0] * sign
    case JointFastPath::revolute_x: RevoluteJoint<S>::template aligned_pose<0>(placement, q[0] * sign, pose); return true;
    case JointFastPath::revolute_y: RevoluteJoint<S>::template aligned_pose<1>(placement, q[0] * sign, pose); return true;
    case JointFastPath::revolute_z: RevoluteJoint<S>::template aligned_pose<2>(placement, q[0] * sign, pose); return true;
    case JointFastPath::prismatic_x:
    case JointFastPath::prismatic_y:
    case JointFastPath::prismatic_z:
      PrismaticJoint<S>::aligned_pose(static_cast<int>(path) - static_cast<int>(JointFastPath::prismatic_x), placement,
                                      q[0] * sign, pose);
      return true;
    case JointFastPath::fixed: pose = placement; return true;
    default: return false;
  }
}

// Tree frame: the pose and motion subspace in the tree frame from the pose
// `base` of the joint frame there (root: a root's). A revolute fast path reads
// its angle's cosine and sine at `slot` of the sweep's tables
// (sweeps/joint_angles.hpp); `q` points at the joint's coordinates, `sign`
// is the model's axis_sign. False for the universal joint and the general
// path, which the sweeps update themselves (they need the joint's velocity
// product).
template <class S, class Index>
SOADYN_ALWAYS_INLINE bool fast_path_tree_update(JointFastPath path, const JointModel<S>& joint, const Transform<S>& base,
                                           const S* q, S sign, const S* cosines, const S* sines, Index slot, bool root,
                                           Transform<S>& pose, Mat6N<S>& s) {
  switch (path) {
    case JointFastPath::revolute_x:
      RevoluteJoint<S>::template aligned_tree_update<0>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointFastPath::revolute_y:
      RevoluteJoint<S>::template aligned_tree_update<1>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointFastPath::revolute_z:
      RevoluteJoint<S>::template aligned_tree_update<2>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointFastPath::prismatic_x:
    case JointFastPath::prismatic_y:
    case JointFastPath::prismatic_z:
      PrismaticJoint<S>::aligned_tree_update(static_cast<int>(path) - static_cast<int>(JointFastPath::prismatic_x), base,
                                           q[0] * sign, sign, root, pose, s);
      return true;
    case JointFastPath::free: FreeJoint<S>::tree_update(base, q, root, pose, s); return true;
    case JointFastPath::fixed: pose = base; return true;
    case JointFastPath::spherical: SphericalJoint<S>::tree_update(base, q, root, pose, s); return true;
    case JointFastPath::revolute_axis: std::get_if<RevoluteJoint<S>>(&joint)->tree_update(base, q[0], pose, s); return true;
    case JointFastPath::prismatic_axis:
      std::get_if<PrismaticJoint<S>>(&joint)->tree_update(base, q[0], root, pose, s);
      return true;
    default: return false;
  }
}

}  // namespace soadyn
