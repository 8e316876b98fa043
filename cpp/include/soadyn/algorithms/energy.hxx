#pragma once
#include "soadyn/algorithms/energy.hpp"
#include "soadyn/algorithms/kinematics.hxx"

namespace soadyn {

template <class S>
S kinetic_energy(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  S energy(0);
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    joint_step(m, d, i, q.data(), v.data());
    velocity_step(m, d, i, v.data());
    energy += S(0.5) * d.velocity[i].dot(m.inertia[i] * d.velocity[i]);
  }
  return energy;
}

template <class S>
Vec3<S> center_of_mass(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, S* total_mass) {
  forward_kinematics<S>(m, d, q.data(), nullptr);
  S mass(0);
  Vec3<S> first_moment = Vec3<S>::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    mass += m.mass[i];
    first_moment += m.mass[i] * d.pose_in_world[i].apply_point(m.com[i]);
  }
  if (total_mass) *total_mass = mass;
  return mass > S(0) ? Vec3<S>(first_moment / mass) : Vec3<S>::Zero();
}

template <class S>
S potential_energy(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  S mass;
  const Vec3<S> c = center_of_mass(m, d, q, &mass);
  return -mass * m.gravity.dot(c);
}

template <class S>
Vec6<S> momentum(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(m, d, q.data(), v.data());
  Vec6<S> h = Vec6<S>::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i)
    h += d.pose_in_world[i].force_to_parent(Vec6<S>(m.inertia[i] * d.velocity[i]));
  return h;
}

}  // namespace soadyn
