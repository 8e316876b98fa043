#pragma once
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/analysis/loop_force_stiffness.hpp"

namespace soadyn {

namespace detail {

// DOF column c of body j as a world Plucker axis about the world origin:
// [omega; c], the velocity of the point at the origin being c.
template <class S>
Vec6<S> world_dof_axis(const DataTpl<S>& d, std::size_t j, Eigen::Index c) {
  const Transform<S>& X = d.pose_in_world[j];
  const Mat6N<S>& H = d.sweep.body_subspace[j];
  const Vec3<S> omega = X.rotation * H.col(c).template head<3>();
  Vec6<S> axis;
  axis << omega, X.rotation * H.col(c).template tail<3>() + X.translation.cross(omega);
  return axis;
}

// Velocity of the world point p per unit rate of a DOF with world axis psi.
template <class S>
Vec3<S> point_rate(const Vec6<S>& psi, const Vec3<S>& p) {
  return psi.template tail<3>() + psi.template head<3>().cross(p);
}

// Does DOF (k_body, k_col) turn the axis of DOF (j_body, j_col)? Every DOF
// of an ancestor does; within a joint every DOF does, except a universal
// joint's second angle, which leaves the first axis in place.
template <class S>
bool turns_axis(const ModelTpl<S>& m, std::size_t k_body, Eigen::Index k_col, std::size_t j_body, Eigen::Index j_col) {
  if (k_body != j_body) return true;  // the caller walks only k inboard of j
  return !(joint_axes_coupled(m.joint_fast_path[j_body]) && j_col == 0 && k_col == 1);
}

// One side of a loop: sign * J_body(p)' w with w_O = [tau + p x f; f], the
// point p carried by body `carrier`. Adds its derivative to out.
template <class S>
void add_side_stiffness(const ModelTpl<S>& m, const DataTpl<S>& d, int body, int carrier, const Vec3<S>& p,
                        const Vec6<S>& w, S sign, Eigen::Ref<MatX<S>> out) {
  const Vec3<S> f = w.template tail<3>();
  Vec6<S> w_origin;
  w_origin << w.template head<3>() + p.cross(f), f;
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t js = static_cast<std::size_t>(j);
    for (Eigen::Index cj = 0; cj < m.nv_body[js]; ++cj) {
      const Vec6<S> psi_j = world_dof_axis(d, js, cj);
      const Eigen::Index vj = m.v_index[js] + cj;
      // The axis psi_j turns with the DOFs inboard of it.
      for (int k = j; k >= 0; k = m.parent[static_cast<std::size_t>(k)]) {
        const std::size_t ks = static_cast<std::size_t>(k);
        for (Eigen::Index ck = 0; ck < m.nv_body[ks]; ++ck)
          if (turns_axis(m, ks, ck, js, cj))
            out(vj, m.v_index[ks] + ck) += sign * motion_cross(world_dof_axis(d, ks, ck), psi_j).dot(w_origin);
      }
      // The point of application moves with its carrier.
      const Vec3<S> omega_j = psi_j.template head<3>();
      for (int k = carrier; k >= 0; k = m.parent[static_cast<std::size_t>(k)]) {
        const std::size_t ks = static_cast<std::size_t>(k);
        for (Eigen::Index ck = 0; ck < m.nv_body[ks]; ++ck)
          out(vj, m.v_index[ks] + ck) += sign * omega_j.dot(point_rate(world_dof_axis(d, ks, ck), p).cross(f));
      }
    }
  }
}

// out.col(k) += J_rel' dw for every DOF k on `body`'s root path, with dw the
// change of W nu per unit q_k: `turning` (a world vector fixed in the body)
// turns, placed in the angular (angular = true) or linear half.
template <class S>
void add_turning_direction(const ModelTpl<S>& m, const DataTpl<S>& d, int body, const Vec3<S>& turning, bool angular,
                           Eigen::Ref<MatX<S>> out) {
  for (int k = body; k >= 0; k = m.parent[static_cast<std::size_t>(k)]) {
    const std::size_t ks = static_cast<std::size_t>(k);
    for (Eigen::Index ck = 0; ck < m.nv_body[ks]; ++ck) {
      const Vec3<S> change = world_dof_axis(d, ks, ck).template head<3>().cross(turning);
      const Mat6X<S>& J = d.loops.relative_jacobian;
      out.col(m.v_index[ks] + ck).noalias() +=
          (angular ? J.template topRows<3>() : J.template bottomRows<3>()).transpose() * change;
    }
  }
}

// A distance loop's direction n = d/|d|: dn = (I - n n') dd / |d| with dd the
// change of p_A (sign +1, body A) or of p_B (sign -1, body B); dw = [0; dn nu].
template <class S>
void add_distance_direction(const ModelTpl<S>& m, const DataTpl<S>& d, int body, const Vec3<S>& p, const Vec3<S>& n,
                            S length, S nu, S sign, Eigen::Ref<MatX<S>> out) {
  for (int k = body; k >= 0; k = m.parent[static_cast<std::size_t>(k)]) {
    const std::size_t ks = static_cast<std::size_t>(k);
    for (Eigen::Index ck = 0; ck < m.nv_body[ks]; ++ck) {
      const Vec3<S> dd = sign * point_rate(world_dof_axis(d, ks, ck), p);
      const Vec3<S> dn = (dd - n * n.dot(dd)) / length;
      out.col(m.v_index[ks] + ck).noalias() += d.loops.relative_jacobian.template bottomRows<3>().transpose() * (nu * dn);
    }
  }
}

template <class S>
void add_loop_stiffness(const ModelTpl<S>& m, DataTpl<S>& d, const LoopTpl<S>& loop, const ConstVecRef<S>& nu,
                        Eigen::Ref<MatX<S>> out) {
  const Transform<S> A = loop_frame_in_world(d, loop.body_a, loop.placement_a);
  const Transform<S> B = loop_frame_in_world(d, loop.body_b, loop.placement_b);
  const bool prismatic = loop.kind == LoopKind::prismatic;
  const Vec3<S> P = prismatic ? A.translation : B.translation;
  Mat6<S> W;
  loop_directions<S>(loop, A.translation, B.translation, prismatic ? B.rotation : A.rotation, Vec3<S>(Vec3<S>::Zero()),
                     Vec3<S>(Vec3<S>::Zero()), Vec3<S>(Vec3<S>::Zero()), W, nullptr);
  const int k = loop.rows();
  const Vec6<S> w = W.leftCols(k) * nu;
  add_side_stiffness(m, d, loop.body_a, loop.body_a, A.translation, w, S(1), out);
  add_side_stiffness(m, d, loop.body_b, prismatic ? loop.body_a : loop.body_b, P, w, S(-1), out);
  d.loops.relative_jacobian.setZero();
  add_point_jacobian<BodyFrameLoopKinematics>(m, d, loop.body_a, A.translation, S(1), d.loops.relative_jacobian);
  add_point_jacobian<BodyFrameLoopKinematics>(m, d, loop.body_b, P, S(-1), d.loops.relative_jacobian);
  switch (loop.kind) {
    case LoopKind::revolute:
      add_turning_direction(m, d, loop.body_a, Vec3<S>(A.rotation.col(0) * nu[3] + A.rotation.col(1) * nu[4]), true, out);
      break;
    case LoopKind::prismatic:
      add_turning_direction(m, d, loop.body_b, Vec3<S>(B.rotation.col(0) * nu[3] + B.rotation.col(1) * nu[4]), false, out);
      break;
    case LoopKind::distance: {
      Vec3<S> n;
      const S length = scaled_norm<S>(A.translation - B.translation, &n);
      add_distance_direction(m, d, loop.body_a, A.translation, n, length, nu[0], S(1), out);
      add_distance_direction(m, d, loop.body_b, B.translation, n, length, nu[0], S(-1), out);
      break;
    }
    case LoopKind::point:
    case LoopKind::weld:
      break;  // constant directions
  }
}

}  // namespace detail

template <class S>
Status loop_force_stiffness(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& nu,
                            Eigen::Ref<MatX<S>> out) {
  loop_residual(m, d, q, static_cast<const S*>(nullptr));
  out.setZero();
  for (const LoopTpl<S>& loop : m.loops) detail::add_loop_stiffness(m, d, loop, nu.segment(loop.first_row, loop.rows()), out);
  return detail::check_finite_columns(out);
}

}  // namespace soadyn
