// The response of the hybrid algorithm's articulated-body factorisation to
// the loops' multipliers: Y = M_rr^-1 C_r' (the change of the regular
// accelerations per unit multiplier) and the matching change of the
// prescribed DOFs' forces, without forming M.
//
// A multiplier lambda_c of loop l acts on the tree as the wrench W_c
// (loop_directions) on frame A's body and -W_c on frame B's body: C' e_c is
// their generalized force. The sweeps are linear in the external forces, so
// with the articulated inertias P, gains G and D of the hybrid sweeps already
// in `data` (tree frames, tree_frame_sweeps.hxx), the change they cause obeys
// the same recursions with the velocity, gravity and torque terms removed
// (Jain & Rodriguez 1993, Eqs. 28, 29):
//   inward, on the loop bodies' root paths only:
//     dz = sum of the children's dz+ - (applied wrench),
//     deps = -H_r dz,  dz+ = dz + G deps,
//   outward, over the bodies that move with them:
//     dqdd_r = D^-1 deps - G' dalpha+,  dqdd_p = 0,  dalpha = dalpha+ + H*_r dqdd_r,
//     dT_p = H_p (P dalpha + dz).
// All m multipliers are carried at once, one row each (the blocks are the
// transposes: m x 6 per body, m x n per hinge). The cost is O(N m) with N
// bodies, against O(N d^2) for factoring M on a tree of depth d; the
// Delassus matrix is then K = C_r Y (m x m). This is the operational-space
// inverse inertia of Kreutz-Delgado, Jain & Rodriguez, "Recursive
// formulation of operational space control" (IJRR 11(4), 1992), for the
// loops' cut-joint wrenches, in the hybrid setting.
#pragma once
#include <algorithm>
#include "soadyn/algorithms/loop_closure.hxx"
#include "soadyn/algorithms/small_cholesky.hpp"
#include "soadyn/algorithms/tree_frame_sweeps.hxx"

namespace soadyn {
namespace detail {

enum : std::uint8_t { response_loaded = 1, response_moves = 2 };

// loops.tree_origin (the world position of each body's tree origin: its
// root body's origin) and pose_in_world from the tree-frame poses.
template <class S>
void set_world_poses_from_tree_frames(const ModelTpl<S>& m, DataTpl<S>& d, const S* q) {
  LoopData<S>& ld = d.loops;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int p = m.parent[i];
    if (p >= 0) {
      ld.tree_origin[i] = ld.tree_origin[static_cast<std::size_t>(p)];
    } else {  // a root's tree pose keeps the rotation of placement * joint and drops its translation
      const Transform<S>& X = m.placement[i];
      ld.tree_origin[i] = X.translation;
      if (joint_translates(m.joints[i])) {
        Transform<S> joint_pose;
        Mat6N<S> s;
        Vec6<S> bias;
        joint_init_subspace(m.joints[i], s);
        joint_calc(m.joints[i], q + m.q_index[i], static_cast<const S*>(nullptr), joint_pose, s, bias);
        ld.tree_origin[i] += X.rotation * joint_pose.translation;
      }
    }
    d.pose_in_world[i].rotation = d.sweep.tree_pose[i].rotation;
    d.pose_in_world[i].translation = d.sweep.tree_pose[i].translation + ld.tree_origin[i];
  }
}

// Flags the bodies on a loop body's root path (loaded) and every body that
// moves with them (moves: loaded, or a child of a body that moves), clears
// the loaded bodies' dz rows and applies each multiplier's wrenches there.
template <class S>
void load_loop_wrenches(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  std::fill(ld.response_flags.begin(), ld.response_flags.end(), std::uint8_t(0));
  for (const LoopTpl<S>& loop : m.loops)
    for (const int body : {loop.body_a, loop.body_b})
      if (body >= 0) ld.response_flags[static_cast<std::size_t>(body)] = response_loaded;
  for (std::size_t i = n; i-- > 0;)
    if ((ld.response_flags[i] & response_loaded) && m.parent[i] >= 0)
      ld.response_flags[static_cast<std::size_t>(m.parent[i])] |= response_loaded;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = m.parent[i];
    if ((ld.response_flags[i] & response_loaded) || (p >= 0 && (ld.response_flags[static_cast<std::size_t>(p)] & response_moves)))
      ld.response_flags[i] |= response_moves;
    if (ld.response_flags[i] & response_loaded) ld.z_response.middleCols(6 * static_cast<Eigen::Index>(i), 6).setZero();
  }
  // dz = -(applied wrench), in the body's tree frame: [torque + (point - origin) x force; force].
  const auto apply = [&](int body, const Vec3<S>& point, const Vec6<S>& w, S sign, Eigen::Index row) {
    if (body < 0) return;
    const std::size_t b = static_cast<std::size_t>(body);
    Vec6<S> about_origin;
    about_origin << w.template head<3>() + (point - ld.tree_origin[b]).cross(w.template tail<3>()), w.template tail<3>();
    ld.z_response.template block<1, 6>(row, 6 * static_cast<Eigen::Index>(b)) -= sign * about_origin.transpose();
  };
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    const Transform<S> A = loop_frame_in_world(d, loop.body_a, loop.placement_a);
    const Transform<S> B = loop_frame_in_world(d, loop.body_b, loop.placement_b);
    const Vec3<S> P = loop.kind == LoopKind::prismatic ? A.translation : B.translation;
    for (int k = 0; k < loop.rows(); ++k) {
      const Vec6<S> w = ld.directions[l].col(k);
      apply(loop.body_a, A.translation, w, S(1), loop.first_row + k);
      apply(loop.body_b, P, w, S(-1), loop.first_row + k);
    }
  }
}

// The inward half: deps of each loaded hinge and dz+ into its parent.
template <class S>
void loop_response_inward(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  for (std::size_t i = static_cast<std::size_t>(m.nbodies()); i-- > 0;) {
    if (!(ld.response_flags[i] & response_loaded)) continue;
    const auto dz = ld.z_response.middleCols(6 * static_cast<Eigen::Index>(i), 6);
    const HingeModes& h = m.modes[i];
    const int p = m.parent[i];
    const bool gains = h.needs_articulated_inertia && h.n_regular > 0 &&
                       !is_regular_free_root<ModePolicy::model_flags>(m, i);
    if (gains) {
      const Mat6N<S>& Sr = h.n_prescribed > 0 ? d.sweep.tree_regular_subspace[i] : d.sweep.tree_subspace[i];
      auto deps = ld.innovation_response.middleCols(m.v_index[i], h.n_regular);
      deps.noalias() = -dz.lazyProduct(Sr);  // eps = T - H z with T unchanged
    }
    if (p < 0) continue;
    auto dz_parent = ld.z_response.middleCols(6 * static_cast<Eigen::Index>(p), 6);
    dz_parent += dz;  // z+ = z for a hinge without regular DOFs, and in a Newton-Euler region
    if (gains)
      dz_parent.noalias() +=
          ld.innovation_response.middleCols(m.v_index[i], h.n_regular).lazyProduct(d.sweep.tree_gain[i].transpose());
  }
}

// D^-1 deps of regular hinge i into hinge_response's first n_regular columns,
// D = H_r P H_r* + armature (Eq. 28). Returns false for a singular D.
template <class S>
bool solve_hinge_inertia(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i) {
  LoopData<S>& ld = d.loops;
  const HingeModes& h = m.modes[i];
  const int nr = h.n_regular, vi = m.v_index[i];
  const Mat6N<S>& Sr = h.n_prescribed > 0 ? d.sweep.tree_regular_subspace[i] : d.sweep.tree_subspace[i];
  const Mat6<S>& P = d.sweep.tree_articulated_inertia[i];
  const Mat6N<S> PS = P * Sr;
  MatN<S> D = Sr.transpose() * PS;
  if (h.has_armature)
    for (int k = 0; k < nr; ++k) D(k, k) += m.armature[static_cast<std::size_t>(vi + (h.n_prescribed > 0 ? h.regular[k] : k))];
  const auto deps = ld.innovation_response.middleCols(vi, nr);
  if (nr == 1) {
    ld.hinge_response.col(0) = deps.col(0) / D(0, 0);
    return true;
  }
  if (cholesky_in_place(D, singular_pivot_threshold(P)) >= 0) return false;
  auto work = ld.hinge_work.topRows(nr);
  work = deps.transpose();
  cholesky_solve_in_place(D, work);
  ld.hinge_response.leftCols(nr) = work.transpose();
  return true;
}

// The outward half: dqdd (loops.qdd_response), dalpha and the prescribed
// DOFs' dT (loops.tau_response) of every body that moves.
template <class S>
Status loop_response_outward(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int vi = m.v_index[i], ni = m.nv_body[i];
    const std::uint8_t flags = ld.response_flags[i];
    auto dqdd = ld.qdd_response.middleCols(vi, ni);
    if (!(flags & response_moves)) {
      dqdd.setZero();
      continue;
    }
    const HingeModes& h = m.modes[i];
    const bool loaded = flags & response_loaded;
    const int p = m.parent[i];
    const Mat6N<S>& s = d.sweep.tree_subspace[i];
    const Mat6<S>& P = d.sweep.tree_articulated_inertia[i];
    const auto dz = ld.z_response.middleCols(6 * static_cast<Eigen::Index>(i), 6);
    auto dalpha = ld.acceleration_response.middleCols(6 * static_cast<Eigen::Index>(i), 6);
    auto dtau = ld.tau_response.middleCols(vi, ni);
    if (!h.needs_articulated_inertia) {  // accelerations given from the world in: f = dz, T = H f
      dalpha.setZero();
      dqdd.setZero();
      if (loaded)
        dtau.noalias() = dz.lazyProduct(s);
      else
        dtau.setZero();
      continue;
    }
    if (is_regular_free_root<ModePolicy::model_flags>(m, i)) {  // alpha = P^-1 (H^-* T - z) (free_root_inward)
      Mat6<S> L = P;
      if (cholesky_in_place(L, singular_pivot_threshold(P)) >= 0)
        return {StatusCode::singular_articulated_inertia, vi};
      ld.hinge_work = -dz.transpose();
      cholesky_solve_in_place(L, ld.hinge_work);
      dalpha = ld.hinge_work.transpose();
      dqdd.leftCols(3).noalias() = dalpha.leftCols(3).lazyProduct(s.template topLeftCorner<3, 3>());
      dqdd.rightCols(3).noalias() = dalpha.rightCols(3).lazyProduct(s.template bottomRightCorner<3, 3>());
      continue;
    }
    if (p >= 0)
      dalpha = ld.acceleration_response.middleCols(6 * static_cast<Eigen::Index>(p), 6);
    else
      dalpha.setZero();
    if (h.n_regular > 0) {
      const int nr = h.n_regular;
      auto r = ld.hinge_response.leftCols(nr);
      if (loaded) {
        if (!solve_hinge_inertia(m, d, i)) return {StatusCode::singular_articulated_inertia, vi};
      } else {
        r.setZero();
      }
      if (p >= 0) r.noalias() -= dalpha.lazyProduct(d.sweep.tree_gain[i]);  // - G' dalpha+
      const Mat6N<S>& Sr = h.n_prescribed > 0 ? d.sweep.tree_regular_subspace[i] : s;
      dalpha.noalias() += r.lazyProduct(Sr.transpose());
      if (h.n_prescribed == 0) {
        dqdd = r;
        continue;
      }
      for (int k = 0; k < nr; ++k) dqdd.col(h.regular[k]) = r.col(k);
      for (int k = 0; k < h.n_prescribed; ++k) dqdd.col(h.prescribed[k]).setZero();
    } else {
      dqdd.setZero();
    }
    if (h.n_prescribed == 0) continue;
    MatX<S>& df = ld.hinge_response;  // f = P alpha + z (P symmetric)
    df.noalias() = dalpha.lazyProduct(P);
    if (loaded) df += dz;
    for (int k = 0; k < h.n_prescribed; ++k) dtau.col(h.prescribed[k]).noalias() = df * s.col(h.prescribed[k]);
  }
  return {};
}

// loops.qdd_response and loops.tau_response after the tree-frame sweeps of
// hybrid dynamics ran (their P, G and poses in `data`), with pose_in_world,
// loops.tree_origin and loops.directions current.
template <class S>
Status articulated_loop_response(const ModelTpl<S>& m, DataTpl<S>& d) {
  load_loop_wrenches(m, d);
  loop_response_inward(m, d);
  return loop_response_outward(m, d);
}

}  // namespace detail
}  // namespace soadyn
