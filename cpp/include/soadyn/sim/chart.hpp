// Local coordinates for integrating q on the joint manifolds (Runge-Kutta-
// Munthe-Kaas). Around a base configuration q0 every joint has a chart of
// dimension nv: q = retract(q0, xi). Classical Runge-Kutta on xi and v is
// then of full order and keeps every quaternion exactly on the unit sphere
// (it only ever multiplies by exact exponentials). Each joint's
// configuration space (its `Space`: joints/vector_space.hpp, planar.hpp,
// spherical.hpp, free.hpp) defines its chart.
#pragma once
#include "soadyn/joints/joint.hpp"

namespace soadyn {

template <class S>
void chart_retract(const JointModel<S>& j, const S* q0, const S* xi, S* q) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::retract(q0, xi, q); }, j);
}

// dxi/dt at the configuration q = retract(q0, xi) for velocity v.
template <class S>
void chart_rate(const JointModel<S>& j, const S* q, const S* xi, const S* v, S* rate) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::chart_rate(q, xi, v, rate); }, j);
}

// Whether the DOF's coordinate is its velocity's integral (q' = v), so a
// motion source can set the coordinate directly.
template <class S>
bool joint_has_scalar_coordinates(const JointModel<S>& j) {
  return std::visit([](const auto& jj) { return detail::joint_type<decltype(jj)>::Space::scalar_coordinates; }, j);
}

}  // namespace soadyn
