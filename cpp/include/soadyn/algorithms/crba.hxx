#pragma once
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/algorithms/tree_frame_steps.hpp"

namespace soadyn {

namespace detail {

// Composite-rigid-body algorithm (rigid models) in tree frames
// (tree_frame_steps.hpp): composite inertias add without a congruence, and
// a column block F = Ic(i) H*(i) needs no transform on its way to the root,
// M(j, i) = H(j) F for every ancestor j.
// Returns false, having formed no M, when a body lies beyond its tree-frame
// reach (tree_frame_reach.hxx).
template <class S>
bool composite_rigid_body(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  for (std::size_t i = 0; i < n; ++i) {
    tree_joint_step(m, d, i, q.data(), static_cast<const S*>(nullptr));
    if (beyond_tree_frame_reach(m, d, i)) return false;
    spatial_inertia_in_frame(d.sweep.tree_pose[i], m.mass[i], m.com[i], m.inertia_com[i],
                             d.sweep.tree_articulated_inertia[i]);
  }
  for (std::size_t i = n; i-- > 0;) {  // M(j, i) = M(i, j) for j = i and every ancestor (v_index[j] <= v_index[i])
    const int p = m.parent[i];
    const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
    for (Eigen::Index b = 0; b < ni; ++b) {
      // force of a unit hinge acceleration
      const Vec6<S> F = d.sweep.tree_articulated_inertia[i] * d.sweep.tree_subspace[i].col(b);
      for (std::size_t j = i;;) {
        const Eigen::Index vj = m.v_index[j], nj = j == i ? b + 1 : m.nv_body[j];
        for (Eigen::Index a = 0; a < nj; ++a)  // both triangles here: no transposed copy afterwards
          d.mass_matrix(vi + b, vj + a) = d.mass_matrix(vj + a, vi + b) = d.sweep.tree_subspace[j].col(a).dot(F);
        if (m.parent[j] < 0) break;
        j = static_cast<std::size_t>(m.parent[j]);
      }
    }
    if (p >= 0)
      d.sweep.tree_articulated_inertia[static_cast<std::size_t>(p)] += d.sweep.tree_articulated_inertia[i];
  }
  if (m.has_armature) d.mass_matrix.diagonal() += Eigen::Map<const VecX<S>>(m.armature.data(), m.nv);
  return true;
}

// Models with flexible bodies: column k of M is the generalized force of a
// unit acceleration of DOF k at rest without gravity (Newton-Euler with
// zero velocity, hence without elastic forces). O(nv N).
template <class S>
void mass_matrix_by_columns(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  d.sweep.unit_acceleration.setZero();
  for (Eigen::Index k = 0; k < m.nv; ++k) {
    d.sweep.unit_acceleration[k] = S(1);
    newton_euler_sweeps<true>(m, d, q.data(), static_cast<const S*>(nullptr), d.sweep.unit_acceleration.data(),
                              static_cast<const S*>(nullptr), Vec6<S>(Vec6<S>::Zero()));
    d.sweep.unit_acceleration[k] = S(0);
    d.mass_matrix.col(k) = d.tau;
  }
  for (Eigen::Index r = 0; r < m.nv; ++r)  // symmetric to rounding; make it exactly so
    for (Eigen::Index c = r + 1; c < m.nv; ++c)
      d.mass_matrix(r, c) = d.mass_matrix(c, r) = S(0.5) * (d.mass_matrix(r, c) + d.mass_matrix(c, r));
}

}  // namespace detail

template <class S>
Status mass_matrix(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  // Models with flexible bodies, or with a body beyond its tree-frame reach: by columns, in body frames.
  if (m.has_flexible_bodies() || !detail::composite_rigid_body(m, d, q)) detail::mass_matrix_by_columns(m, d, q);
  for (Eigen::Index c = 0; c < m.nv; ++c)
    if (!d.mass_matrix.col(c).allFinite()) return Status{StatusCode::non_finite_result, static_cast<int>(c)};
  return Status{};
}

}  // namespace soadyn
