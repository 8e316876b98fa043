// Operations on a joint of any type. Each joint maps its coordinates q (nq)
// and velocities v (nv) to the pose of the body frame in the joint frame, the
// motion subspace S (Jain & Rodriguez 1993's H*(k), body frame, 6 x nv) and
// the bias S' v (velocity-product part of the hinge acceleration).
// Velocities of multi-DOF joints on a Lie group (planar, spherical, free)
// are body-frame twists, so S is constant and their coordinates are
// integrated with the group's exponential map.
//
// Every function here is a std::visit over JointModel (joint_types.hpp): the
// joint type is resolved at compile time inside each alternative, with no
// virtual call; the joint's own struct (revolute.hpp, ...) holds the code.
#pragma once
#include <string>
#include <vector>
#include <type_traits>
#include "soadyn/joints/joint_types.hpp"

namespace soadyn {

namespace detail {
template <class J>
using joint_type = std::decay_t<J>;

// Whether the joint type declares a dedicated fast path (joint_fast_path.hpp).
template <class J, class = void>
struct has_fast_path : std::false_type {};
template <class J>
struct has_fast_path<J, std::void_t<decltype(&J::fast_path)>> : std::true_type {};
}  // namespace detail

template <class S>
int joint_nq(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::nq; }, j);
}
template <class S>
int joint_nv(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::nv; }, j);
}
template <class S>
bool joint_is_fixed(const JointModel<S>& j) {
  return std::holds_alternative<FixedJoint<S>>(j);
}

// Whether the joint's coordinates are its velocities' integrals (q' = v), so a motion source can set a
// coordinate directly (revolute, prismatic, helical, cylindrical, universal, translation).
template <class S>
bool joint_has_scalar_coordinates(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::Space::scalar_coordinates; }, j);
}

// The joint's type name ("revolute", ...).
template <class S>
const char* joint_type_name(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::name; }, j);
}

// Suffixes naming the joint's coordinates and velocities (unused for 1-DOF joints).
template <class S>
const char* const* joint_coordinate_suffixes(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::coordinate_suffixes.data(); }, j);
}
template <class S>
const char* const* joint_velocity_suffixes(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::velocity_suffixes.data(); }, j);
}

// Offset of the unit quaternion inside the joint's q block, or -1.
template <class S>
int joint_quaternion_offset(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::Space::quaternion_offset; }, j);
}

// Whether the joint can move its body's origin.
template <class S>
bool joint_translates(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::translates; }, j);
}

// Validates and normalises the joint's parameters; throws
// std::invalid_argument naming `joint_name` when it cannot be built.
template <class S>
void check_joint(JointModel<S>& j, const std::string& joint_name) {
  std::visit([&](auto& jj) { jj.check(joint_name); }, j);
}

// The joint's fast-path tag; `sign` receives the axis sign of an axis-aligned
// revolute or prismatic joint (1 otherwise).
template <class S>
JointFastPath classify_joint(const JointModel<S>& j, S& sign) {
  sign = S(1);
  return std::visit(
      [&](const auto& jj) {
        if constexpr (detail::has_fast_path<detail::joint_type<decltype(jj)>>::value)
          return jj.fast_path(sign);
        else
          return JointFastPath::general;
      },
      j);
}

// The signs of the joint's angles that the sweeps' table holds
// (sweeps/joint_angles.hpp), one per tabulated coordinate, in order: an
// axis-aligned revolute joint's one (`fast_path` and `sign` from
// classify_joint), a universal joint's two when both its axes are coordinate
// axes; none for any other joint.
template <class S>
std::vector<S> tabulated_angle_signs(const JointModel<S>& j, JointFastPath path, const S& sign) {
  if (path == JointFastPath::revolute_x || path == JointFastPath::revolute_y || path == JointFastPath::revolute_z)
    return {sign};
  if (const auto* universal = std::get_if<UniversalJoint<S>>(&j)) {
    S sign1, sign2;
    if (coordinate_axis(universal->axis1, sign1) >= 0 && coordinate_axis(universal->axis2, sign2) >= 0)
      return {sign1, sign2};
  }
  return {};
}

// Pose, subspace and bias at (q, v); q and v point at the joint's blocks.
// Joints with a constant subspace and no bias leave `subspace` and `bias` as
// joint_init_subspace and Data's construction set them.
template <class S>
void joint_calc(const JointModel<S>& j, const S* q, const S* v, Transform<S>& pose, Mat6N<S>& subspace,
                Vec6<S>& bias) {
  std::visit([&](const auto& jj) { jj.calc(q, v, pose, subspace, bias); }, j);
}

// Sizes and fills the constant part of the motion subspace (once, at Data creation).
template <class S>
void joint_init_subspace(const JointModel<S>& j, Mat6N<S>& s) {
  s.setZero(6, joint_nv(j));
  std::visit([&](const auto& jj) { jj.fill_subspace(s); }, j);
}

// Neutral configuration: zeros, identity quaternions.
template <class S>
void joint_neutral(const JointModel<S>& j, S* q) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::neutral(q); }, j);
}

// A random configuration of the joint (CoordinateSampler, joint_base.hpp).
template <class S>
void joint_random(const JointModel<S>& j, CoordinateSampler& draw, S* q) {
  std::visit([&](const auto& jj) { jj.random(draw, q); }, j);
}

// q_out = q (+) v dt on the joint's manifold (may alias q).
template <class S>
void joint_integrate(const JointModel<S>& j, const S* q, const S* v, const S& dt, S* q_out) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::integrate(q, v, dt, q_out); }, j);
}

}  // namespace soadyn
