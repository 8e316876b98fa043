#pragma once
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/linalg/tree_cholesky.hpp"
#include "soadyn/sweeps/tree_frame_updates.hpp"

namespace soadyn {

namespace detail {

// The columns of body i's DOFs in M (both triangles), from its composite
// inertia (ten parameters in tree_composite_inertia[i], its subtree's
// inertias already added) and the subspaces in tree_subspace_columns; their
// entries are added to `probe`, and the composite inertia to the parent's.
// FreeRootFrames: a free root's tree frame is the root's body frame
// (composite_rigid_body), so its H* is the identity: its six rows are F, and
// its own 6x6 block, H*' Ic H*, is its composite inertia, written as it is
// (36 entries where six F's and 21 dot products would compute the same).
template <bool FreeRootFrames, class S>
SOADYN_ALWAYS_INLINE void composite_body_columns(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, S& probe) {
  const Mat6X<S>& H = d.sweep.tree_subspace_columns;
  MatX<S>& M = d.mass_matrix;
  const InertiaParameters<S>& composite = d.sweep.tree_composite_inertia[i];
  // Into the parent's first: the parent's columns, next, then read sums whose
  // stores have long retired (read at once, a sum's 2-vector stores would not
  // forward to the unaligned pairs the products load).
  const int p = m.parent[i];
  if (p >= 0) d.sweep.tree_composite_inertia[static_cast<std::size_t>(p)] += composite;
  if constexpr (FreeRootFrames) {
    if (p < 0 && joint_is_free(m.joint_fast_path[i])) {  // H* = 1: its block of M is its composite inertia
      Mat6<S> block;
      assign_spatial_inertia(composite, block);
      M.template block<6, 6>(m.v_index[i], m.v_index[i]) = block;
      probe += block.sum();
      return;
    }
  }
  for (int k = m.v_index[i]; k < m.v_index[i] + m.nv_body[i]; ++k) {
    const Vec6<S> F = momentum(composite, H.col(k));  // force of a unit acceleration of DOF k
    S* const column_k = &M(0, k);
    S column_sum(0);  // a chain per column, not one through the whole matrix
    for_each_ancestor_run(k, true, m.dof_parent, m.dof_run_start, [&](int first, int last) {
      if (last >= first + 5 && m.dof_parent[static_cast<std::size_t>(first)] < 0) {
        const std::size_t root = static_cast<std::size_t>(m.dof_body[static_cast<std::size_t>(first)]);
        if (joint_is_free(m.joint_fast_path[root])) {
          Vec6<S> rows;
          if constexpr (FreeRootFrames) {
            rows = F;
          } else {  // H* = diag(R, R) (FreeJoint::tree_update): the rows are R' F, two 3x3 products
            const Mat3<S>& R = d.sweep.tree_pose[root].rotation;
            rows.template head<3>().noalias() = R.transpose() * F.template head<3>();
            rows.template tail<3>().noalias() = R.transpose() * F.template tail<3>();
          }
          for (int a = 0; a < 6; ++a) column_k[first + a] = M(k, first + a) = rows[a];
          column_sum += rows.sum();
          first += 6;
        }
      }
      for (int j = first; j <= last; ++j) {
        const S value = H.col(j).dot(F);
        column_k[j] = value;
        M(k, j) = value;  // both triangles here: no transposed copy afterwards
        column_sum += value;
      }
    });
    probe += column_sum;
  }
}

// Body i's subspace into its columns of the side-by-side H
// (tree_subspace_columns): one fixed-size column for a 1-DOF joint.
template <class S>
SOADYN_ALWAYS_INLINE void store_subspace_columns(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i) {
  const Mat6N<S>& s = d.sweep.tree_subspace[i];
  if (m.nv_body[i] == 1)
    d.sweep.tree_subspace_columns.col(m.v_index[i]) = s.col(0);
  else
    d.sweep.tree_subspace_columns.middleCols(m.v_index[i], m.nv_body[i]) = s;
}

// M's armature, and its check: a finite probe (the sum of all entries)
// proves M finite without reading it again.
template <class S>
Status finish_mass_matrix(const ModelTpl<S>& m, DataTpl<S>& d, S probe) {
  MatX<S>& M = d.mass_matrix;
  if (m.has_armature) {
    M.diagonal() += Eigen::Map<const VecX<S>>(m.armature.data(), m.nv);
    probe += M.diagonal().sum();
  }
  using std::isfinite;
  if (!isfinite(scalar_value(probe))) return detail::check_finite_columns(M);  // names the column; a false alarm (the sum overflowed) passes
  return Status{};
}

// Composite-rigid-body algorithm (rigid models) in tree frames
// (tree_frame_updates.hpp): composite inertias add without a congruence, and
// a column block F = Ic(i) H*(i) needs no transform on its way to the root,
// M(j, k) = H*(j)' F for every DOF j on the path from DOF k to the root.
// Those DOFs are walked as runs of consecutive indices (model.dof_run_start),
// and the subspaces of all DOFs lie side by side in one 6 x nv matrix.
// Every entry is added to its column's sum as
// it is written; a finite total of the sums proves M finite without reading
// M again. A root whose joint has a constant subspace in its body frame
// (every robot's: revolute, prismatic, free) lends its tree its body frame:
// M(j, k) = H*(j)' Ic H*(k) is the same in any frame all of a tree's bodies
// share, and in this one the root's pose is the identity and its H* the
// constant body-frame subspace. M then depends on neither the root's joint
// coordinates nor its pose, as it must not (a free joint's velocity is the
// body's twist in its own frame), and a free root's H* is the identity: its
// rows of M are F itself.
// Returns TreeFrameStatus::beyond, having formed no M, when a body lies
// beyond its tree-frame reach (tree_frame_reach.hxx).
template <class S>
SOADYN_FLATTEN TreeFrameStatus composite_rigid_body(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  tabulate_joint_angles(m, d.sweep, q.data());
  for (std::size_t i = 0; i < n; ++i) {
    if (m.parent[i] < 0 && joint_has_constant_body_subspace(m.joint_fast_path[i])) {
      d.sweep.tree_pose[i] = Transform<S>();
      d.sweep.tree_subspace[i] = d.sweep.body_subspace[i];
    } else {  // such a root's frame is its body frame, as in the dynamics sweeps: its children's bases are their placements
      tree_joint_update<true>(m, d, i, q.data(), static_cast<const S*>(nullptr));
    }
    if (beyond_tree_frame_reach(m, d, i)) return TreeFrameStatus::beyond(static_cast<int>(i));
    if (m.derived.constant_tree_inertia[i])  // constant in its root's frame (constant_tree_inertia.hxx)
      d.sweep.tree_composite_inertia[i] = m.derived.tree_inertia_parameters[i];
    else
      inertia_parameters_in_frame(d.sweep.tree_pose[i], m.mass[i], m.com[i], m.inertia_com[i], m.derived.diagonal_inertia_com[i] != 0,
                                  d.sweep.tree_composite_inertia[i]);
    store_subspace_columns(m, d, i);
  }
  S probe(0);
  for (std::size_t i = n; i-- > 0;) composite_body_columns<true>(m, d, i, probe);
  return finish_mass_matrix(m, d, probe);
}

// M and the bias forces h - J' f_ext (inverse dynamics at qdd = 0, in
// d.tau) of a rigid model in one pair of tree-frame sweeps, sharing the
// kinematics: outward, each body's pose, subspace, velocity, inertia
// (tree_rigid_body_update), its acceleration at qdd = 0 (in tree_acceleration,
// the base accelerating at world_acceleration: what the loop equations read
// for kappa) and its force I a + b; inward, the hinge forces H' f (Jain &
// Rodriguez 1993, Eq. 1, all bodies of a tree in one frame: no transforms)
// and the composite-body columns of M. Returns TreeFrameStatus::beyond,
// having formed neither, when a body lies beyond its tree-frame reach.
template <class S>
TreeFrameStatus tree_frame_mass_matrix_and_bias(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* f_ext) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = detail::world_acceleration(m);
  tabulate_joint_angles(m, d.sweep, q);
  for (std::size_t i = 0; i < n; ++i) {
    tree_velocity_update(m, d, i, q, v);
    if (beyond_tree_frame_reach(m, d, i)) return TreeFrameStatus::beyond(static_cast<int>(i));
    InertiaParameters<S>& inertia = d.sweep.tree_composite_inertia[i];  // the body's own, then its subtree's
    tree_rigid_body_update(m, d, i, v, f_ext, inertia);
    const int p = m.parent[i];
    Vec6<S>& a = d.sweep.tree_acceleration[i];
    a = (p >= 0 ? d.sweep.tree_acceleration[static_cast<std::size_t>(p)] : world_acc) + d.sweep.tree_coriolis[i];
    d.sweep.tree_bias_and_children_z[i] += momentum(inertia, a);  // f = I a + b
    store_subspace_columns(m, d, i);
  }
  S probe(0);
  for (std::size_t i = n; i-- > 0;) {
    const Vec6<S>& f = d.sweep.tree_bias_and_children_z[i];  // with the children's added
    d.tau.segment(m.v_index[i], m.nv_body[i]).noalias() = d.sweep.tree_subspace[i].transpose() * f;
    const int p = m.parent[i];
    if (p >= 0) d.sweep.tree_bias_and_children_z[static_cast<std::size_t>(p)] += f;
    composite_body_columns<false>(m, d, i, probe);
  }
  return finish_mass_matrix(m, d, probe);
}

// Models with flexible bodies, and rigid models with a body beyond its
// tree-frame reach: the composite-body algorithm in body frames, with the
// augmented bodies of Jain & Rodriguez (JGCD 15(6), 1992; flexible_updates.hpp).
// A flexible body's composite inertia K = [K_VV K_Ve; K_eV K_ee] over its
// augmented velocity [V; eta_dot] starts from M(eta); a child c's composite
// block K_c,VV (its own modal rates and hinges frozen) enters its parent's K
// as J_c' K_c,VV J_c, J_c = [X(c,p), Psi_c] (push_articulated). The force of a
// unit rate of DOF l of body i is F = K_i u_l, so M(k, l) = u_k' F for the DOFs
// k of i; F's 6-vector part carried up by J' (X* f, and Psi' f into a flexible
// parent's modal rows) gives the rows of every ancestor's DOFs. O(N depth),
// where columns by Newton-Euler cost nv sweeps. Both triangles are written
// with one value: M is exactly symmetric.
template <class S>
void composite_body_frames(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  d.mass_matrix.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    body_joint_update<true>(m, d, i, q.data(), static_cast<const S*>(nullptr));
    d.sweep.body_bias_force[i].setZero();
    if (m.is_flexible(static_cast<int>(i))) {
      flexible_inertia_update(m, d, i, q.data());
      flexible_data(m, d, i).modal_bias.setZero();
    }
    init_articulated<true>(m, d, i);
  }
  const auto set = [&](Eigen::Index row, Eigen::Index col, const S& value) {
    d.mass_matrix(row, col) = d.mass_matrix(col, row) = value;
  };
  for (std::size_t i = n; i-- > 0;) {
    const int body = static_cast<int>(i);
    const bool flexible = m.is_flexible(body);
    const Mat6<S>& P = d.sweep.body_articulated_inertia[i];
    const Mat6N<S>& H = d.sweep.body_subspace[i];
    const Eigen::Index vi = m.v_index[i], nh = m.nv_body[i], nm = flexible ? m.n_modes[i] : 0;
    for (Eigen::Index l = 0; l < nh + nm; ++l) {  // DOFs of body i: its hinge's, then its modes'
      const FlexibleBodyData<S>* fd = flexible ? &flexible_data(m, d, i) : nullptr;
      const Vec6<S> F = l < nh ? Vec6<S>(P * H.col(l)) : Vec6<S>(fd->coupling.col(l - nh));
      for (Eigen::Index k = 0; k <= l; ++k) {
        // k <= l: a modal row k comes with a modal column l
        set(vi + k, vi + l, k < nh ? H.col(k).dot(F) : fd->modal_inertia(k - nh, l - nh));
      }
      Vec6<S> f = F;  // up the ancestors, in the frame of body j
      for (std::size_t j = i; m.parent[j] >= 0;) {
        const std::size_t p = static_cast<std::size_t>(m.parent[j]);
        if (m.attachment_node[j] >= 0) {  // Psi' f: the parent's modal rows
          const Mat6X<S>& psi = d.sweep.attachment_subspace[j];
          const Eigen::Index first = m.modal_v_index(static_cast<int>(p));
          for (Eigen::Index c = 0; c < psi.cols(); ++c) set(first + c, vi + l, psi.col(c).dot(f));
        }
        f = d.pose_in_parent[j].force_to_parent(f);
        const Mat6N<S>& Hp = d.sweep.body_subspace[p];
        for (Eigen::Index a = 0; a < m.nv_body[p]; ++a) set(m.v_index[p] + a, vi + l, Hp.col(a).dot(f));
        j = p;
      }
    }
    if (m.parent[i] >= 0) push_articulated<true>(m, d, i, P, Vec6<S>(Vec6<S>::Zero()));
  }
  if (m.has_armature) d.mass_matrix.diagonal() += Eigen::Map<const VecX<S>>(m.armature.data(), m.nv);
}

// The composite-rigid-body algorithm above as this processor runs it best:
// for double, the kernel crba.cpp chose (mass_matrix_kernel()).
template <class S>
inline TreeFrameStatus rigid_mass_matrix(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  return composite_rigid_body(m, d, q);
}
template <>
TreeFrameStatus rigid_mass_matrix<double>(const ModelTpl<double>& m, DataTpl<double>& d, const ConstVecRef<double>& q);

}  // namespace detail

template <class S>
Status mass_matrix(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  // Models with flexible bodies, or with a body beyond its tree-frame reach: in body frames.
  if constexpr (detail::has_speed_paths<S>) {
    if (!m.has_flexible_bodies()) {
      const detail::TreeFrameStatus status = detail::rigid_mass_matrix(m, d, q);
      if (!status.beyond_reach) return status.status;
    }
  }
  detail::composite_body_frames(m, d, q);
  return detail::check_finite_columns(d.mass_matrix);
}

}  // namespace soadyn
