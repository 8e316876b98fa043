#pragma once
#include "soadyn/algorithms/energy.hpp"
#include "soadyn/algorithms/force_elements.hxx"
#include "soadyn/algorithms/kinematics.hxx"

namespace soadyn {

namespace detail {

// Spatial momentum of body i about its origin, body frame: M V for a rigid
// body, the rigid rows of M(eta) [V; eta_dot] for a flexible one (after
// forward_kinematics with velocities). Uses the flexible body's scratch.
template <class S>
Vec6<S> body_momentum(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  if (!m.is_flexible(static_cast<int>(i))) return m.inertia[i] * d.body_velocity[i];
  flexible_inertia_update(m, d, i, q);
  const FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  Vec6<S> h;
  h.noalias() = fd.mass.template topLeftCorner<6, 6>() * d.body_velocity[i];
  h.noalias() += fd.mass.topRightCorner(6, m.n_modes[i]) * modal_velocities(m, static_cast<int>(i), v);
  return h;
}

// First moment of mass of body i about its origin, body frame (c(eta) of a
// flexible body, modal_integrals.hpp Eq. 2).
template <class S>
Vec3<S> body_first_moment(const ModelTpl<S>& m, std::size_t i, const S* q) {
  if (!m.is_flexible(static_cast<int>(i))) return m.mass[i] * m.com[i];
  return m.flexible_body(static_cast<int>(i)).modal_integrals().first_moment_at(modal_coordinates(m, static_cast<int>(i), q));
}

// 1/2 sum V' M V, the body velocities of a kinematic sweep at (q, v) in d.
template <class S>
S kinetic_energy_of_velocities(const ModelTpl<S>& m, const DataTpl<S>& d, const S* q, const S* v) {
  S energy(0);
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int body = static_cast<int>(i);
    if (m.is_flexible(body))  // 1/2 [V; eta_dot]' M(eta) [V; eta_dot], M(eta) left unformed
      energy += m.flexible_body(body).modal_integrals().kinetic_energy_at(
          modal_coordinates(m, body, q), d.body_velocity[i], modal_velocities(m, body, v));
    else
      energy += S(0.5) * d.body_velocity[i].dot(m.inertia[i] * d.body_velocity[i]);
  }
  for (int k = 0; k < m.nv; ++k)  // rotor inertias (ModelTpl::set_armature)
    if (m.armature[static_cast<std::size_t>(k)] != S(0)) energy += S(0.5) * m.armature[static_cast<std::size_t>(k)] * v[k] * v[k];
  return energy;
}

// Total mass and centre of mass in the world frame, the world poses at q in d.
template <class S>
Vec3<S> center_of_mass_of_poses(const ModelTpl<S>& m, const DataTpl<S>& d, const S* q, S& mass) {
  mass = S(0);
  Vec3<S> first_moment = Vec3<S>::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    mass += m.mass[i];
    const Transform<S>& X = d.pose_in_world[i];
    first_moment += m.mass[i] * X.translation + X.rotation * body_first_moment(m, i, q);
  }
  return mass > S(0) ? Vec3<S>(first_moment / mass) : Vec3<S>::Zero();
}

// -sum m g . c, the strain energy and the force elements' potential, the world poses at q in d.
template <class S>
S potential_energy_of_poses(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  S mass;
  const Vec3<S> c = center_of_mass_of_poses(m, d, q.data(), mass);
  S strain(0);  // 1/2 eta' K eta
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    if (!m.is_flexible(static_cast<int>(i))) continue;
    const MatX<S>& K = m.flexible_body(static_cast<int>(i)).stiffness();
    const auto eta = modal_coordinates(m, static_cast<int>(i), q.data());
    for (Eigen::Index r = 0; r < eta.size(); ++r) strain += S(0.5) * eta[r] * K.row(r).dot(eta.transpose());
  }
  const S springs = m.has_force_elements() ? force_element_potential(m, d, q) : S(0);
  return strain + springs - mass * m.gravity.dot(c);
}

}  // namespace detail

template <class S>
S kinetic_energy(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(m, d, q.data(), v.data());
  return detail::kinetic_energy_of_velocities(m, d, q.data(), v.data());
}

template <class S>
Vec3<S> center_of_mass(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, S* total_mass) {
  forward_kinematics<S>(m, d, q.data(), nullptr);
  S mass;
  const Vec3<S> c = detail::center_of_mass_of_poses(m, d, q.data(), mass);
  if (total_mass) *total_mass = mass;
  return c;
}

template <class S>
S potential_energy(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  forward_kinematics<S>(m, d, q.data(), nullptr);
  return detail::potential_energy_of_poses(m, d, q);
}

template <class S>
void mechanical_energy(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       S& kinetic, S& potential) {
  forward_kinematics<S>(m, d, q.data(), v.data());  // the poses of the positions-only sweep, and the velocities
  kinetic = detail::kinetic_energy_of_velocities(m, d, q.data(), v.data());
  potential = detail::potential_energy_of_poses(m, d, q);
}

template <class S>
Vec6<S> momentum(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(m, d, q.data(), v.data());
  Vec6<S> h = Vec6<S>::Zero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i)
    h += d.pose_in_world[i].force_to_parent(detail::body_momentum(m, d, i, q.data(), v.data()));
  return h;
}

}  // namespace soadyn
