#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/flexible_steps.hpp"
#include "soadyn/algorithms/tree_frame_sweeps.hxx"

namespace soadyn {

namespace detail {

// The articulated-body sweeps in body frames, with the modal DOFs of
// flexible bodies (flexible_steps.hpp): the path of models with bodies on a
// flexible body's node. Every other model runs tree_frame_sweeps.
template <class S>
Status articulated_body_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v,
                               const ConstVecRef<S>& tau, const S* f_ext) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = world_acceleration(m);
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, b (seed Eq. 1)
    body_joint_step<true>(m, d, i, q, v);
    body_motion_step<true>(m, d, i, q, v, f_ext);
    init_articulated<true>(m, d, i);
  }
  Mat6<S> P_plus;
  Vec6<S> z_plus;
  for (std::size_t i = n; i-- > 0;) {  // tip to base (seed Eqs. 14, 28, all hinges regular)
    if (m.is_flexible(static_cast<int>(i))) {
      const int bad = eliminate_modal_coordinates(m, d, i, tau.data());
      if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, bad};
    }
    const Mat6<S>& P = d.articulated_inertia[i];
    const Vec6<S> z = d.articulated_bias[i] + P * d.coriolis[i];
    if (m.nv_body[i] > 0) {
      VecN<S> eps = tau.segment(m.v_index[i], m.nv_body[i]);
      const int bad = articulated_hinge_step(P, d.subspace[i], z, eps, d.gain[i], d.innovation[i], P_plus, z_plus);
      if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, m.v_index[i] + bad};
    } else {  // a clamped flexible body
      P_plus = P;
      z_plus = z;
    }
    if (m.parent[i] >= 0) push_articulated<true>(m, d, i, P_plus, z_plus);
  }
  for (std::size_t i = 0; i < n; ++i) {  // base to tip (seed Eq. 29)
    const Vec6<S> alpha_plus = body_parent_acceleration<true>(m, d, i, world_acc, d.qdd.data());
    const Eigen::Index ni = m.nv_body[i];
    S* qdd = d.qdd.data() + m.v_index[i];
    for (Eigen::Index k = 0; k < ni; ++k) qdd[k] = d.innovation[i][k] - d.gain[i].col(k).dot(alpha_plus);
    d.acceleration[i] = alpha_plus + d.coriolis[i];
    if (ni > 0) d.acceleration[i] += subspace_times(d.subspace[i], qdd);
    if (m.is_flexible(static_cast<int>(i))) modal_accelerations(m, d, i, tau.data());
  }
  return check_finite(d.qdd);
}

}  // namespace detail

template <class S>
Status forward_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& tau, const S* f_ext) {
  constexpr auto all_regular = detail::ModePolicy::all_regular;
  if (!m.has_node_attachments()) {
    const Status s =
        m.has_flexible_bodies()
            ? detail::tree_frame_sweeps<all_regular, true>(m, d, q.data(), v.data(), tau.data(), f_ext,
                                                           world_acceleration(m), false)
            : detail::tree_frame_sweeps<all_regular, false>(m, d, q.data(), velocities_unless_at_rest(m, v),
                                                            tau.data(), f_ext, world_acceleration(m), false);
    if (s.code != StatusCode::beyond_tree_frame_reach) return s;
  }
  return detail::articulated_body_sweeps(m, d, q.data(), v.data(), tau, f_ext);
}

}  // namespace soadyn
