// The hybrid algorithm's three sweeps in body frames (Jain & Rodriguez 1993,
// Eqs. 1, 14, 28, 29, Lemma 8, the recursion as written), with the modal DOFs
// of flexible bodies and the bodies on their nodes (flexible_updates.hpp). This
// is the path of models with a body on a flexible body's node, and of any
// model in a call where a body lies beyond its tree-frame reach
// (tree_frame_reach.hxx); every other call runs tree_frame_sweeps.hxx
// (dynamics_path.hxx chooses).
#pragma once
#include "soadyn/sweeps/flexible_updates.hpp"
#include "soadyn/sweeps/hinge_updates.hpp"

namespace soadyn {
namespace detail {

// Tip-to-base update of a body with an articulated inertia (Eq. 28), body
// frames: a flexible body first eliminates its modal DOFs. Returns the DOF
// of a singular D or modal block, or -1.
template <ModePolicy Modes, class S>
inline int body_articulated_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                   const Vec6<S>& world_acc) {
  if (m.is_flexible(static_cast<int>(i))) {
    const int bad = eliminate_modal_coordinates(m, d, i, u);
    if (bad >= 0) return bad;
  }
  Mat6<S> P_plus;
  Vec6<S> z_plus;
  const Mat6<S>* P_out = nullptr;
  constexpr bool all_regular = Modes == ModePolicy::all_regular;
  const int bad = hinge_inward<Frames::body, all_regular>(m, d, i, u, P_plus, z_plus, P_out);
  if (bad >= 0) return bad;
  const int p = m.parent[i];
  if (p < 0) return -1;
  if (needs_articulated_inertia<Modes>(m, static_cast<std::size_t>(p))) {
    push_articulated<true>(m, d, i, *P_out, z_plus);
  } else {  // the parent's acceleration is already known: f = P+ alpha+ + z+
    const Vec6<S> f = *P_out * detail::parent_acceleration(m, d, i, world_acc) + z_plus;
    detail::push_force_to_parent(m, d, i, f);
  }
  return -1;
}

// Base-to-tip update of a body with an articulated inertia (Eq. 29), body frames.
template <ModePolicy Modes, class S>
inline void body_articulated_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                     const Vec6<S>& world_acc, bool want_force) {
  const Vec6<S> alpha_plus = body_parent_acceleration<true>(m, d, i, world_acc, d.qdd.data());
  hinge_outward<Frames::body, Modes == ModePolicy::all_regular>(m, d, i, u, alpha_plus, want_force);
  if (m.is_flexible(static_cast<int>(i))) modal_accelerations(m, d, i, u, d.body_acceleration[i]);
}

// The three sweeps. `Modes` (hinge_updates.hpp): model_flags for hybrid
// dynamics and its impulse form, all_regular for forward dynamics. `u` holds
// per DOF the torque of a regular DOF or the acceleration of a prescribed
// one; `v` null means zero velocity; `want_force` also leaves every hinge
// force in data.hinge_force.
template <ModePolicy Modes, class S>
Status body_frame_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u, const S* f_ext,
                         const Vec6<S>& world_acc, bool want_force) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, b (Eq. 1); accelerations of all-prescribed regions
    body_joint_update<true>(m, d, i, q, v);
    body_motion_update<true>(m, d, i, q, v, f_ext);
    if (needs_articulated_inertia<Modes>(m, i)) {
      init_articulated<true>(m, d, i);
    } else {  // neither flexible nor on a flexible body (those need P): Newton-Euler
      Vec6<S>& alpha = d.body_acceleration[i];
      alpha = detail::parent_acceleration(m, d, i, world_acc) + d.sweep.body_coriolis[i];
      alpha += detail::subspace_times(d.sweep.body_subspace[i], u + m.v_index[i]);
      d.hinge_force[i] = m.inertia[i] * alpha + d.sweep.body_bias_force[i];
    }
  }
  for (std::size_t i = n; i-- > 0;) {  // tip to base (Eq. 28)
    if (needs_articulated_inertia<Modes>(m, i)) {
      const int bad = body_articulated_inward<Modes>(m, d, i, u, world_acc);
      if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, bad};
    } else {  // Newton-Euler: T = H f, f(parent) += phi f
      const int vi = m.v_index[i], ni = m.nv_body[i];
      d.qdd.segment(vi, ni) = Eigen::Map<const VecX<S>>(u + vi, ni);
      detail::subspace_transpose_times(d.sweep.body_subspace[i], d.hinge_force[i], d.tau.segment(vi, ni));
      detail::add_armature_torques(m, i, u, d.tau.data());
      detail::push_force_to_parent(m, d, i, d.hinge_force[i]);
    }
  }
  for (std::size_t i = 0; i < n; ++i)  // base to tip (Eq. 29)
    if (needs_articulated_inertia<Modes>(m, i)) body_articulated_outward<Modes>(m, d, i, u, world_acc, want_force);
  const Status s = detail::check_finite(d.qdd);
  if constexpr (Modes == ModePolicy::all_regular) return s;  // tau is the given torque
  return s.ok() ? detail::check_prescribed_finite(m, d.tau) : s;
}

}  // namespace detail
}  // namespace soadyn
