#pragma once
#include "soadyn/constraints/constrained_dynamics.hpp"
#include "soadyn/constraints/constrained_impulse.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/constraints/loop_closure.hpp"

namespace soadyn {

template <class S>
Status constrained_impulse(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                           const ConstVecRef<S>& u) {
  if (m.nloops() == 0) return hybrid_impulse<S>(m, d, q, u);
  const Status status = mass_matrix<S>(m, d, q);
  if (!status.ok()) return status;
  loop_residual<S>(m, d, q, v.data());  // C and C v
  d.loops.bias.setZero();               // an impulse: no velocity-product or gravity terms
  d.loops.kappa = -d.loops.velocity_residual;
  return detail::constrained_solve<S>(m, d, u);
}

}  // namespace soadyn
