// Modal integrals (templated implementation of modal_integrals.hpp).
#pragma once
#include "soadyn/flex/modal_integrals.hpp"

namespace soadyn {

namespace flex_detail {

// Adds one node's terms of the mode-independent invariants m, c0, E0, sum J.
template <class S>
void add_rigid_moments(const FlexibleNode<S>& node, ModalIntegrals<S>& mi) {
  const S m = node.mass;
  const Vec3<S>& r = node.position;
  mi.mass += m;
  mi.first_moment += m * r;
  mi.second_moment += m * r * r.transpose();
  mi.rotary_inertia += node.rotary_inertia;
}

// Adds one node's terms of S1, A_k, B_kl, H0 and Q_k (modal_integrals.hpp).
template <class S>
void add_modal_moments(const FlexibleNode<S>& node, ModalIntegrals<S>& mi) {
  const int n = mi.n_modes;
  const S m = node.mass;
  const Vec3<S>& r = node.position;
  const ModeShape3<S> translation = node.translation_shape();
  mi.modal_first_moment += m * translation;
  mi.angular_coupling += m * skew(r) * translation + node.rotary_inertia * node.rotation_shape();
  for (int k = 0; k < n; ++k) {
    const Vec3<S> tk = translation.col(k);
    mi.second_moment_linear.template middleCols<3>(3 * k) += m * r * tk.transpose();
    mi.angular_coupling_linear.middleCols(k * n, n) += m * skew(tk) * translation;
    for (int l = 0; l < n; ++l)
      mi.second_moment_quadratic.template middleCols<3>(3 * (k * n + l)) += m * tk * translation.col(l).transpose();
  }
}

}  // namespace flex_detail

template <class S>
MatX<S> modal_mass_matrix(const FlexibleNodes<S>& nodes, int n_modes) {
  // Eq. (6): M_ee = sum_j m_j Phi_t,j' Phi_t,j + Phi_r,j' J_j Phi_r,j.
  MatX<S> mass = MatX<S>::Zero(n_modes, n_modes);
  for (const FlexibleNode<S>& node : nodes) {
    const ModeShape3<S> translation = node.translation_shape();
    const ModeShape3<S> rotation = node.rotation_shape();
    mass += node.mass * translation.transpose() * translation +
            rotation.transpose() * node.rotary_inertia * rotation;
  }
  return S(0.5) * (mass + mass.transpose());
}

template <class S>
ModalIntegrals<S> ModalIntegrals<S>::from_nodes(const FlexibleNodes<S>& nodes, int n_modes) {
  ModalIntegrals<S> mi;
  const int n = n_modes;
  mi.n_modes = n;
  mi.modal_first_moment = ModeShape3<S>::Zero(3, n);
  mi.second_moment_linear = MatX<S>::Zero(3, 3 * n);
  mi.second_moment_quadratic = MatX<S>::Zero(3, 3 * n * n);
  mi.angular_coupling = ModeShape3<S>::Zero(3, n);
  mi.angular_coupling_linear = MatX<S>::Zero(3, n * n);
  for (const FlexibleNode<S>& node : nodes) {
    flex_detail::add_rigid_moments(node, mi);
    flex_detail::add_modal_moments(node, mi);
  }
  mi.modal_mass = modal_mass_matrix(nodes, n);
  // M_ee is positive definite (FlexibleBodyDescription::validate); its
  // inverse is symmetrized like the matrix itself.
  const MatX<S> inverse = mi.modal_mass.llt().solve(MatX<S>::Identity(n, n));
  mi.modal_mass_inverse = S(0.5) * (inverse + inverse.transpose());
  return mi;
}

template <class S>
Vec3<S> ModalIntegrals<S>::first_moment_at(const Eigen::Ref<const VecX<S>>& eta) const {
  return first_moment + modal_first_moment * eta;  // Eq. (2)
}

template <class S>
Mat3<S> ModalIntegrals<S>::second_moment_at(const Eigen::Ref<const VecX<S>>& eta) const {
  // Eq. (3): E0 + sum_k eta_k (A_k + A_k') + sum_k eta_k sum_l eta_l B_kl,
  // the quadratic part as eta' (9 x n_m^2 block product) eta: 9 n_m^2
  // multiply-adds in contiguous memory.
  const int n = n_modes;
  using Mat9X = Eigen::Matrix<S, 9, Eigen::Dynamic>;
  Eigen::Matrix<S, 9, 1> quadratic = Eigen::Matrix<S, 9, 1>::Zero(), row;
  Mat3<S> linear = Mat3<S>::Zero();
  for (int k = 0; k < n; ++k) {
    linear += eta[k] * second_moment_linear.template middleCols<3>(3 * k);
    row.noalias() = Eigen::Map<const Mat9X>(second_moment_quadratic.data() + 9 * k * n, 9, n) * eta;
    quadratic += eta[k] * row;
  }
  const Mat3<S> E = second_moment + linear + linear.transpose() + Eigen::Map<const Mat3<S>>(quadratic.data());
  // E is symmetric (B_lk = B_kl'); averaging makes it so in floating point.
  return S(0.5) * (E + E.transpose());
}

template <class S>
void ModalIntegrals<S>::augmented_mass_matrix(const Eigen::Ref<const VecX<S>>& eta,
                                              Eigen::Ref<MatX<S>> out) const {
  const int n = n_modes;
  const Mat3<S> E = second_moment_at(eta);
  const Mat3<S> cx = skew(first_moment_at(eta));
  // Rigid 6x6 block: Eqs. (2) and (4).
  out.template topLeftCorner<3, 3>() = E.trace() * Mat3<S>::Identity() - E + rotary_inertia;
  out.template block<3, 3>(0, 3) = cx;
  out.template block<3, 3>(3, 0) = -cx;
  out.template block<3, 3>(3, 3) = mass * Mat3<S>::Identity();
  // Rigid-modal coupling: Eq. (5) for omega, S1 for v; 3 n_m^2 multiply-adds.
  // M_we = H0 + sum_k eta_k Q_k, column by column in fixed-size 3-vectors.
  for (int c = 0; c < n; ++c) out.template block<3, 1>(0, 6 + c) = angular_coupling.col(c);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < n; ++c) out.template block<3, 1>(0, 6 + c) += eta[k] * angular_coupling_linear.template block<3, 1>(0, k * n + c);
  out.block(3, 6, 3, n) = modal_first_moment;
  out.block(6, 0, n, 6) = out.block(0, 6, 6, n).transpose();
  // Modal block: Eq. (6).
  out.bottomRightCorner(n, n) = modal_mass;
}

template <class S>
void ModalIntegrals<S>::second_moment_rates(const Eigen::Ref<const VecX<S>>& eta, Eigen::Ref<MatX<S>> out) const {
  // D_k = A_k + sum_l eta_l B_lk = A_k + (sum_l eta_l B_kl)': the B_kl of one
  // k are 9 n_m contiguous scalars, so the sum is one 9 x n_m product.
  const int n = n_modes;
  using Mat9X = Eigen::Matrix<S, 9, Eigen::Dynamic>;
  Eigen::Matrix<S, 9, 1> sum;
  for (int k = 0; k < n; ++k) {
    sum.noalias() = Eigen::Map<const Mat9X>(second_moment_quadratic.data() + 9 * k * n, 9, n) * eta;
    out.template middleCols<3>(3 * k) =
        second_moment_linear.template middleCols<3>(3 * k) + Eigen::Map<const Mat3<S>>(sum.data()).transpose();
  }
}

template <class S>
void ModalIntegrals<S>::inertial_bias(const Eigen::Ref<const VecX<S>>& eta_dot, const Vec6<S>& V,
                                      const Eigen::Ref<const MatX<S>>& mass, const Eigen::Ref<const MatX<S>>& rates,
                                      Eigen::Ref<VecX<S>> out) const {
  // Loops over fixed-size 3-vectors (q_kl: column l of Q_k): no dynamic temporaries.
  const int n = n_modes;
  const Vec3<S> omega = V.template head<3>(), v = V.template tail<3>();
  const Vec3<S> v_cross_omega = v.cross(omega);
  const S omega2 = omega.squaredNorm();
  Mat3<S> G = Mat3<S>::Zero();                                 // sum_k eta_dot_k D_k
  Vec3<S> c_rate = Vec3<S>::Zero();                            // S1 eta_dot
  Vec6<S> momentum = mass.template topLeftCorner<6, 6>() * V;  // (M w)_V
  for (int k = 0; k < n; ++k) {
    const Mat3<S> Dk = rates.template middleCols<3>(3 * k);
    G += eta_dot[k] * Dk;
    c_rate += eta_dot[k] * modal_first_moment.col(k);
    momentum += eta_dot[k] * mass.template block<6, 1>(0, 6 + k);
    // Eq. (9) without its last term, which the double loop below subtracts.
    out[6 + k] = -(Dk.trace() * omega2 - omega.dot(Dk * omega) + modal_first_moment.col(k).dot(v_cross_omega));
  }
  Vec3<S> coupling_rate = Vec3<S>::Zero();  // sum_k eta_dot_k Q_k eta_dot
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < n; ++l) {
      const Vec3<S> q_kl = angular_coupling_linear.template block<3, 1>(0, k * n + l);
      const S q_omega = q_kl.dot(omega);
      coupling_rate += (eta_dot[k] * eta_dot[l]) * q_kl;
      out[6 + l] += eta_dot[k] * q_omega;  // Eq. (8), modal rows: sum_k eta_dot_k Q_k' omega
      out[6 + k] -= eta_dot[l] * q_omega;  // Eq. (9): omega' Q_k eta_dot
    }
  }
  const Mat3<S> E_rate = G + G.transpose();
  // Eq. (8), rigid rows, plus the gyroscopic term V x* (M w)_V.
  out.template head<3>() = E_rate.trace() * omega - E_rate * omega + c_rate.cross(v) + coupling_rate;
  out.template segment<3>(3) = omega.cross(c_rate);
  out.template head<6>() += force_cross(V, momentum);
}

}  // namespace soadyn
