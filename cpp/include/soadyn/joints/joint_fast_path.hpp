// Tags of the compile-time fast paths for the joints robots are made of. A
// revolute or prismatic joint whose axis is +-x, +-y or +-z of its joint frame
// (nearly every URDF joint), the free joint and the fixed joint get their
// pose and motion subspace from dedicated code; the universal and spherical
// joints, and revolute and prismatic joints about any other axis, have
// tree-frame fast paths. The code of each fast path lives in its
// joint's header (revolute.hpp, prismatic.hpp, free.hpp, universal.hpp,
// spherical.hpp), and the one switch on the tag is fast_path_updates.hpp, which
// the sweeps call once per body; elsewhere the tag is read through the
// predicates below.
// Every other joint takes the general path through JointModel's variant.
// The model classifies each joint once, when the body is added
// (classify_joint in joint.hpp, from the joint's own `fast_path`).
#pragma once
#include <cstdint>
#include "soadyn/spatial/types.hpp"

namespace soadyn {

enum class JointFastPath : std::uint8_t {
  revolute_x, revolute_y, revolute_z,
  prismatic_x, prismatic_y, prismatic_z,
  free,
  fixed,  // no motion: the placement alone (a flexible body clamped to its parent)
  universal,  // tree frames only; body-frame updates take the general path
  spherical,  // tree frames only; body-frame updates take the general path
  revolute_axis,   // any other axis; tree frames only, body-frame updates take the general path
  prismatic_axis,  // any other axis; tree frames only, body-frame updates take the general path
  general,
};

// Whether the fast path's joint has a velocity-product term of its own (dS/dt v
// with S varying in the body frame): the universal joint and the general
// path; every other fast path's tree update returns zero for it.
constexpr bool joint_has_rate_term(JointFastPath k) { return k == JointFastPath::universal || k == JointFastPath::general; }

// Whether the fast path's joint has a constant motion subspace in its body
// frame, the one Data's constructor writes into body_subspace: the
// axis-aligned revolute and prismatic joints, the free and the fixed joint.
constexpr bool joint_has_constant_body_subspace(JointFastPath k) {
  return k <= JointFastPath::prismatic_z || k == JointFastPath::free || k == JointFastPath::fixed;
}

// The free joint: its motion subspace in the body frame is the identity
// (H* = 1), so a free root's twist is its v and its block of M its
// composite inertia.
constexpr bool joint_is_free(JointFastPath k) { return k == JointFastPath::free; }

// A weld: no motion, the placement alone.
constexpr bool joint_is_weld(JointFastPath k) { return k == JointFastPath::fixed; }

// The coordinate axis (0, 1, 2) a revolute joint turns about, or -1 for
// every other fast path.
constexpr int joint_turning_axis(JointFastPath k) {
  return k <= JointFastPath::revolute_z ? static_cast<int>(k) - static_cast<int>(JointFastPath::revolute_x) : -1;
}

// Whether the joint's second subspace column turns with its first
// coordinate (the universal joint: S depends on q, so the derivatives of
// S v by q couple its two axes).
constexpr bool joint_axes_coupled(JointFastPath k) { return k == JointFastPath::universal; }

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

// The tag of the first fast path of a family (revolute_x, prismatic_x) moved
// to coordinate axis k.
inline JointFastPath fast_path_along(JointFastPath first, int k) {
  return static_cast<JointFastPath>(static_cast<int>(first) + k);
}

}  // namespace soadyn
