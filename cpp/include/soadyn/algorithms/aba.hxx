#pragma once
#include "soadyn/algorithms/aba.hpp"

namespace soadyn {

template <class S>
Status forward_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& tau, const S* f_ext) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = world_acceleration(m);
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, b (seed Eq. 1)
    joint_step(m, d, i, q.data(), v.data());
    velocity_step(m, d, i, v.data());
    bias_force_step(m, d, i, f_ext);
    d.articulated_inertia[i] = m.inertia[i];
    d.articulated_bias[i] = d.bias_force[i];
  }
  Mat6<S> P_plus;
  Vec6<S> z_plus;
  for (std::size_t i = n; i-- > 0;) {  // tip to base (seed Eqs. 14, 28, all hinges regular)
    const Mat6<S>& P = d.articulated_inertia[i];
    const Vec6<S> z = d.articulated_bias[i] + P * d.coriolis[i];
    VecN<S> eps = tau.segment(m.v_index[i], m.nv_body[i]);
    const int bad = articulated_hinge_step(P, d.subspace[i], z, eps, d.gain[i], d.innovation[i], P_plus, z_plus);
    if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, m.v_index[i] + bad};
    if (m.parent[i] >= 0) push_articulated_to_parent(m, d, i, P_plus, z_plus);
  }
  for (std::size_t i = 0; i < n; ++i) {  // base to tip (seed Eq. 29)
    const Vec6<S> alpha_plus = parent_acceleration(m, d, i, world_acc);
    auto qdd = d.qdd.segment(m.v_index[i], m.nv_body[i]);
    qdd.noalias() = d.innovation[i] - d.gain[i].transpose() * alpha_plus;
    d.acceleration[i] = alpha_plus + d.coriolis[i];
    d.acceleration[i].noalias() += d.subspace[i] * qdd;
  }
  return check_finite(d.qdd);
}

}  // namespace soadyn
