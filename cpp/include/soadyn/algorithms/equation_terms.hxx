#pragma once
#include "soadyn/algorithms/equation_terms.hpp"
#include "soadyn/algorithms/rnea.hxx"
#include "soadyn/sweeps/tree_frame_updates.hpp"
#include "soadyn/spatial/coriolis_inertia.hpp"

namespace soadyn {

template <class S>
EquationTermsWorkspace<S>::EquationTermsWorkspace(const ModelTpl<S>& m) {
  for (int i = 0; i < m.nbodies(); ++i)
    if (m.is_flexible(i))
      throw std::invalid_argument("body '" + m.body_names[static_cast<std::size_t>(i)] +
                                  "' is flexible: the Coriolis matrix, its Christoffel symbols and dM/dt are "
                                  "computed for rigid bodies only");
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  composite_inertia.resize(n);
  composite_coriolis_inertia.resize(n);
  subspace_rate.resize(n);
  for (std::size_t i = 0; i < n; ++i) subspace_rate[i].resize(6, m.nv_body[i]);
  unit_velocity = VecX<S>::Zero(m.nv);
}

namespace detail {

// dH*/dt of body i's hinge in the tree frame: V(i) x H* for a subspace that is
// constant in the body frame, plus the body-frame rate carried to the tree
// frame for the universal joint, whose first axis in the body frame is R2' a1
// (joints/universal.hpp): d/dt (R2' a1) = qd2 (R2' a1) x a2.
template <class S>
void hinge_subspace_rate(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                         Mat6N<S>& rate) {
  const Mat6N<S>& s = d.sweep.tree_subspace[i];
  for (Eigen::Index c = 0; c < s.cols(); ++c)
    rate.col(c) = motion_cross(d.sweep.tree_velocity[i], Vec6<S>(s.col(c)));
  if (!joint_axes_coupled(m.joint_fast_path[i])) return;
  const UniversalJoint<S>& joint = *std::get_if<UniversalJoint<S>>(&m.joints[i]);
  const S* qi = q + m.q_index[i];
  const Vec3<S> first_axis = axis_angle_rotation(joint.axis2, qi[1]).transpose() * joint.axis1;
  Vec6<S> body_rate;
  body_rate << v[m.v_index[i] + 1] * first_axis.cross(joint.axis2), Vec3<S>::Zero();
  rate.col(0) += d.sweep.tree_pose[i].motion_to_parent(body_rate);
}

// C(q, v) in tree frames (Echeandia & Wensing 2021, Algorithm 1 recast on
// composite quantities). With J_k the tree-frame Jacobian of body k,
//   C = sum_k J_k' (I_k dJ_k/dt + B(I_k, V_k) J_k),
// and the columns of J_k are the hinge subspaces H*(j) of k's ancestors j, so
// with Ic(j), Bc(j) the sums of I and B over the subtree of j:
//   C(j, i) = H*(j)' (Ic(i) dH*(i)/dt + Bc(i) H*(i))       j ancestor of i or i itself,
//   C(i, j) = (Ic(i) H*(i))' dH*(j)/dt + (Bc(i)' H*(i))' H*(j)   j a strict ancestor of i.
// One outward sweep (kinematics, I, B), one inward sweep; each hinge's blocks
// walk to the root: O(N d) for tree depth d. Different trees share no
// ancestor, so their blocks stay zero.
template <class S>
void coriolis_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, EquationTermsWorkspace<S>& w, const S* q, const S* v,
                     Eigen::Ref<MatX<S>> coriolis) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  tabulate_joint_angles(m, d.sweep, q);
  for (std::size_t i = 0; i < n; ++i) {  // base to tip
    tree_velocity_update(m, d, i, q, v);
    spatial_inertia_in_frame(d.sweep.tree_pose[i], m.mass[i], m.com[i], m.inertia_com[i], w.composite_inertia[i]);
    w.composite_coriolis_inertia[i] = coriolis_inertia(w.composite_inertia[i], d.sweep.tree_velocity[i]);
    hinge_subspace_rate(m, d, i, q, v, w.subspace_rate[i]);
  }
  coriolis.setZero();
  for (std::size_t i = n; i-- > 0;) {  // tip to base: composites are complete at i
    const Eigen::Index vi = m.v_index[i], ni = m.nv_body[i];
    const Mat6<S>& inertia = w.composite_inertia[i];
    const Mat6<S>& coriolis_inertia_sum = w.composite_coriolis_inertia[i];
    if (ni > 0) {
      const Mat6N<S>& s = d.sweep.tree_subspace[i];
      const Mat6N<S> column_force = inertia * w.subspace_rate[i] + coriolis_inertia_sum * s;
      const Mat6N<S> inertia_force = inertia * s;
      const Mat6N<S> coriolis_force = coriolis_inertia_sum.transpose() * s;
      coriolis.block(vi, vi, ni, ni).noalias() = s.transpose() * column_force;
      for (int j = m.parent[i]; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
        const std::size_t a = static_cast<std::size_t>(j);
        const Eigen::Index vj = m.v_index[a], nj = m.nv_body[a];
        if (nj == 0) continue;
        const Mat6N<S>& sj = d.sweep.tree_subspace[a];
        coriolis.block(vj, vi, nj, ni).noalias() = sj.transpose() * column_force;
        coriolis.block(vi, vj, ni, nj).noalias() =
            inertia_force.transpose() * w.subspace_rate[a] + coriolis_force.transpose() * sj;
      }
    }
    const int p = m.parent[i];
    if (p >= 0) {
      w.composite_inertia[static_cast<std::size_t>(p)] += inertia;
      w.composite_coriolis_inertia[static_cast<std::size_t>(p)] += coriolis_inertia_sum;
    }
  }
}

}  // namespace detail

template <class S>
Status gravity_forces(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  detail::rnea<S>(m, d, q.data(), nullptr, nullptr, nullptr);  // h at rest: g(q)
  return detail::check_finite(d.tau);
}

template <class S>
Status external_forces_to_generalized(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                      const S* f_ext) {
  // Newton-Euler at rest without gravity returns -J' f_ext.
  const Vec6<S> no_gravity = Vec6<S>::Zero();
  if (m.has_flexible_bodies())
    detail::newton_euler_sweeps<true>(m, d, q.data(), static_cast<const S*>(nullptr), static_cast<const S*>(nullptr),
                                      f_ext, no_gravity);
  else
    detail::newton_euler_sweeps<false>(m, d, q.data(), static_cast<const S*>(nullptr),
                                       static_cast<const S*>(nullptr), f_ext, no_gravity);
  d.tau = -d.tau;
  return detail::check_finite(d.tau);
}

template <class S>
Status coriolis_matrix(const ModelTpl<S>& m, DataTpl<S>& d, EquationTermsWorkspace<S>& w, const ConstVecRef<S>& q,
                       const ConstVecRef<S>& v, Eigen::Ref<MatX<S>> coriolis) {
  detail::coriolis_sweeps(m, d, w, q.data(), v.data(), coriolis);
  return detail::check_finite_columns(coriolis);
}

template <class S>
Status mass_matrix_derivative(const ModelTpl<S>& m, DataTpl<S>& d, EquationTermsWorkspace<S>& w,
                              const ConstVecRef<S>& q, const ConstVecRef<S>& v, Eigen::Ref<MatX<S>> coriolis,
                              Eigen::Ref<MatX<S>> mass_rate) {
  detail::coriolis_sweeps(m, d, w, q.data(), v.data(), coriolis);
  mass_rate = coriolis + coriolis.transpose();  // Mdot - 2C skew-symmetric and Mdot symmetric
  return detail::check_finite_columns(mass_rate);
}

template <class S>
Status christoffel_symbols(const ModelTpl<S>& m, DataTpl<S>& d, EquationTermsWorkspace<S>& w,
                           const ConstVecRef<S>& q, Eigen::Ref<MatX<S>> christoffel) {
  const Eigen::Index nv = m.nv;
  for (Eigen::Index k = 0; k < nv; ++k) {  // C is linear in v: Gamma(:, :, k) = C(q, e_k)
    w.unit_velocity[k] = S(1);
    detail::coriolis_sweeps<S>(m, d, w, q.data(), w.unit_velocity.data(), christoffel.middleCols(k * nv, nv));
    w.unit_velocity[k] = S(0);
  }
  return detail::check_finite_columns(christoffel);
}

}  // namespace soadyn
