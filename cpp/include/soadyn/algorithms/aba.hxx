#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/dynamics_path.hxx"

namespace soadyn {

template <class S>
Status forward_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& tau, const S* f_ext) {
  return detail::dynamics_sweeps<detail::ModePolicy::all_regular>(m, d, q.data(), v.data(), tau.data(), f_ext,
                                                                  world_acceleration(m), false);
}

}  // namespace soadyn
