#pragma once
#include "soadyn/sweeps/flexible_updates.hpp"
#include "soadyn/algorithms/force_elements.hxx"
#include "soadyn/algorithms/rnea.hpp"

namespace soadyn {

namespace detail {
// v and qdd may be null (zero velocities: no velocity products and no
// elastic forces; zero accelerations). Flex adds flexible bodies.
template <bool Flex, class S>
void newton_euler_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* qdd, const S* f_ext,
                         const Vec6<S>& world_acc) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: kinematics, accelerations, body forces
    body_joint_update<Flex>(m, d, i, q, v);
    body_motion_update<Flex>(m, d, i, q, v, f_ext);
    d.body_acceleration[i] = body_parent_acceleration<Flex>(m, d, i, world_acc, qdd) + d.sweep.body_coriolis[i];
    if (qdd) d.body_acceleration[i] += detail::subspace_times(d.sweep.body_subspace[i], qdd + m.v_index[i]);
    if constexpr (Flex) {
      if (m.is_flexible(static_cast<int>(i))) {
        flexible_newton_euler(m, d, i, qdd);
        continue;
      }
    }
    d.hinge_force[i] = m.inertia[i] * d.body_acceleration[i] + d.sweep.body_bias_force[i];
  }
  for (std::size_t i = n; i-- > 0;) {  // tip to base: hinge forces
    detail::subspace_transpose_times(d.sweep.body_subspace[i], d.hinge_force[i],
                             d.tau.segment(m.v_index[i], m.nv_body[i]));
    if (qdd) detail::add_armature_torques(m, i, qdd, d.tau.data());
    if constexpr (Flex)
      if (m.is_flexible(static_cast<int>(i)))
        d.tau.segment(m.modal_v_index(static_cast<int>(i)), m.n_modes[i]) = flexible_data(m, d, i).modal_force;
    push_body_force<Flex>(m, d, i, d.hinge_force[i]);
  }
}

// Compiled once, in rnea.cpp, for double (and float): inverse dynamics, the
// all-prescribed hybrid dynamics, the equation terms and the loop solves
// call that code.
#define SOADYN_NEWTON_EULER_SWEEPS(FLEX, S)                                                                 \
  template void newton_euler_sweeps<FLEX, S>(const ModelTpl<S>&, DataTpl<S>&, const S*, const S*, const S*, \
                                             const S*, const Vec6<S>&);
extern SOADYN_NEWTON_EULER_SWEEPS(false, double)
extern SOADYN_NEWTON_EULER_SWEEPS(true, double)
#if SOADYN_FLOAT
extern SOADYN_NEWTON_EULER_SWEEPS(false, float)
extern SOADYN_NEWTON_EULER_SWEEPS(true, float)
#endif

template <class S>
void rnea(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* qdd, const S* f_ext) {
  if (m.has_flexible_bodies())
    newton_euler_sweeps<true>(m, d, q, v, qdd, f_ext, detail::world_acceleration(m));
  else
    newton_euler_sweeps<false>(m, d, q, v, qdd, f_ext, detail::world_acceleration(m));
}
}  // namespace detail

template <class S>
Status inverse_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& qdd, const S* f_ext) {
  const auto rigid = [&](const S*, const S* f) {
    detail::rnea(m, d, q.data(), detail::velocities_unless_at_rest(m, v), qdd.data(), f);
    return detail::check_finite(d.tau);
  };
  if (!m.has_force_elements()) return rigid(nullptr, f_ext);
  return detail::with_force_elements(m, d, q.data(), v.data(), static_cast<const S*>(nullptr), f_ext,
                                     detail::SpringInputRows::none, rigid);
}

template <class S>
Status bias_forces(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  const auto rigid = [&](const S*, const S* f) {
    detail::rnea<S>(m, d, q.data(), v.data(), nullptr, f);
    return detail::check_finite(d.tau);
  };
  if (!m.has_force_elements()) return rigid(nullptr, nullptr);
  return detail::with_force_elements(m, d, q.data(), v.data(), static_cast<const S*>(nullptr),
                                     static_cast<const S*>(nullptr), detail::SpringInputRows::none, rigid);
}

}  // namespace soadyn
