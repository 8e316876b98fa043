#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/sweeps/dynamics_path.hxx"
#include "soadyn/algorithms/force_elements.hxx"

namespace soadyn {

template <class S>
Status forward_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& tau, const S* f_ext) {
  const auto rigid = [&](const S* torques, const S* f) {
    return detail::dynamics_sweeps<detail::ModePolicy::all_regular>(m, d, q.data(), v.data(), torques, f,
                                                                    detail::world_acceleration(m), false);
  };
  if (!m.has_force_elements()) return rigid(tau.data(), f_ext);
  return detail::with_force_elements(m, d, q.data(), v.data(), tau.data(), f_ext, detail::SpringInputRows::all, rigid);
}

}  // namespace soadyn
