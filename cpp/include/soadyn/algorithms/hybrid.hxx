#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/flexible_steps.hpp"
#include "soadyn/algorithms/hybrid.hpp"

namespace soadyn {

namespace detail {

// S_p qdd_p: the known hinge acceleration of the prescribed DOFs of body i.
template <class S>
inline Vec6<S> prescribed_hinge_acceleration(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i, const S* u) {
  const HingeModes& h = m.modes[i];
  const S* ui = u + m.v_index[i];
  if (h.n_regular == 0) return subspace_times(d.subspace[i], ui);
  Vec6<S> a = Vec6<S>::Zero();
  for (int k = 0; k < h.n_prescribed; ++k) a += d.subspace[i].col(h.prescribed[k]) * ui[h.prescribed[k]];
  return a;
}

// Tip-to-base step of a body that needs an articulated inertia (seed Eq. 28).
template <bool Flex, class S>
inline int articulated_body_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                   const Vec6<S>& world_acc) {
  if constexpr (Flex) {
    if (m.is_flexible(static_cast<int>(i))) {
      const int bad = eliminate_modal_coordinates(m, d, i, u);
      if (bad >= 0) return bad;
    }
  }
  const HingeModes& h = m.modes[i];
  const Mat6<S>& P = d.articulated_inertia[i];
  // z(k) = phi z+(k-1) + b(k) + P(k) [H_p* qdd_p(k) + a(k)]
  Vec6<S> hinge_acc = d.coriolis[i];
  if (h.n_prescribed > 0) hinge_acc += prescribed_hinge_acceleration(m, d, i, u);
  const Vec6<S> z = d.articulated_bias[i] + P * hinge_acc;
  Mat6<S> P_plus;
  Vec6<S> z_plus;
  const Mat6<S>* P_out = &P;
  const Vec6<S>* z_out = &z;
  if (h.n_regular > 0) {
    const S* ui = u + m.v_index[i];
    VecN<S> eps(h.n_regular);
    const Mat6N<S>* Sr = &d.subspace[i];
    if (h.n_prescribed > 0) {  // mixed hinge: gather the regular columns
      Mat6N<S>& gathered = d.regular_subspace[i];
      gathered.resize(6, h.n_regular);
      for (int k = 0; k < h.n_regular; ++k) gathered.col(k) = d.subspace[i].col(h.regular[k]);
      Sr = &gathered;
    }
    if (h.n_prescribed == 0)
      eps = Eigen::Map<const VecN<S>>(ui, h.n_regular);
    else
      for (int k = 0; k < h.n_regular; ++k) eps[k] = ui[h.regular[k]];
    const int bad = articulated_hinge_step(P, *Sr, z, eps, d.gain[i], d.innovation[i], P_plus, z_plus);
    if (bad >= 0) return m.v_index[i] + h.regular[bad];
    P_out = &P_plus;
    z_out = &z_plus;
  }
  const int p = m.parent[i];
  if (p < 0) return -1;
  if (m.modes[static_cast<std::size_t>(p)].needs_articulated_inertia) {
    push_articulated<Flex>(m, d, i, *P_out, *z_out);
  } else {  // the parent's acceleration is already known: f = P+ alpha+ + z+
    const Vec6<S> f = *P_out * parent_acceleration(m, d, i, world_acc) + *z_out;
    push_force_to_parent(m, d, i, f);
  }
  return -1;
}

// Base-to-tip step of a body that needs an articulated inertia (seed Eq. 29).
template <bool Flex, class S>
inline void articulated_body_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                     const Vec6<S>& world_acc, bool want_force) {
  const HingeModes& h = m.modes[i];
  const int vi = m.v_index[i], ni = m.nv_body[i];
  const Vec6<S> alpha_plus = body_parent_acceleration<Flex>(m, d, i, world_acc, d.qdd.data());
  auto qdd = d.qdd.segment(vi, ni);
  auto tau = d.tau.segment(vi, ni);
  if (h.n_prescribed == 0) {  // the articulated-body case: no gather, no scatter
    for (int k = 0; k < ni; ++k) qdd[k] = d.innovation[i][k] - d.gain[i].col(k).dot(alpha_plus);
    tau = Eigen::Map<const VecN<S>>(u + vi, ni);
  } else if (h.n_regular > 0) {  // qdd_r = nu - G* alpha+
    const VecN<S> qdd_r = d.innovation[i] - d.gain[i].transpose() * alpha_plus;
    for (int k = 0; k < h.n_regular; ++k) {
      qdd[h.regular[k]] = qdd_r[k];
      tau[h.regular[k]] = u[vi + h.regular[k]];
    }
  }
  for (int k = 0; k < h.n_prescribed; ++k) qdd[h.prescribed[k]] = u[vi + h.prescribed[k]];
  // alpha = alpha+ + H* qdd + a
  d.acceleration[i] = alpha_plus + d.coriolis[i];
  if (ni > 0) d.acceleration[i] += subspace_times(d.subspace[i], qdd);
  if (h.n_prescribed > 0 || want_force) {  // f = P alpha + z, T_p = H f
    d.hinge_force[i] = d.articulated_inertia[i] * d.acceleration[i] + d.articulated_bias[i];
    for (int k = 0; k < h.n_prescribed; ++k)
      tau[h.prescribed[k]] = d.subspace[i].col(h.prescribed[k]).dot(d.hinge_force[i]);
  }
  if constexpr (Flex)
    if (m.is_flexible(static_cast<int>(i))) modal_accelerations(m, d, i, u);
}

}  // namespace detail

namespace detail {

// The three sweeps; `v` null means zero velocity.
template <bool Flex, class S>
Status hybrid_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const ConstVecRef<S>& u,
                     const S* f_ext, const Vec6<S>& world_acc, HybridOutputs outputs) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const S* up = u.data();
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, b; accelerations of all-prescribed regions
    body_joint_step<Flex>(m, d, i, q, v);
    body_motion_step<Flex>(m, d, i, q, v, f_ext);
    if (m.modes[i].needs_articulated_inertia) {
      init_articulated<Flex>(m, d, i);
    } else {  // neither flexible nor on a flexible body (those need P)
      d.acceleration[i] = parent_acceleration(m, d, i, world_acc) + d.coriolis[i];
      d.acceleration[i] += subspace_times(d.subspace[i], up + m.v_index[i]);
      d.hinge_force[i] = m.inertia[i] * d.acceleration[i] + d.bias_force[i];
    }
  }
  for (std::size_t i = n; i-- > 0;) {  // tip to base
    if (m.modes[i].needs_articulated_inertia) {
      const int bad = articulated_body_inward<Flex>(m, d, i, up, world_acc);
      if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, bad};
    } else {  // Newton-Euler: T = H f, f(parent) += phi f
      const int vi = m.v_index[i], ni = m.nv_body[i];
      d.qdd.segment(vi, ni) = u.segment(vi, ni);
      subspace_transpose_times(d.subspace[i], d.hinge_force[i], d.tau.segment(vi, ni));
      push_force_to_parent(m, d, i, d.hinge_force[i]);
    }
  }
  for (std::size_t i = 0; i < n; ++i)  // base to tip
    if (m.modes[i].needs_articulated_inertia)
      articulated_body_outward<Flex>(m, d, i, up, world_acc, outputs.hinge_forces);
  const Status s = check_finite(d.qdd);
  return s.ok() ? check_finite(d.tau) : s;
}

}  // namespace detail

template <class S>
Status hybrid_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const ConstVecRef<S>& u, const S* f_ext, HybridOutputs outputs) {
  if (m.n_prescribed == 0 && !outputs.hinge_forces) {  // a regular tree: exactly the articulated-body sweeps
    const Status s = forward_dynamics(m, d, q, v, u, f_ext);
    d.tau = u;
    return s;
  }
  if (m.has_flexible_bodies())
    return detail::hybrid_sweeps<true>(m, d, q.data(), v.data(), u, f_ext, world_acceleration(m), outputs);
  return detail::hybrid_sweeps<false>(m, d, q.data(), v.data(), u, f_ext, world_acceleration(m), outputs);
}

template <class S>
Status hybrid_impulse(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& u) {
  if (m.has_flexible_bodies())
    return detail::hybrid_sweeps<true, S>(m, d, q.data(), nullptr, u, nullptr, Vec6<S>::Zero(), HybridOutputs{});
  return detail::hybrid_sweeps<false, S>(m, d, q.data(), nullptr, u, nullptr, Vec6<S>::Zero(), HybridOutputs{});
}


}  // namespace soadyn
