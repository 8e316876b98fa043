// Compile-time kernels for the joints robots are made of. A revolute or
// prismatic joint whose axis is +-x, +-y or +-z of its joint frame (nearly
// every URDF joint), the free joint and the fixed joint get their pose and
// motion subspace from dedicated code: a rotation about a coordinate axis changes two columns
// of the parent rotation (12 multiplications instead of Rodrigues' formula
// and a 3x3 product), and the subspace is a column of the body rotation.
// The universal joint has a tree-frame kernel too (algorithms/
// tree_frame_steps.hpp): its subspace and velocity product are read off the
// two axes in the tree frame, with no body-frame subspace to carry over.
// Every other joint takes the general path through JointModel's variant.
// The model classifies each joint once, when the body is added; the sweeps
// switch on the kernel once per body.
#pragma once
#include <cstdint>
#include "soadyn/joints/joint.hpp"

namespace soadyn {

enum class JointKernel : std::uint8_t {
  revolute_x, revolute_y, revolute_z,
  prismatic_x, prismatic_y, prismatic_z,
  free,
  fixed,  // no motion: the placement alone (a flexible body clamped to its parent)
  universal,  // tree frames only; body-frame steps take the general path
  general,
};

// The coordinate axis k and sign s with axis = s e_k, or k = -1.
template <class S>
int coordinate_axis(const Vec3<S>& axis, S& sign) {
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    if (axis[a] == S(0) && axis[b] == S(0) && (axis[k] == S(1) || axis[k] == S(-1))) {
      sign = axis[k];
      return k;
    }
  }
  return -1;
}

// The kernel of `joint`; `sign` receives the axis sign of an axis-aligned
// revolute or prismatic joint (1 otherwise).
template <class S>
JointKernel classify_joint(const JointModel<S>& joint, S& sign) {
  sign = S(1);
  if (const auto* r = std::get_if<RevoluteJoint<S>>(&joint)) {
    const int k = coordinate_axis(r->axis, sign);
    if (k >= 0) return static_cast<JointKernel>(static_cast<int>(JointKernel::revolute_x) + k);
  } else if (const auto* p = std::get_if<PrismaticJoint<S>>(&joint)) {
    const int k = coordinate_axis(p->axis, sign);
    if (k >= 0) return static_cast<JointKernel>(static_cast<int>(JointKernel::prismatic_x) + k);
  } else if (std::holds_alternative<FreeJoint<S>>(joint)) {
    return JointKernel::free;
  } else if (std::holds_alternative<FixedJoint<S>>(joint)) {
    return JointKernel::fixed;
  } else if (std::holds_alternative<UniversalJoint<S>>(joint)) {
    return JointKernel::universal;
  }
  sign = S(1);
  return JointKernel::general;
}

// pose = base * Rot(e_Axis, angle): the rotation about a coordinate axis
// mixes two columns of base's rotation (cyclic order Axis, Axis+1, Axis+2).
template <int Axis, class S>
inline void rotate_about_coordinate_axis(const Transform<S>& base, const S& angle, Transform<S>& pose) {
  using std::cos;
  using std::sin;
  constexpr int a1 = (Axis + 1) % 3, a2 = (Axis + 2) % 3;
  const S c = cos(angle), s = sin(angle);
  pose.translation = base.translation;
  pose.rotation.col(Axis) = base.rotation.col(Axis);
  pose.rotation.col(a1) = c * base.rotation.col(a1) + s * base.rotation.col(a2);
  pose.rotation.col(a2) = c * base.rotation.col(a2) - s * base.rotation.col(a1);
}

// pose = base * Rot(e_axis, angle) for a run-time axis 0, 1 or 2.
template <class S>
inline void rotate_about_coordinate_axis(int axis, const Transform<S>& base, const S& angle, Transform<S>& pose) {
  switch (axis) {
    case 0: rotate_about_coordinate_axis<0>(base, angle, pose); return;
    case 1: rotate_about_coordinate_axis<1>(base, angle, pose); return;
    default: rotate_about_coordinate_axis<2>(base, angle, pose); return;
  }
}

}  // namespace soadyn
