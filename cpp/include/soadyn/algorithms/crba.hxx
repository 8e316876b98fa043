#pragma once
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/rnea.hxx"

namespace soadyn {

namespace detail {

// Composite-rigid-body algorithm (rigid models).
template <class S>
void composite_rigid_body(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  for (std::size_t i = 0; i < n; ++i) {
    joint_step(m, d, i, q.data(), static_cast<const S*>(nullptr));
    d.articulated_inertia[i] = m.inertia[i];  // composite inertia accumulator
  }
  for (std::size_t i = n; i-- > 0;) {
    const int p = m.parent[i];
    const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
    // Force of unit accelerations of hinge i on the composite body i.
    Mat6N<S> F = d.articulated_inertia[i] * d.subspace[i];
    d.mass_matrix.block(vi, vi, ni, ni).noalias() = d.subspace[i].transpose() * F;
    for (std::size_t j = i; m.parent[j] >= 0;) {  // walk to the root
      d.pose_in_parent[j].forces_to_parent_inplace(F);
      j = static_cast<std::size_t>(m.parent[j]);
      const Eigen::Index vj = m.v_index[j], nj = m.nv_body[j];
      d.mass_matrix.block(vj, vi, nj, ni).noalias() = d.subspace[j].transpose() * F;
      d.mass_matrix.block(vi, vj, ni, nj) = d.mass_matrix.block(vj, vi, nj, ni).transpose();
    }
    if (p >= 0)
      d.articulated_inertia[static_cast<std::size_t>(p)] += d.pose_in_parent[i].inertia_to_parent(d.articulated_inertia[i]);
  }
}

// Models with flexible bodies: column k of M is the generalized force of a
// unit acceleration of DOF k at rest without gravity (Newton-Euler with
// zero velocity, hence without elastic forces). O(nv N).
template <class S>
void mass_matrix_by_columns(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  d.unit_acceleration.setZero();
  for (Eigen::Index k = 0; k < m.nv; ++k) {
    d.unit_acceleration[k] = S(1);
    newton_euler_sweeps<true>(m, d, q.data(), static_cast<const S*>(nullptr), d.unit_acceleration.data(),
                              static_cast<const S*>(nullptr), Vec6<S>(Vec6<S>::Zero()));
    d.unit_acceleration[k] = S(0);
    d.mass_matrix.col(k) = d.tau;
  }
  for (Eigen::Index r = 0; r < m.nv; ++r)  // symmetric to rounding; make it exactly so
    for (Eigen::Index c = r + 1; c < m.nv; ++c)
      d.mass_matrix(r, c) = d.mass_matrix(c, r) = S(0.5) * (d.mass_matrix(r, c) + d.mass_matrix(c, r));
}

}  // namespace detail

template <class S>
void mass_matrix(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  if (m.has_flexible_bodies())
    detail::mass_matrix_by_columns(m, d, q);
  else
    detail::composite_rigid_body(m, d, q);
}

}  // namespace soadyn
