#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/sweeps/dynamics_path.hxx"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/algorithms/rnea.hxx"

namespace soadyn {

namespace detail {
// hybrid_dynamics of the tree without its force elements.
template <class S>
Status rigid_hybrid_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                             const ConstVecRef<S>& u, const S* f_ext, DynamicsOutputs outputs) {
  if constexpr (has_speed_paths<S>) {
    if (m.n_prescribed == 0 && !outputs.hinge_forces) {  // a regular tree: exactly the articulated-body sweeps
      const Status s = dynamics_sweeps<ModePolicy::all_regular>(m, d, q.data(), v.data(), u.data(), f_ext,
                                                                detail::world_acceleration(m), false);
      d.tau = u;
      return s;
    }
    if (m.n_prescribed == m.nv) {  // every DOF prescribed (so rigid: modal DOFs are regular): exactly RNEA
      newton_euler_sweeps<false>(m, d, q.data(), detail::velocities_unless_at_rest(m, v), u.data(), f_ext,
                                 detail::world_acceleration(m));
      d.qdd = u;
      return detail::check_finite(d.tau);
    }
  }
  return dynamics_sweeps<ModePolicy::model_flags>(m, d, q.data(), v.data(), u.data(), f_ext, detail::world_acceleration(m),
                                                  outputs.hinge_forces);
}
}  // namespace detail

template <class S>
Status hybrid_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const ConstVecRef<S>& u, const S* f_ext, DynamicsOutputs outputs) {
  if (!m.has_force_elements()) return detail::rigid_hybrid_dynamics(m, d, q, v, u, f_ext, outputs);
  return detail::with_force_elements(m, d, q.data(), v.data(), u.data(), f_ext, detail::SpringInputRows::regular,
                                     [&](const S* input, const S* f) {
                                       return detail::rigid_hybrid_dynamics(
                                           m, d, q, v, Eigen::Map<const VecX<S>>(input, m.nv), f, outputs);
                                     });
}

template <class S>
Status hybrid_impulse(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& u) {
  return detail::dynamics_sweeps<detail::ModePolicy::model_flags>(m, d, q.data(), static_cast<const S*>(nullptr),
                                                                  u.data(), static_cast<const S*>(nullptr),
                                                                  Vec6<S>(Vec6<S>::Zero()), false);
}

}  // namespace soadyn
