#pragma once
#include "soadyn/algorithms/constrained_dynamics.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/algorithms/kinematics.hpp"
#include "soadyn/algorithms/loop_closure.hxx"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/algorithms/semidefinite_solve.hpp"

namespace soadyn {

namespace detail {

// M with prescribed rows and columns replaced by the identity, and C with the
// prescribed columns zeroed: the regular block of the problem at full size.
template <class S>
void substitute_prescribed(const ModelTpl<S>& m, LoopData<S>& ld, const MatX<S>& M) {
  ld.regular_mass = M;
  ld.constraint_jacobian_regular = ld.jacobian;
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    ld.regular_mass.row(p).setZero();
    ld.regular_mass.col(p).setZero();
    ld.regular_mass(p, p) = S(1);
    ld.constraint_jacobian_regular.col(p).setZero();
  }
}

// Loop wrenches W lambda from the multipliers (loops/loop.hpp), from the
// directions at the current configuration.
template <class S>
void loop_wrenches_from_multipliers(const ModelTpl<S>& m, DataTpl<S>& d) {
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    const Transform<S> A = loop_frame_in_world(d, loop.body_a, loop.placement_a);
    const Transform<S> B = loop_frame_in_world(d, loop.body_b, loop.placement_b);
    const LoopDirections<S> dir = loop_directions<S>(loop, A, B, Vec6<S>::Zero(), Vec3<S>::Zero(), Vec3<S>::Zero());
    d.loops.wrench[l].noalias() = dir.W.leftCols(loop.rows()) * d.loops.multipliers.segment(loop.first_row, loop.rows());
  }
}

template <class S>
Status constrained_solve(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& u) {
  LoopData<S>& ld = d.loops;
  detail::substitute_prescribed(m, ld, d.mass_matrix);
  // Plain-loop Cholesky (small_cholesky.hpp): Eigen's blocked one allocates for nv >= 32.
  const int bad_pivot = cholesky_in_place(ld.regular_mass, S(0));
  if (bad_pivot >= 0) return {StatusCode::singular_articulated_inertia, bad_pivot};
  // b: tau_r - h_r - M_rp qdd_p on regular rows, qdd_p on prescribed rows.
  for (int k = 0; k < m.nv; ++k) d.qdd[k] = m.is_prescribed(k) ? u[k] : S(0);
  ld.free_acceleration.noalias() = d.mass_matrix * d.qdd;  // M_rp qdd_p (a negated product would need a temporary)
  for (int k = 0; k < m.nv; ++k)
    ld.free_acceleration[k] = m.is_prescribed(k) ? u[k] : u[k] - ld.bias[k] - ld.free_acceleration[k];
  cholesky_solve_in_place(ld.regular_mass, ld.free_acceleration);
  ld.inverse_mass_times_ct = ld.constraint_jacobian_regular.transpose();
  cholesky_solve_in_place(ld.regular_mass, ld.inverse_mass_times_ct);
  // lazyProduct: coefficient-wise, without the blocked product's workspace.
  ld.delassus.noalias() = ld.constraint_jacobian_regular.lazyProduct(ld.inverse_mass_times_ct);
  // rhs = kappa - C qdd_free: the free accelerations carry qdd_p on prescribed rows.
  ld.rhs = ld.kappa;
  ld.rhs.noalias() -= ld.jacobian * ld.free_acceleration;
  if (semidefinite_min_norm_solve(ld.delassus, ld.rhs, delassus_threshold<S>(), ld.delassus_solve, ld.multipliers) < 0)
    return {StatusCode::non_finite_result, -1};
  d.qdd = ld.free_acceleration;
  d.qdd.noalias() += ld.inverse_mass_times_ct * ld.multipliers;  // matrix-vector products need no workspace
  // tau = M qdd + h - J' f_ext - C' lambda; regular entries are the given torques.
  d.tau = ld.bias;
  d.tau.noalias() += d.mass_matrix * d.qdd;
  d.tau.noalias() -= ld.jacobian.transpose() * ld.multipliers;
  for (int k = 0; k < m.nv; ++k)
    if (!m.is_prescribed(k)) d.tau[k] = u[k];
  detail::loop_wrenches_from_multipliers(m, d);
  Status status = check_finite(d.qdd);
  if (!status.ok()) return status;
  status = check_finite(d.tau);
  if (!status.ok()) return status;
  if (!ld.multipliers.allFinite()) return {StatusCode::non_finite_result, -1};
  return status;
}

}  // namespace detail

template <class S>
Status constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                            const ConstVecRef<S>& u, const S* f_ext) {
  if (m.nloops() == 0) return hybrid_dynamics(m, d, q, v, u, f_ext);
  const Status status = mass_matrix(m, d, q);
  if (!status.ok()) return status;
  // h - J' f_ext, and the body accelerations of qdd = 0 that kappa needs.
  detail::rnea(m, d, q.data(), v.data(), static_cast<const S*>(nullptr), f_ext);
  d.loops.bias = d.tau;
  update_world_poses(m, d);
  detail::loop_equations(m, d, true);
  return detail::constrained_solve(m, d, u);
}

}  // namespace soadyn
