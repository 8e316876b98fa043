// The joints' fast paths, chosen by their kernel tag (joint_kernel.hpp): the
// one place that switches on a joint's kernel. Each case calls code of the
// joint's own header; the sweeps (sweeps/steps.hpp, tree_frame_steps.hpp)
// call these two functions once per body and take their general steps where
// they return false.
#pragma once
#include "soadyn/joints/joint.hpp"
#include "soadyn/joints/joint_kernel.hpp"

namespace soadyn {

// Body frame: the pose of the body in its parent, `placement` composed with
// the joint's motion, for the axis-aligned revolute and prismatic joints and
// the fixed joint, whose subspace is constant and bias zero in the body
// frame (Data is built with them). `q` points at the joint's coordinates,
// `sign` is the model's axis_sign. False for every other joint: its calc
// gives the pose, subspace and bias.
template <class S>
SOADYN_ALWAYS_INLINE bool kernel_body_pose(JointKernel kernel, const Transform<S>& placement, const S* q, S sign,
                                           Transform<S>& pose) {
  switch (kernel) {  // the 1-DOF kernels' coordinate along +e_k is q[0] * sign
    case JointKernel::revolute_x: RevoluteJoint<S>::template aligned_pose<0>(placement, q[0] * sign, pose); return true;
    case JointKernel::revolute_y: RevoluteJoint<S>::template aligned_pose<1>(placement, q[0] * sign, pose); return true;
    case JointKernel::revolute_z: RevoluteJoint<S>::template aligned_pose<2>(placement, q[0] * sign, pose); return true;
    case JointKernel::prismatic_x:
    case JointKernel::prismatic_y:
    case JointKernel::prismatic_z:
      PrismaticJoint<S>::aligned_pose(static_cast<int>(kernel) - static_cast<int>(JointKernel::prismatic_x), placement,
                                      q[0] * sign, pose);
      return true;
    case JointKernel::fixed: pose = placement; return true;
    default: return false;
  }
}

// Tree frame: the pose and motion subspace in the tree frame from the pose
// `base` of the joint frame there (root: a root's). A revolute kernel reads
// its angle's cosine and sine at `slot` of the sweep's tables
// (sweeps/joint_angles.hpp); `q` points at the joint's coordinates, `sign`
// is the model's axis_sign. False for the universal joint and the general
// path, which the sweeps step themselves (they need the joint's velocity
// product).
template <class S, class Index>
SOADYN_ALWAYS_INLINE bool kernel_tree_step(JointKernel kernel, const JointModel<S>& joint, const Transform<S>& base,
                                           const S* q, S sign, const S* cosines, const S* sines, Index slot, bool root,
                                           Transform<S>& pose, Mat6N<S>& s) {
  switch (kernel) {
    case JointKernel::revolute_x:
      RevoluteJoint<S>::template aligned_tree_step<0>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointKernel::revolute_y:
      RevoluteJoint<S>::template aligned_tree_step<1>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointKernel::revolute_z:
      RevoluteJoint<S>::template aligned_tree_step<2>(base, cosines[slot], sines[slot], sign, pose, s);
      return true;
    case JointKernel::prismatic_x:
    case JointKernel::prismatic_y:
    case JointKernel::prismatic_z:
      PrismaticJoint<S>::aligned_tree_step(static_cast<int>(kernel) - static_cast<int>(JointKernel::prismatic_x), base,
                                           q[0] * sign, sign, root, pose, s);
      return true;
    case JointKernel::free: FreeJoint<S>::tree_step(base, q, root, pose, s); return true;
    case JointKernel::fixed: pose = base; return true;
    case JointKernel::spherical: SphericalJoint<S>::tree_step(base, q, root, pose, s); return true;
    case JointKernel::revolute_axis: std::get_if<RevoluteJoint<S>>(&joint)->tree_step(base, q[0], pose, s); return true;
    case JointKernel::prismatic_axis:
      std::get_if<PrismaticJoint<S>>(&joint)->tree_step(base, q[0], root, pose, s);
      return true;
    default: return false;
  }
}

}  // namespace soadyn
