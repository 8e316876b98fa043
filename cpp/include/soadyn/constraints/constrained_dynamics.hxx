#pragma once
#include <algorithm>
#include "soadyn/constraints/constrained_dynamics.hpp"
#include "soadyn/constraints/articulated_loop_response.hxx"
#include "soadyn/sweeps/dynamics_path.hxx"
#include "soadyn/algorithms/crba.hxx"
#include "soadyn/algorithms/hybrid.hxx"
#include "soadyn/algorithms/kinematics.hpp"
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/linalg/semidefinite_solve.hpp"
#include "soadyn/linalg/tree_cholesky.hpp"

namespace soadyn {

namespace detail {

// M with prescribed rows and columns replaced by the identity, and C_r' (C
// with the prescribed columns and its rounding noise zeroed, transposed) in
// half_solved_ct: the regular block of the problem at full size.
template <class S>
void substitute_prescribed(const ModelTpl<S>& m, LoopData<S>& ld, const MatX<S>& M) {
  ld.regular_mass = M;
  detail::replace_prescribed_by_identity(m, ld.regular_mass);
  restrict_jacobian_columns_transposed(
      ld.jacobian, [&](Eigen::Index k) { return !m.is_prescribed(static_cast<int>(k)); }, ld.half_solved_ct);
}

// Loop wrenches W lambda from the multipliers (model/loop.hpp), with the
// directions the loop equations left at the current configuration.
template <class S>
void loop_wrenches_from_multipliers(const ModelTpl<S>& m, DataTpl<S>& d) {
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    d.loops.wrench[l].noalias() =
        d.loops.directions[l].leftCols(loop.rows()) * d.loops.multipliers.segment(loop.first_row, loop.rows());
  }
}

// N, a basis of null(K) (m x (m - rank), in ld.null_basis) from the pivoted
// Cholesky factor P K P' = L L' left by the multipliers' solve: with L's
// first `rank` rows L1 (lower triangular) and the rest L2, the permuted
// null vectors are [-L1^-T L2'; I]. Returns m - rank.
template <class S>
int delassus_null_basis(LoopData<S>& ld) {
  const SemidefiniteSolveScratch<S>& s = ld.delassus_solve;
  const MatX<S>& L = s.factor;
  const Eigen::Index m = L.rows(), k = s.rank, r = m - k;
  for (Eigen::Index j = 0; j < r; ++j) {
    for (Eigen::Index i = k; i-- > 0;) {  // back substitution with L1'
      S x = -L(k + j, i);
      for (Eigen::Index l = i + 1; l < k; ++l) x -= L(l, i) * ld.null_work[l];
      ld.null_work[i] = x / L(i, i);
    }
    for (Eigen::Index i = 0; i < m; ++i)
      ld.null_basis(s.permutation[static_cast<std::size_t>(i)], j) = i < k ? ld.null_work[i] : S(i == k + j ? 1 : 0);
  }
  return static_cast<int>(r);
}

// Redundant actuation: given d.tau's prescribed entries (M qdd + h - J' f_ext - C' lambda0)_p,
// moves lambda along null(K) (which leaves qdd unchanged) to the minimum
// ||tau_p||: lambda = lambda0 + N z, z = B^+ tau0 with B = C_p' N.
template <class S>
void minimum_norm_actuation(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  if (m.n_prescribed == 0) return;
  const int r = delassus_null_basis(ld);
  if (r == 0) return;
  const auto N = ld.null_basis.leftCols(r);
  auto B = ld.actuation_map.leftCols(r);
  B.noalias() = ld.jacobian.transpose().lazyProduct(N);
  for (int k = 0; k < m.nv; ++k)
    if (!m.is_prescribed(k)) B.row(k).setZero();  // C_r' N = 0 up to rounding
  ld.actuation_gram.setZero();  // B'B in the top-left corner: the padding's zero pivots are never taken
  ld.actuation_gram.topLeftCorner(r, r).noalias() = B.transpose().lazyProduct(B);
  // How accurate B is: N carries the Delassus factor's error, eps times its
  // condition (largest over smallest kept pivot squared), so B's columns are
  // known to about 10 eps cond |C| |N_j|. Directions of B below that noise
  // level are dropped; all of B when it is noise (the prescribed DOFs are
  // independent coordinates). Thresholds on B'B are the squares.
  const MatX<S>& K_factor = ld.delassus_solve.factor;
  const Eigen::Index kept = ld.delassus_solve.rank;
  const S condition = kept == 0 ? S(1)
                                : S((K_factor(0, 0) * K_factor(0, 0)) / (K_factor(kept - 1, kept - 1) * K_factor(kept - 1, kept - 1)));
  S largest_null = S(0);
  for (int j = 0; j < r; ++j) largest_null = std::max(largest_null, N.col(j).squaredNorm());
  const S noise = S(10) * Eigen::NumTraits<S>::epsilon() * condition;
  const S reference = noise * noise * ld.jacobian.squaredNorm() * largest_null;
  const S largest = ld.actuation_gram.diagonal().maxCoeff();
  if (!(largest > reference)) return;
  // Pivots of B'B resolve singular values of B down to sqrt(eps) of the largest.
  const S relative = std::max<S>(reference / largest, S(10) * Eigen::NumTraits<S>::epsilon());
  ld.actuation_rhs.setZero();
  ld.actuation_rhs.head(r).noalias() = B.transpose().lazyProduct(d.tau);
  if (semidefinite_min_norm_solve(ld.actuation_gram, ld.actuation_rhs, relative, ld.actuation_solve,
                                  ld.actuation_step) < 0)
    return;  // the unchanged lambda0 is still a consistent answer
  ld.multipliers.noalias() += N.lazyProduct(ld.actuation_step.head(r));
  d.tau.noalias() -= B.lazyProduct(ld.actuation_step.head(r));
}

// The loop whose closure acceleration C qdd = kappa is furthest off, relative
// to the size of the equation's terms (below) plus loop_consistency_threshold
// times (the largest such size + 1): equations that vanish identically, as the
// out-of-plane rows of a planar mechanism, are judged against the others,
// and a mechanism at rest with no load against a floor of
// loop_consistency_threshold^2 (2.2e-13 in double, in the equations' SI
// units), below which a closure acceleration is drift. -1 when every
// equation is met.
template <class S>
int inconsistent_loop(const ModelTpl<S>& m, DataTpl<S>& d) {
  using std::abs;
  LoopData<S>& ld = d.loops;
  const S tol = loop_consistency_threshold<S>();
  // The size of the terms of closure equation i: |kappa_i| + |C_i| (|qdd| +
  // |qdd_free|), qdd_free the accelerations without loop forces (a locked
  // mechanism has qdd = 0, its equations balance the loop forces' share).
  // Flat loops over C (column-major, m x nv): a few entries per column.
  const Eigen::Index rows = m.nloop_equations;
  const S* const C = ld.jacobian.data();
  S* const scale = ld.equation_scale.data();
  S* const residual = ld.closure_acceleration_error.data();
  for (Eigen::Index i = 0; i < rows; ++i) {
    scale[i] = abs(ld.kappa[i]);
    residual[i] = S(0);  // C_i qdd - kappa_i
  }
  for (int k = 0; k < m.nv; ++k) {
    const S* const c = C + static_cast<Eigen::Index>(k) * rows;
    const S qdd = d.qdd[k], size = abs(qdd) + abs(ld.free_acceleration[k]);
    for (Eigen::Index i = 0; i < rows; ++i) {
      scale[i] += abs(c[i]) * size;
      residual[i] += c[i] * qdd;
    }
  }
  S largest_scale = S(0);
  for (Eigen::Index i = 0; i < rows; ++i) {
    residual[i] -= ld.kappa[i];
    largest_scale = std::max(largest_scale, scale[i]);
  }
  int worst = -1;
  S worst_ratio = S(1);
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    for (int i = loop.first_row; i < loop.first_row + loop.rows(); ++i) {
      const S ratio = abs(residual[i]) / (tol * (scale[i] + tol * (largest_scale + S(1))));
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = static_cast<int>(l);
      }
    }
  }
  return worst;
}

// The loop wrench w (world axes, [torque; force] about world point p) acting
// on `body`, subtracted from the hinge force of the body and of each of its
// ancestors (each in its own frame about its origin): an external wrench on a
// body relieves every hinge between it and the root (inverse dynamics,
// Jain & Rodriguez 1993, Eq. 1).
template <class S>
void relieve_hinges(const ModelTpl<S>& m, DataTpl<S>& d, int body, const Vec3<S>& p, const Vec6<S>& w) {
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const Transform<S>& X = d.pose_in_world[static_cast<std::size_t>(j)];
    Vec6<S> f;
    f.template head<3>() = X.rotation.transpose() * (w.template head<3>() + (p - X.translation).cross(w.template tail<3>()));
    f.template tail<3>() = X.rotation.transpose() * w.template tail<3>();
    d.hinge_force[static_cast<std::size_t>(j)] -= f;
  }
}

// Adds the loop forces to hinge forces inverse dynamics left in `d` (world
// poses current): `wrench(l)` of each loop on frame A's body about A's
// origin, its opposite on frame B's body with the force at the point P whose
// velocity the loop's C compares (B's origin; A's for a prismatic loop).
template <class S, class Wrench>
void add_loop_forces_to_hinges(const ModelTpl<S>& m, DataTpl<S>& d, const Wrench& wrench) {
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    const Transform<S> A = loop_frame_in_world(d, loop.body_a, loop.placement_a);
    const Transform<S> B = loop_frame_in_world(d, loop.body_b, loop.placement_b);
    const Vec6<S> w = wrench(l);
    relieve_hinges(m, d, loop.body_a, A.translation, w);
    relieve_hinges(m, d, loop.body_b, loop.kind == LoopKind::prismatic ? A.translation : B.translation, Vec6<S>(-w));
  }
}

// data.hinge_force at the solved qdd with f_ext and the loop forces; data.tau
// is kept (inverse dynamics rewrites it: saved in free_acceleration, no
// longer needed once qdd is known).
template <class S>
Status constrained_hinge_forces(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                const ConstVecRef<S>& v, const S* f_ext) {
  d.loops.free_acceleration = d.tau;
  rnea(m, d, q.data(), v.data(), d.qdd.data(), f_ext);
  d.tau = d.loops.free_acceleration;
  update_world_poses(m, d);
  add_loop_forces_to_hinges(m, d, [&](std::size_t l) { return d.loops.wrench[l]; });
  for (const Vec6<S>& f : d.hinge_force)
    if (!f.allFinite()) return {StatusCode::non_finite_result, -1};
  return {};
}

// What both solves do once qdd, tau (at lambda0) and the multipliers are
// known: the minimum-norm actuator forces, the loop wrenches, and the checks.
template <class S>
Status finish_constrained_solve(const ModelTpl<S>& m, DataTpl<S>& d) {
  minimum_norm_actuation(m, d);  // B's regular rows are zero: it reads and moves the prescribed entries only
  loop_wrenches_from_multipliers(m, d);
  Status status = detail::check_finite(d.qdd);
  if (!status.ok()) return status;
  status = detail::check_finite(d.tau);
  if (!status.ok()) return status;
  if (!d.loops.multipliers.allFinite()) return {StatusCode::non_finite_result, -1};
  return status;
}

// The Delassus matrix K = A' B (m x m; A, B: nv x m), symmetric: its lower
// triangle, all the solve reads, as dot products of contiguous columns.
template <class S>
void delassus_lower_triangle(const MatX<S>& A, const MatX<S>& B, MatX<S>& K) {
  for (Eigen::Index j = 0; j < K.cols(); ++j)
    for (Eigen::Index i = j; i < K.rows(); ++i) K(i, j) = A.col(i).dot(B.col(j));
}

template <class S>
Status constrained_solve(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& u) {
  LoopData<S>& ld = d.loops;
  detail::substitute_prescribed(m, ld, d.mass_matrix);
  // M_rr = L' L with the tree's sparsity (tree_cholesky.hpp): O(n d^2), plain loops, no allocation.
  const int bad_pivot = tree_ltl_in_place(ld.regular_mass, m.dof_parent, m.dof_run_start);
  if (bad_pivot >= 0) return {StatusCode::singular_articulated_inertia, bad_pivot};
  const MatX<S>& U = ld.regular_mass;  // the factor, U = L' in the upper triangle
  // b: tau_r - h_r - M_rp qdd_p on regular rows, qdd_p on prescribed rows.
  ld.free_acceleration.setZero();  // M_rp qdd_p: the prescribed columns only
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    ld.free_acceleration.noalias() += d.mass_matrix.col(p) * u[p];
  }
  for (int k = 0; k < m.nv; ++k)
    ld.free_acceleration[k] = m.is_prescribed(k) ? u[k] : u[k] - ld.bias[k] - ld.free_acceleration[k];
  tree_ltl_solve_transposed(U, m.dof_parent, m.dof_run_start, ld.free_acceleration);
  tree_ltl_solve(U, m.dof_parent, m.dof_run_start, ld.free_acceleration);
  // Y = L'^-1 C_r', so that C_r M_rr^-1 C_r' = Y' Y (one half-solve per equation).
  tree_ltl_solve_transposed(U, m.dof_parent, m.dof_run_start, ld.half_solved_ct);
  delassus_lower_triangle(ld.half_solved_ct, ld.half_solved_ct, ld.delassus);
  // rhs = kappa - C qdd_free: the free accelerations carry qdd_p on prescribed rows.
  ld.rhs = ld.kappa;
  ld.rhs.noalias() -= ld.jacobian * ld.free_acceleration;
  if (semidefinite_min_norm_solve(ld.delassus, ld.rhs, delassus_threshold<S>(), ld.delassus_solve, ld.multipliers) < 0)
    return {StatusCode::non_finite_result, -1};
  // qdd = qdd_free + M_rr^-1 C_r' lambda = qdd_free + L^-1 (Y lambda).
  d.qdd.noalias() = ld.half_solved_ct * ld.multipliers;  // matrix-vector products need no workspace
  tree_ltl_solve(U, m.dof_parent, m.dof_run_start, d.qdd);
  d.qdd += ld.free_acceleration;
  // tau: the given torques on regular rows; (M qdd + h - J' f_ext - C' lambda)_p on prescribed ones.
  d.tau = u;
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    d.tau[p] = ld.bias[p] + d.mass_matrix.row(p).dot(d.qdd) - ld.jacobian.col(p).dot(ld.multipliers);
  }
  return finish_constrained_solve(m, d);
}

// constrained_dynamics through the mass matrix: M (CRBA) and h - J' f_ext
// (inverse dynamics at qdd = 0, which leaves the body accelerations kappa
// needs), then constrained_solve. Any dynamics path.
template <class S>
Status mass_matrix_constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                        const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  const Status inertia = mass_matrix(m, d, q);
  if (!inertia.ok()) return inertia;
  detail::rnea(m, d, q.data(), v.data(), static_cast<const S*>(nullptr), f_ext);
  d.loops.bias = d.tau;
  update_world_poses(m, d);
  detail::loop_equations(m, d, LoopTerms::acceleration);
  return detail::constrained_solve(m, d, u);
}

// The same for a rigid model whose loops go through the mass matrix
// (ModelTpl::loops_through_mass_matrix()), in tree frames: M and h - J' f_ext
// from one pair of sweeps sharing the kinematics
// (tree_frame_mass_matrix_and_bias), the loop equations read from the
// tree-frame kinematics those sweeps leave. Returns TreeFrameStatus::beyond,
// having changed no output, when a body lies too far from its tree origin
// for tree frames.
template <class S>
TreeFrameStatus tree_frame_mass_matrix_constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                                   const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  const TreeFrameStatus inertia = tree_frame_mass_matrix_and_bias(m, d, q.data(), detail::velocities_unless_at_rest(m, v), f_ext);
  if (!inertia.ok()) return inertia;
  d.loops.bias = d.tau;
  set_world_poses_from_tree_frames(m, d, q.data());
  loop_equations_from<TreeFrameLoopKinematics>(m, d, LoopTerms::acceleration);
  return detail::constrained_solve(m, d, u);
}

// constrained_dynamics through the articulated-body factorisation of the
// tree-frame hybrid sweeps (rigid models): the inward sweeps give the
// factors, the outward steps on the loop bodies' root paths their
// accelerations without loop forces (qdd_free there); the loop equations,
// read at qdd_free, give rhs = kappa - C qdd_free; unit_multiplier_response
// (articulated_loop_response.hxx) gives Y = M_rr^-1 C_r' on those paths; K = C_r Y
// (its lower triangle) and K lambda = rhs; the loop forces then enter z and nu of the
// loaded bodies and one outward sweep gives qdd and tau: the same equations
// as constrained_solve at O(N + L m) instead of O(N d^2).
// Returns TreeFrameStatus::beyond, having changed no output, when a body
// lies too far from its tree origin for tree frames.
template <class S>
TreeFrameStatus articulated_constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                        const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  constexpr ModePolicy modes = ModePolicy::model_flags;
  const Vec6<S> world_acc = detail::world_acceleration(m);
  const TreeFrameStatus inward =
      tree_frame_inward_sweeps<modes, false>(m, d, q.data(), detail::velocities_unless_at_rest(m, v), u.data(), f_ext, world_acc);
  if (!inward.ok()) return inward;
  LoopData<S>& ld = d.loops;
  mark_loop_paths(m, ld);
  // qdd_free and alpha on the loop bodies' root paths: what the loop equations read.
  ld.free_acceleration.setZero();
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    if (!ld.on_loop_path[i]) continue;
    tree_outward_update<modes, false>(m, d, i, u.data(), world_acc, false);
    ld.free_acceleration.segment(m.v_index[i], m.nv_body[i]) = d.qdd.segment(m.v_index[i], m.nv_body[i]);
  }
  set_world_poses_from_tree_frames(m, d, q.data());
  loop_equations_from<TreeFrameLoopKinematics>(m, d, LoopTerms::acceleration);  // kappa - C qdd_free, in kappa
  ld.rhs = ld.kappa;
  ld.kappa.noalias() += ld.jacobian * ld.free_acceleration;  // C is zero off the loaded DOFs
  restrict_jacobian_columns_transposed(
      ld.jacobian, [&](Eigen::Index k) { return !m.is_prescribed(static_cast<int>(k)); }, ld.regular_jacobian_transposed);
  unit_multiplier_response(m, d);
  // K = C_r Y (Y's rows off the loaded DOFs are zero).
  delassus_lower_triangle(ld.regular_jacobian_transposed, ld.unit_response.qdd, ld.delassus);
  if (semidefinite_min_norm_solve(ld.delassus, ld.rhs, delassus_threshold<S>(), ld.delassus_solve, ld.multipliers) < 0)
    return {StatusCode::non_finite_result, -1};
  add_loop_forces_to_sweeps(m, d);
  const Status outward = tree_frame_outward_sweep<modes, false>(m, d, u.data(), world_acc, false);
  if (!outward.ok()) return outward;
  return finish_constrained_solve(m, d);
}

// constrained_dynamics of the model without its force elements.
template <class S>
Status rigid_constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                  const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext,
                                  DynamicsOutputs outputs) {
  if (m.nloops() == 0) return rigid_hybrid_dynamics(m, d, q, v, u, f_ext, outputs);
  detail::TreeFrameStatus tree = detail::TreeFrameStatus::beyond(-1);  // body frames unless the model's path is tree frames
  if constexpr (has_speed_paths<S>)
    if (m.dynamics_path == DynamicsPath::rigid_tree_frames)
      tree = m.loops_through_mass_matrix() ? tree_frame_mass_matrix_constrained_dynamics(m, d, q, v, u, f_ext)
                                           : articulated_constrained_dynamics(m, d, q, v, u, f_ext);
  Status status = tree.beyond_reach ? mass_matrix_constrained_dynamics(m, d, q, v, u, f_ext) : tree.status;
  if (!status.ok()) return status;
  // A full-rank Delassus system is solved exactly: only a rank-deficient one
  // can leave closure accelerations unmet.
  const int loop = d.loops.delassus_solve.rank < m.nloop_equations ? detail::inconsistent_loop(m, d) : -1;
  if (loop >= 0) status = {StatusCode::inconsistent_loop_equations, loop};
  if (!outputs.hinge_forces) return status;
  const Status wrenches = detail::constrained_hinge_forces(m, d, q, v, f_ext);  // also of a least-squares answer
  return wrenches.ok() ? status : wrenches;
}

// loop_joint_wrenches of the model without its force elements.
template <class S>
Status rigid_loop_joint_wrenches(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                 const ConstVecRef<S>& v, const ConstVecRef<S>& qdd, const S* loop_wrenches,
                                 const S* f_ext) {
  detail::rnea(m, d, q.data(), v.data(), qdd.data(), f_ext);
  Status status = detail::check_finite(d.tau);
  if (!status.ok()) return status;
  if (m.nloops() == 0) return status;
  update_world_poses(m, d);
  detail::add_loop_forces_to_hinges(m, d, [&](std::size_t l) { return Vec6<S>(Eigen::Map<const Vec6<S>>(loop_wrenches + 6 * l)); });
  for (const Vec6<S>& f : d.hinge_force)
    if (!f.allFinite()) return {StatusCode::non_finite_result, -1};
  return status;
}

}  // namespace detail

template <class S>
Status constrained_dynamics(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                            const ConstVecRef<S>& u, const S* f_ext, DynamicsOutputs outputs) {
  if (!m.has_force_elements()) return detail::rigid_constrained_dynamics(m, d, q, v, u, f_ext, outputs);
  return detail::with_force_elements(m, d, q.data(), v.data(), u.data(), f_ext, detail::SpringInputRows::regular,
                                     [&](const S* input, const S* f) {
                                       return detail::rigid_constrained_dynamics(
                                           m, d, q, v, Eigen::Map<const VecX<S>>(input, m.nv), f, outputs);
                                     });
}

template <class S>
Status loop_joint_wrenches(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                           const ConstVecRef<S>& qdd, const S* loop_wrenches, const S* f_ext) {
  if (!m.has_force_elements()) return detail::rigid_loop_joint_wrenches(m, d, q, v, qdd, loop_wrenches, f_ext);
  return detail::with_force_elements(m, d, q.data(), v.data(), static_cast<const S*>(nullptr), f_ext,
                                     detail::SpringInputRows::none, [&](const S*, const S* f) {
                                       return detail::rigid_loop_joint_wrenches(m, d, q, v, qdd, loop_wrenches, f);
                                     });
}

}  // namespace soadyn
