#pragma once
#include "soadyn/algorithms/rnea.hpp"

namespace soadyn {

namespace detail {
// qdd may be null (zero accelerations).
template <class S>
void rnea(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* qdd, const S* f_ext) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = world_acceleration(m);
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: kinematics, accelerations, body forces
    joint_step(m, d, i, q, v);
    velocity_step(m, d, i, v);
    bias_force_step(m, d, i, f_ext);
    d.acceleration[i] = parent_acceleration(m, d, i, world_acc) + d.coriolis[i];
    if (qdd) d.acceleration[i].noalias() += d.subspace[i] * Eigen::Map<const VecN<S>>(qdd + m.v_index[i], m.nv_body[i]);
    d.hinge_force[i] = m.inertia[i] * d.acceleration[i] + d.bias_force[i];
  }
  for (std::size_t i = n; i-- > 0;) {  // tip to base: hinge forces
    d.tau.segment(m.v_index[i], m.nv_body[i]).noalias() = d.subspace[i].transpose() * d.hinge_force[i];
    push_force_to_parent(m, d, i, d.hinge_force[i]);
  }
}
}  // namespace detail

template <class S>
void inverse_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                      const ConstVecRef<S>& qdd, const S* f_ext) {
  detail::rnea(m, d, q.data(), v.data(), qdd.data(), f_ext);
}

template <class S>
void bias_forces(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  detail::rnea<S>(m, d, q.data(), v.data(), nullptr, nullptr);
}

}  // namespace soadyn
