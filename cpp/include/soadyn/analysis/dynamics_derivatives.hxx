#pragma once
#include <algorithm>
#include <utility>
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/linalg/tree_cholesky.hpp"
#include "soadyn/sweeps/tree_frame_updates.hpp"
#include "soadyn/spatial/coriolis_inertia.hpp"

namespace soadyn {

template <class S>
DynamicsDerivativesTpl<S>::DynamicsDerivativesTpl(const ModelTpl<S>& m) {
  if (!m.force_elements.point_springs.empty())
    throw std::invalid_argument("point spring '" + m.force_elements.point_springs.front().name +
                                "': the analytic derivatives of the dynamics take joint springs, not point springs");
  for (int i = 0; i < m.nbodies(); ++i)
    if (m.is_flexible(i))
      throw std::invalid_argument("body '" + m.body_names[static_cast<std::size_t>(i)] +
                                  "' is flexible: the analytic derivatives of the dynamics are computed for rigid "
                                  "bodies only");
  const Eigen::Index nv = m.nv;
  inverse_force.setZero(nv);
  for (MatX<S>* x : {&inverse_dq, &inverse_dv, &dqdd_dq, &dqdd_dv, &dqdd_du, &dtau_dq, &dtau_dv, &dtau_du, &regular_mass})
    x->setZero(nv, nv);
  inverse_factor.setZero(nv, nv);
  subtree_end.resize(static_cast<std::size_t>(nv));
  for (Eigen::Index k = nv; k-- > 0;) {  // DOFs in topological order: a subtree is a contiguous range
    subtree_end[static_cast<std::size_t>(k)] = std::max(subtree_end[static_cast<std::size_t>(k)], static_cast<int>(k));
    const int parent = m.dof_parent[static_cast<std::size_t>(k)];
    if (parent >= 0) subtree_end[static_cast<std::size_t>(parent)] = std::max(subtree_end[static_cast<std::size_t>(parent)], subtree_end[static_cast<std::size_t>(k)]);
  }
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  composite_inertia.resize(n);
  body_inertia.resize(n);
  velocity_force.resize(n);
  composite_coriolis_inertia.resize(n);
  composite_force.resize(n);
  acceleration.resize(n);
  for (Mat6X<S>* x : {&displacement_lever, &displacement_acceleration, &velocity_acceleration, &dof_axis,
                      &inertia_axis, &coriolis_t_axis})
    x->setZero(6, nv);
}

template <class S>
DynamicsDerivativesTpl<S>::DynamicsDerivativesTpl(const ModelTpl<S>& m, OutputsOnly) {
  for (MatX<S>* x : {&inverse_dq, &inverse_dv, &dqdd_dq, &dqdd_dv, &dqdd_du, &dtau_dq, &dtau_dv, &dtau_du})
    x->setZero(m.nv, m.nv);
}

namespace detail {

// Outward steps of the derivative sweeps for rigid body i, in two parts so
// that the derivatives (one_sweep_dynamics_derivatives) can run the kinematics once and the
// accelerations twice (one_sweep_dynamics_derivatives).
//
// derivative_kinematics_update: tree-frame kinematics (tree_frame_updates.hpp),
// the body's own inertia, Coriolis factor and velocity force
// V x* (I V) - f_ext, and the per-DOF terms of DynamicsDerivativesTpl that do
// not depend on qdd. derivative_acceleration_update: alpha(i) = alpha(parent) +
// H* qdd + a(i) (Jain & Rodriguez 1993, Eq. 1), the Newton-Euler force
// f = I alpha + V x* (I V) - f_ext and, with `partials`, y_k (qdd null:
// zero accelerations).
//
// A change e of DOF k's coordinate turns the bodies outboard of it about H_k:
// their axes and forces by H_k x e, their velocities by e H_k x (V - V-), and
// -- since the motion inboard of the hinge stays -- the velocity products
// leave them the rigidly turned acceleration plus e y_k,
// y_k = -H_k x A- + (H_k x V-) x V-, and the turned velocity minus e (H_k x V-).
// V- and A- are the parent body's, or for a universal joint's second axis
// its middle frame's (inboard_motion).
template <class S>
Vec6<S> inboard_velocity(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i, Eigen::Index c, const S* v,
                         const Vec6<S>& parent_velocity) {
  if (c == 1 && joint_axes_coupled(m.joint_fast_path[i]))
    return parent_velocity + Vec6<S>(d.sweep.tree_subspace[i].col(0)) * v[m.v_index[i]];
  return parent_velocity;
}

template <class S>
void derivative_kinematics_update(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, std::size_t i,
                                const S* q, const S* v, const S* f_ext) {
  tree_velocity_update(m, d, i, q, v);
  const int p = m.parent[i];
  const Vec6<S> parent_velocity = p >= 0 ? d.sweep.tree_velocity[static_cast<std::size_t>(p)] : Vec6<S>::Zero();
  const Mat6N<S>& s = d.sweep.tree_subspace[i];
  const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
  const Vec6<S>& velocity = d.sweep.tree_velocity[i];
  Mat6<S>& inertia = w.body_inertia[i];
  spatial_inertia_in_frame(d.sweep.tree_pose[i], m.mass[i], m.com[i], m.inertia_com[i], inertia);
  w.composite_inertia[i] = inertia;
  w.composite_coriolis_inertia[i] = coriolis_inertia(inertia, velocity);
  Vec6<S>& velocity_force = w.velocity_force[i];
  velocity_force = force_cross(velocity, Vec6<S>(inertia * velocity));
  if (f_ext) velocity_force -= d.sweep.tree_pose[i].force_to_parent(Eigen::Map<const Vec6<S>>(f_ext + 6 * i));
  const bool universal = joint_axes_coupled(m.joint_fast_path[i]);
  for (Eigen::Index c = 0; c < ni; ++c) {
    const Vec6<S> axis = s.col(c);
    const Vec6<S> inboard = inboard_velocity(m, d, i, c, v, parent_velocity);
    // Axes constant in the body frame turn with the body (dH/dt = V(i) x H);
    // a universal joint's first axis is fixed in the parent, its second in
    // the body, whose middle frame moves with the first angle only.
    const Vec6<S> turning_velocity = universal ? inboard : velocity;
    w.displacement_lever.col(vi + c) = motion_cross(axis, inboard);
    w.velocity_acceleration.col(vi + c) = motion_cross(Vec6<S>(turning_velocity + inboard), axis);
    w.dof_axis.col(vi + c) = axis;
  }
}

template <class S>
void derivative_acceleration_update(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, std::size_t i,
                                  const S* v, const S* qdd, const Vec6<S>& world_acc, bool partials) {
  const int p = m.parent[i];
  const Vec6<S> parent_velocity = p >= 0 ? d.sweep.tree_velocity[static_cast<std::size_t>(p)] : Vec6<S>::Zero();
  const Vec6<S> parent_acceleration = p >= 0 ? w.acceleration[static_cast<std::size_t>(p)] : world_acc;
  const Mat6N<S>& s = d.sweep.tree_subspace[i];
  const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
  Vec6<S>& acceleration = w.acceleration[i];
  acceleration = parent_acceleration + d.sweep.tree_coriolis[i];
  if (qdd && ni > 0) acceleration += detail::subspace_times(s, qdd + vi);
  w.composite_force[i] = w.body_inertia[i] * acceleration + w.velocity_force[i];
  if (!partials) return;
  for (Eigen::Index c = 0; c < ni; ++c) {
    const Vec6<S> axis = s.col(c);
    const Vec6<S> inboard = inboard_velocity(m, d, i, c, v, parent_velocity);
    Vec6<S> inboard_acceleration = parent_acceleration;
    if (c == 1 && joint_axes_coupled(m.joint_fast_path[i])) {
      const Vec6<S> first_axis = s.col(0);
      inboard_acceleration += motion_cross(parent_velocity, first_axis) * v[vi];
      if (qdd) inboard_acceleration += first_axis * qdd[vi];
    }
    w.displacement_acceleration.col(vi + c) =
        motion_cross(Vec6<S>(w.displacement_lever.col(vi + c)), inboard) - motion_cross(axis, inboard_acceleration);
  }
}

// Inward steps for body i, whose subtree sums are complete. With Ic, Bc, F the
// subtree's inertia, Coriolis factor and force, and for a DOF k of body i
//   f_q(k) = Ic y_k - 2 Bc (H_k x V-),       f_v(k) = 2 Bc H_k + Ic z_k
// the change of the subtree's force per unit change of q_k and of qdot_k
// (2 B W gathers the gyroscopic change and the velocity products, see
// coriolis_inertia.hpp):
//   dtau_j/dq_k = H_j' (f_q(k) + H_k x* F)   j inboard of k (its axis stays),
//   dtau_k'/dq_k = H_k'' f_q(k) and dtau_k'/dqdot_k = H_k'' f_v(k) for DOFs k'
//     of body i, whose axes turn with the body (the universal joint's first
//     axis does not turn with its second angle: it keeps the H_k x* F term);
//   dtau_i/dq_j = (Ic H_i)' y_j - 2 (Bc' H_i)' (H_j x V-_j) and
//   dtau_i/dqdot_j = 2 (Bc' H_i)' H_j + (Ic H_i)' z_j for DOFs j inboard of body i;
//   M(j, i) = H_j' Ic H_i (the composite-rigid-body algorithm).
// One DOF (column k) at a time in 6-vectors; the ancestors' DOFs along
// Model::dof_parent. derivative_velocity_terms: M and dID/dv, which do not
// depend on qdd (and Ic H_k, Bc' H_k for the next); derivative_acceleration_terms:
// ID = H' F and, with `partials`, dID/dq.
template <class S>
void derivative_velocity_terms(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, std::size_t i) {
  const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
  const Mat6<S>& inertia = w.composite_inertia[i];
  const Mat6<S>& coriolis = w.composite_coriolis_inertia[i];
  for (Eigen::Index c = 0; c < ni; ++c) {
    const Eigen::Index k = vi + c;
    const Vec6<S> axis = w.dof_axis.col(k);
    const Vec6<S> force_per_v = S(2) * coriolis_times(coriolis, axis) + inertia * w.velocity_acceleration.col(k);
    const Vec6<S> inertia_axis = inertia * axis, coriolis_t_axis = coriolis_transpose_times(coriolis, axis);
    w.inertia_axis.col(k) = inertia_axis;  // for derivative_acceleration_terms
    w.coriolis_t_axis.col(k) = coriolis_t_axis;
    for (Eigen::Index c2 = 0; c2 < ni; ++c2) {  // the body's own DOFs: their axes turn with it
      const Vec6<S> own_axis = w.dof_axis.col(vi + c2);
      w.inverse_dv(vi + c2, k) = own_axis.dot(force_per_v);
      d.mass_matrix(vi + c2, k) = own_axis.dot(inertia_axis);
    }
    for (int j = m.dof_parent[static_cast<std::size_t>(vi)]; j >= 0; j = m.dof_parent[static_cast<std::size_t>(j)]) {
      const Vec6<S> inboard_axis = w.dof_axis.col(j);
      w.inverse_dv(j, k) = inboard_axis.dot(force_per_v);
      w.inverse_dv(k, j) = S(2) * coriolis_t_axis.dot(inboard_axis) + inertia_axis.dot(w.velocity_acceleration.col(j));
      d.mass_matrix(k, j) = d.mass_matrix(j, k) = inertia_axis.dot(inboard_axis);
    }
  }
}

template <class S>
void derivative_acceleration_terms(const ModelTpl<S>& m, DynamicsDerivativesTpl<S>& w, std::size_t i, bool partials) {
  const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
  const Mat6<S>& inertia = w.composite_inertia[i];
  const Mat6<S>& coriolis = w.composite_coriolis_inertia[i];
  const Vec6<S>& force = w.composite_force[i];
  const bool universal = joint_axes_coupled(m.joint_fast_path[i]);
  for (Eigen::Index c = 0; c < ni; ++c) {
    const Eigen::Index k = vi + c;
    const Vec6<S> axis = w.dof_axis.col(k);
    w.inverse_force[k] = axis.dot(force);
    if (!partials) continue;
    const Vec6<S> force_per_q =
        inertia * w.displacement_acceleration.col(k) - S(2) * coriolis_times(coriolis, Vec6<S>(w.displacement_lever.col(k)));
    const Vec6<S> inboard_force_per_q = force_per_q + force_cross(axis, force);
    const Vec6<S> inertia_axis = w.inertia_axis.col(k), coriolis_t_axis = w.coriolis_t_axis.col(k);
    for (Eigen::Index c2 = 0; c2 < ni; ++c2)  // the body's own DOFs: their axes turn with it
      w.inverse_dq(vi + c2, k) =
          w.dof_axis.col(vi + c2).dot(universal && c == 1 && c2 == 0 ? inboard_force_per_q : force_per_q);
    for (int j = m.dof_parent[static_cast<std::size_t>(vi)]; j >= 0; j = m.dof_parent[static_cast<std::size_t>(j)]) {
      w.inverse_dq(j, k) = w.dof_axis.col(j).dot(inboard_force_per_q);
      w.inverse_dq(k, j) = inertia_axis.dot(w.displacement_acceleration.col(j)) -
                           S(2) * coriolis_t_axis.dot(w.displacement_lever.col(j));
    }
  }
}

// The subtree sums of body i added to its parent's: the inertia and
// Coriolis factor with `inertias`, the force always.
template <class S>
void add_to_parent(const ModelTpl<S>& m, DynamicsDerivativesTpl<S>& w, std::size_t i, bool inertias) {
  const int p = m.parent[i];
  if (p < 0) return;
  const std::size_t a = static_cast<std::size_t>(p);
  if (inertias) {
    w.composite_inertia[a] += w.composite_inertia[i];
    w.composite_coriolis_inertia[a].template leftCols<3>() += w.composite_coriolis_inertia[i].template leftCols<3>();
  }
  w.composite_force[a] += w.composite_force[i];
}

// Armature (ModelTpl::set_armature; constant in q and v) and joint springs
// (force_elements.hpp: ID carries -Q = k (q - rest) + c v on their DOF):
// `qdd` null for the terms of ID(q, v, 0) and M, dID/dv; `partials` adds the
// springs' stiffness to dID/dq.
template <class S>
void add_joint_terms(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, const S* q, const S* v,
                     const S* qdd, bool velocity_terms, bool partials) {
  if (m.has_armature) {
    for (Eigen::Index k = 0; k < m.nv; ++k) {
      const S armature = m.armature[static_cast<std::size_t>(k)];
      if (qdd) w.inverse_force[k] += armature * qdd[k];
      if (velocity_terms) d.mass_matrix(k, k) += armature;
    }
  }
  for (const JointSpringTpl<S>& e : m.force_elements.joint_springs) {
    w.inverse_force[e.dof] += e.stiffness * (q[e.coordinate] - e.rest) + e.damping * v[e.dof];
    if (partials) w.inverse_dq(e.dof, e.dof) += e.stiffness;
    if (velocity_terms) w.inverse_dv(e.dof, e.dof) += e.damping;
  }
}

template <class S>
Status inverse_derivative_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, const S* q,
                                 const S* v, const S* qdd, const S* f_ext) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = detail::world_acceleration(m);
  // Blocks between DOFs of different branches stay zero.
  w.inverse_dq.setZero();
  w.inverse_dv.setZero();
  d.mass_matrix.setZero();
  tabulate_joint_angles(m, d.sweep, q);
  for (std::size_t i = 0; i < n; ++i) {
    derivative_kinematics_update(m, d, w, i, q, v, f_ext);
    derivative_acceleration_update(m, d, w, i, v, qdd, world_acc, true);
  }
  for (std::size_t i = n; i-- > 0;) {
    derivative_velocity_terms(m, d, w, i);
    derivative_acceleration_terms(m, w, i, true);
    add_to_parent(m, w, i, true);
  }
  add_joint_terms(m, d, w, q, v, qdd, true, true);
  for (const MatX<S>* x : {&w.inverse_dq, &w.inverse_dv}) {
    const Status status = detail::check_finite_columns(*x);
    if (!status.ok()) return status;
  }
  return detail::check_finite(w.inverse_force);
}

// The prescribed rows of dtau/dx = dID/dx + M dqdd/dx (the regular rows are
// zero for x = q, v: their torques are inputs). Rows P of dqdd/dx are zero, so
// M_P. dqdd/dx = M_PR dqdd_R/dx = -E dID_R/dx with E = M_PR M_RR^-1. Row p of
// E is minus the regular part of dqdd/du's column p (-M_RR^-1 M_Rp, M_RR^-1
// symmetric): placed in M~^-1's prescribed rows (zero there on the regular
// columns), the products that form dqdd_R/dx leave M_PR dqdd_R/dx in rows P
// of dqdd/dx at no extra cost. Called after dqdd/du's prescribed columns are
// formed and before dqdd/dq and dqdd/dv are.
template <class S>
void place_prescribed_rows_of_inverse(const ModelTpl<S>& m, DynamicsDerivativesTpl<S>& w) {
  MatX<S>& Minv = w.dqdd_du;
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    for (Eigen::Index c = 0; c < m.nv; ++c)
      if (!m.is_prescribed(static_cast<int>(c))) Minv(p, c) = -Minv(c, p);
  }
}

// dtau_P/du on the prescribed columns: with qdd_P = u_P, entry (p, j) is
//   M_pR dqdd_R/du_j + M_pj = M_pj - M_pR M_RR^-1 M_Rj,
// the Schur complement of M_RR, symmetric. Column j of dqdd/du holds
// -M_RR^-1 M_Rj on the regular rows and e_j on the prescribed ones, so the
// whole sum is the dot product of M's column p with it, over the DOFs where
// that column is nonzero (p's ancestors and subtree: contiguous runs, each
// an Eigen dot product of two column segments). Entries j < p are mirrored.
template <class S>
void prescribed_schur_complement(const ModelTpl<S>& m, const MatX<S>& mass, DynamicsDerivativesTpl<S>& w) {
  for (int a = 0; a < m.n_prescribed; ++a) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(a)];
    for (int b = a; b < m.n_prescribed; ++b) {
      const int j = m.prescribed_dofs[static_cast<std::size_t>(b)];
      S sum(0);
      const auto add_run = [&](int first, int last) {
        const Eigen::Index length = last - first + 1;
        sum += mass.col(p).segment(first, length).dot(w.dqdd_du.col(j).segment(first, length));
      };
      add_run(p, w.subtree_end[static_cast<std::size_t>(p)]);
      for_each_ancestor_run(p, false, m.dof_parent, m.dof_run_start, add_run);
      w.dtau_du(p, j) = w.dtau_du(j, p) = sum;
    }
  }
}

// Column k of dtau_P/dq and dtau_P/dv, dID_P/dx + (rows P of dqdd/dx), taken
// as soon as column k of dqdd/dx is formed with M~^-1's prescribed rows
// placed (place_prescribed_rows_of_inverse), while it is in cache; rows P of
// that column are then set back to zero, as they are in dqdd/dx.
template <class S>
SOADYN_ALWAYS_INLINE void take_prescribed_rows(const ModelTpl<S>& m, DynamicsDerivativesTpl<S>& w, Eigen::Index k) {
  for (int a = 0; a < m.n_prescribed; ++a) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(a)];
    w.dtau_dq(p, k) = w.inverse_dq(p, k) + w.dqdd_dq(p, k);
    w.dtau_dv(p, k) = w.inverse_dv(p, k) + w.dqdd_dv(p, k);
    w.dqdd_dq(p, k) = w.dqdd_dv(p, k) = S(0);
  }
}

// dtau/du: the identity on the regular rows (tau_R = u_R); on the prescribed
// rows, rows P of M~^-1 (M_PR dqdd_R/du) on the regular columns and the
// Schur complement (prescribed_schur_complement) on the prescribed ones.
// Rows P of dqdd/du then go back to what they are: zero on the regular
// columns (the prescribed columns kept e_j there).
template <class S>
void input_derivatives_of_force(const ModelTpl<S>& m, const MatX<S>& mass, DynamicsDerivativesTpl<S>& w) {
  w.dtau_du.setZero();
  prescribed_schur_complement(m, mass, w);
  for (int j = 0; j < m.nv; ++j) {
    if (m.is_prescribed(j)) continue;
    w.dtau_du(j, j) = S(1);
    for (int a = 0; a < m.n_prescribed; ++a) {
      const int p = m.prescribed_dofs[static_cast<std::size_t>(a)];
      w.dtau_du(p, j) = w.dqdd_du(p, j);
      w.dqdd_du(p, j) = S(0);
    }
  }
}

// The hybrid dynamics and its derivatives from one kinematic sweep. The
// velocity terms (M, dID/dv) and h = ID(q, v, 0) come first; with M~ = M
// whose prescribed rows and columns are the identity and its tree factor
// M~ = U U' (tree_cholesky.hpp), M~^-1 = W' W for W = U^-1, upper triangular
// with the tree's pattern (W(j, i) != 0 for j an ancestor of i or i: column
// i of W is nonzero on i's ancestors only, so entry (a, b), a <= b, of W' W
// is a dot product over the first a + 1 rows). Then
//   qdd = M~^-1 b,  b_R = u_R - h_R - M_RP u_P,  b_P = u_P
// (Jain & Rodriguez 1993, Eq. 12, partitioned), the accelerations, ID and its
// q-derivative at qdd, tau_P = ID_P, and
//   dqdd/dx = -M~^-1 dID~/dx (x = q, v; dID~ without its prescribed rows),
//   dqdd/du = M~^-1 on regular columns, e_p - M~^-1 M~_.p on prescribed ones
//     (M~_.p: column p of M without its prescribed rows),
//   dtau_P/dx = dID_P/dx + M_P. dqdd/dx,  dtau_P/du = M_P. dqdd/du.
// The products use the tree pattern of dID/dx and of M: a column is nonzero
// on its DOF's ancestors and subtree (DOFs k..subtree_end[k]) only. Against
// an articulated-body pass for qdd and solving [dID/dq dID/dv I] with the
// factor, one kinematic sweep fewer and about half the multiplications for a
// humanoid.
template <class S>
Status one_sweep_dynamics_derivatives(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w,
                                      const S* q, const S* v, const S* u, const S* f_ext) {
  const Eigen::Index nv = m.nv;
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  const Vec6<S> world_acc = detail::world_acceleration(m);
  w.inverse_dq.setZero();  // blocks between DOFs of different branches stay zero
  w.inverse_dv.setZero();
  d.mass_matrix.setZero();
  tabulate_joint_angles(m, d.sweep, q);
  for (std::size_t i = 0; i < n; ++i) {
    derivative_kinematics_update(m, d, w, i, q, v, f_ext);
    derivative_acceleration_update(m, d, w, i, v, static_cast<const S*>(nullptr), world_acc, false);
  }
  for (std::size_t i = n; i-- > 0;) {
    derivative_velocity_terms(m, d, w, i);
    derivative_acceleration_terms(m, w, i, false);
    add_to_parent(m, w, i, true);
  }
  add_joint_terms(m, d, w, q, v, static_cast<const S*>(nullptr), true, false);
  MatX<S>& U = w.regular_mass;
  U = d.mass_matrix;
  detail::replace_prescribed_by_identity(m, U);
  const int bad_pivot = tree_ltl_in_place(U, m.dof_parent, m.dof_run_start);
  if (bad_pivot >= 0) return {StatusCode::singular_articulated_inertia, bad_pivot};
  MatX<S>& inverse_factor = w.inverse_factor;
  tree_ltl_inverse_factor(U, m.dof_parent, m.dof_run_start, inverse_factor);
  MatX<S>& Minv = w.dqdd_du;
  // W's prescribed rows and columns are those of the identity (M~'s are): so are M~^-1's, without the dots.
  for (Eigen::Index b = 0; b < nv; ++b)
    for (Eigen::Index a = 0; a <= b; ++a)
      Minv(a, b) = Minv(b, a) =
          m.is_prescribed(static_cast<int>(a)) || m.is_prescribed(static_cast<int>(b))
              ? S(a == b ? 1 : 0)
              : inverse_factor.col(a).head(a + 1).dot(inverse_factor.col(b).head(a + 1));
  VecX<S>& rhs = d.tau;  // b, then tau
  rhs = Eigen::Map<const VecX<S>>(u, nv) - w.inverse_force;
  for (int k = 0; k < m.n_prescribed; ++k) {  // b_R -= M_RP u_P, b_P = u_P
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    rhs.noalias() -= d.mass_matrix.col(p) * u[p];
  }
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    rhs[p] = u[p];
  }
  d.qdd.noalias() = Minv * rhs;
  Status status = detail::check_finite(d.qdd);
  if (!status.ok()) return status;
  for (std::size_t i = 0; i < n; ++i) derivative_acceleration_update(m, d, w, i, v, d.qdd.data(), world_acc, true);
  for (std::size_t i = n; i-- > 0;) {
    derivative_acceleration_terms(m, w, i, true);
    add_to_parent(m, w, i, false);
  }
  add_joint_terms(m, d, w, q, v, d.qdd.data(), false, true);
  d.tau = Eigen::Map<const VecX<S>>(u, nv);
  for (int k = 0; k < m.n_prescribed; ++k) {  // tau_P = ID_P(q, v, qdd)
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    d.tau[p] = w.inverse_force[p];
  }
  status = detail::check_prescribed_finite(m, d.tau);
  if (!status.ok()) return status;
  // dqdd/du: M~^-1 on regular columns; column p = e_p - M~^-1 M~_.p on a
  // prescribed one (M~^-1 has e_p there, and M's column p is nonzero on p's
  // ancestors and subtree only).
  for (int k = 0; k < m.n_prescribed; ++k) {
    const int p = m.prescribed_dofs[static_cast<std::size_t>(k)];
    const auto subtract = [&](int first, int last) {
      for (int c = first; c <= last; ++c)
        if (!m.is_prescribed(c)) Minv.col(p) -= Minv.col(c) * d.mass_matrix(c, p);
    };
    subtract(p, w.subtree_end[static_cast<std::size_t>(p)]);
    for_each_ancestor_run(p, false, m.dof_parent, m.dof_run_start, subtract);
  }
  place_prescribed_rows_of_inverse(m, w);
  w.dqdd_dq.setZero();
  w.dqdd_dv.setZero();
  w.dtau_dq.setZero();  // the regular rows stay zero: their torques are inputs
  w.dtau_dv.setZero();
  // Columns k of dqdd/dq and dqdd/dv together: each column of M^-1 is read
  // once for both (plain loops: no product dispatch for these short columns).
  // dID~ is dID without its prescribed rows: their columns of M^-1 are skipped.
  for (Eigen::Index k = 0; k < nv; ++k) {
    S* const out_q = &w.dqdd_dq(0, k);
    S* const out_v = &w.dqdd_dv(0, k);
    const S* const partial_q = &w.inverse_dq(0, k);
    const S* const partial_v = &w.inverse_dv(0, k);
    const auto one_column = [&](int c) {
      const S a_q = partial_q[c], a_v = partial_v[c];
      const S* const column = &Minv(0, c);
      for (Eigen::Index r = 0; r < nv; ++r) {
        out_q[r] -= a_q * column[r];
        out_v[r] -= a_v * column[r];
      }
    };
    const auto two_columns = [&](int c, int e) {  // two columns of M^-1 per pass over the outputs
      const S a_q = partial_q[c], a_v = partial_v[c], b_q = partial_q[e], b_v = partial_v[e];
      const S* const column_a = &Minv(0, c);
      const S* const column_b = &Minv(0, e);
      for (Eigen::Index r = 0; r < nv; ++r) {
        out_q[r] -= a_q * column_a[r] + b_q * column_b[r];
        out_v[r] -= a_v * column_a[r] + b_v * column_b[r];
      }
    };
    const auto accumulate = [&](int first, int last) {
      int pending = -1;
      for (int c = first; c <= last; ++c) {
        if (m.is_prescribed(c)) continue;
        if (pending < 0) {
          pending = c;
        } else {
          two_columns(pending, c);
          pending = -1;
        }
      }
      if (pending >= 0) one_column(pending);
    };
    accumulate(static_cast<int>(k), w.subtree_end[static_cast<std::size_t>(k)]);
    for_each_ancestor_run(static_cast<int>(k), false, m.dof_parent, m.dof_run_start, accumulate);
    take_prescribed_rows(m, w, k);
  }
  input_derivatives_of_force(m, d.mass_matrix, w);
  for (const MatX<S>* x : {&w.dqdd_dq, &w.dqdd_dv, &w.dqdd_du, &w.dtau_dq, &w.dtau_dv, &w.dtau_du}) {
    status = detail::check_finite_columns(*x);
    if (!status.ok()) return status;
  }
  return Status{};
}

}  // namespace detail

template <class S>
Status inverse_dynamics_derivatives(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w,
                                    const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& qdd,
                                    const S* f_ext) {
  const Status status = detail::inverse_derivative_sweeps(m, d, w, q.data(), v.data(), qdd.data(), f_ext);
  d.tau = w.inverse_force;
  return status;
}

template <class S>
Status dynamics_derivatives(const ModelTpl<S>& m, DataTpl<S>& d, DynamicsDerivativesTpl<S>& w, const ConstVecRef<S>& q,
                            const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  return detail::one_sweep_dynamics_derivatives(m, d, w, q.data(), v.data(), u.data(), f_ext);
}

}  // namespace soadyn
