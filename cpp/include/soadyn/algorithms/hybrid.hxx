#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/flexible_steps.hpp"
#include "soadyn/algorithms/hinge_steps.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/algorithms/tree_frame_sweeps.hxx"

namespace soadyn {

namespace detail {

// Tip-to-base step of a body that needs an articulated inertia (seed Eq. 28),
// body frames: flexible bodies first eliminate their modal DOFs.
template <class S>
inline int articulated_body_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                   const Vec6<S>& world_acc) {
  if (m.is_flexible(static_cast<int>(i))) {
    const int bad = eliminate_modal_coordinates(m, d, i, u);
    if (bad >= 0) return bad;
  }
  Mat6<S> P_plus;
  Vec6<S> z_plus;
  const Mat6<S>* P_out = nullptr;
  const int bad = hinge_inward<false>(m, d, i, u, d.subspace[i], P_plus, z_plus, P_out);
  if (bad >= 0) return bad;
  const int p = m.parent[i];
  if (p < 0) return -1;
  if (m.modes[static_cast<std::size_t>(p)].needs_articulated_inertia) {
    push_articulated<true>(m, d, i, *P_out, z_plus);
  } else {  // the parent's acceleration is already known: f = P+ alpha+ + z+
    const Vec6<S> f = *P_out * parent_acceleration(m, d, i, world_acc) + z_plus;
    push_force_to_parent(m, d, i, f);
  }
  return -1;
}

// Base-to-tip step of a body that needs an articulated inertia (seed Eq. 29), body frames.
template <class S>
inline void articulated_body_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                     const Vec6<S>& world_acc, bool want_force) {
  const Vec6<S> alpha_plus = body_parent_acceleration<true>(m, d, i, world_acc, d.qdd.data());
  hinge_outward<false>(m, d, i, u, alpha_plus, d.subspace[i], want_force);
  if (m.is_flexible(static_cast<int>(i))) modal_accelerations(m, d, i, u);
}

}  // namespace detail

namespace detail {

// The three sweeps in body frames, with the modal DOFs of flexible bodies:
// the path of models with bodies on a flexible body's node (every other model
// runs tree_frame_sweeps). `v` null means zero velocity.
template <class S>
Status hybrid_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const ConstVecRef<S>& u,
                     const S* f_ext, const Vec6<S>& world_acc, DynamicsOutputs outputs) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const S* up = u.data();
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, b; accelerations of all-prescribed regions
    body_joint_step<true>(m, d, i, q, v);
    body_motion_step<true>(m, d, i, q, v, f_ext);
    if (m.modes[i].needs_articulated_inertia) {
      init_articulated<true>(m, d, i);
    } else {  // neither flexible nor on a flexible body (those need P)
      d.acceleration[i] = parent_acceleration(m, d, i, world_acc) + d.coriolis[i];
      d.acceleration[i] += subspace_times(d.subspace[i], up + m.v_index[i]);
      d.hinge_force[i] = m.inertia[i] * d.acceleration[i] + d.bias_force[i];
    }
  }
  for (std::size_t i = n; i-- > 0;) {  // tip to base
    if (m.modes[i].needs_articulated_inertia) {
      const int bad = articulated_body_inward(m, d, i, up, world_acc);
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
      articulated_body_outward(m, d, i, up, world_acc, outputs.hinge_forces);
  const Status s = check_finite(d.qdd);
  return s.ok() ? check_prescribed_finite(m, d.tau) : s;
}

// The tree-frame sweeps under the model's flags; a model whose every body has
// an articulated inertia (a regular hinge at each root) runs the variant
// without the Newton-Euler branches.
template <bool Flex, class S>
Status flagged_tree_frame_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u,
                                 const S* f_ext, const Vec6<S>& world_acc, bool want_force) {
  if (m.has_newton_euler_region)
    return tree_frame_sweeps<ModePolicy::model_flags, Flex>(m, d, q, v, u, f_ext, world_acc, want_force);
  return tree_frame_sweeps<ModePolicy::model_flags_articulated, Flex>(m, d, q, v, u, f_ext, world_acc, want_force);
}

}  // namespace detail

template <class S>
Status hybrid_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const ConstVecRef<S>& u, const S* f_ext, DynamicsOutputs outputs) {
  if (m.n_prescribed == 0 && !outputs.hinge_forces) {  // a regular tree: exactly the articulated-body sweeps
    const Status s = forward_dynamics(m, d, q, v, u, f_ext);
    d.tau = u;
    return s;
  }
  if (m.n_prescribed == m.nv) {  // every DOF prescribed (so rigid: modal DOFs are regular): exactly RNEA
    detail::newton_euler_sweeps<false>(m, d, q.data(), velocities_unless_at_rest(m, v), u.data(), f_ext,
                                       world_acceleration(m));
    d.qdd = u;
    return check_finite(d.tau);
  }
  if (!m.has_node_attachments()) {
    const Status s =
        m.has_flexible_bodies()
            ? detail::flagged_tree_frame_sweeps<true>(m, d, q.data(), v.data(), u.data(), f_ext, world_acceleration(m),
                                                      outputs.hinge_forces)
            : detail::flagged_tree_frame_sweeps<false>(m, d, q.data(), velocities_unless_at_rest(m, v), u.data(),
                                                       f_ext, world_acceleration(m), outputs.hinge_forces);
    if (s.code != StatusCode::beyond_tree_frame_reach) return s;
  }
  return detail::hybrid_sweeps(m, d, q.data(), v.data(), u, f_ext, world_acceleration(m), outputs);
}

template <class S>
Status hybrid_impulse(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& u) {
  const Vec6<S> no_gravity = Vec6<S>::Zero();
  if (!m.has_node_attachments()) {
    const Status s =
        m.has_flexible_bodies()
            ? detail::flagged_tree_frame_sweeps<true, S>(m, d, q.data(), nullptr, u.data(), nullptr, no_gravity, false)
            : detail::flagged_tree_frame_sweeps<false, S>(m, d, q.data(), nullptr, u.data(), nullptr, no_gravity, false);
    if (s.code != StatusCode::beyond_tree_frame_reach) return s;
  }
  return detail::hybrid_sweeps<S>(m, d, q.data(), nullptr, u, nullptr, no_gravity, DynamicsOutputs{});
}


}  // namespace soadyn
