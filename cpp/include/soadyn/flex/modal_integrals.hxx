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

// (A + A') / 2: E0 and sum J are kept symmetric to the last bit (products
// such as m r r' round their two triangles differently), as the appendage
// step adds symmetric changes to E0 without symmetrizing again.
template <class S>
Mat3<S> symmetric_part(const Mat3<S>& A) {
  return S(0.5) * (A + A.transpose());
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
  mi.second_moment = flex_detail::symmetric_part(mi.second_moment);
  mi.rotary_inertia = flex_detail::symmetric_part(mi.rotary_inertia);
  mi.modal_mass = modal_mass_matrix(nodes, n);
  // M_ee is positive definite (FlexibleBodyDescription::validate); its
  // inverse is symmetrized like the matrix itself.
  const MatX<S> inverse = mi.modal_mass.llt().solve(MatX<S>::Identity(n, n));
  mi.modal_mass_inverse = S(0.5) * (inverse + inverse.transpose());
  mi.modal_first_moment_gain = mi.modal_mass_inverse * mi.modal_first_moment.transpose();
  const Mat3<S> translational = mi.mass * Mat3<S>::Identity() - mi.modal_first_moment * mi.modal_first_moment_gain;
  mi.translational_appendage_inertia = flex_detail::symmetric_part<S>(translational);
  mi.refresh_symmetric_rates();
  return mi;
}

template <class S>
void ModalIntegrals<S>::refresh_symmetric_rates() {
  const int n = n_modes;
  symmetric_rate_linear.resize(6, n);
  symmetric_rate_quadratic.resize(6 * n, n);
  const auto block = [](const MatX<S>& blocks, int b) { return Mat3<S>(Eigen::Map<const Mat3<S>>(blocks.data() + 9 * b)); };
  for (int k = 0; k < n; ++k) {
    symmetric_rate_linear.col(k) = packed_symmetric(block(second_moment_linear, k));
    for (int l = 0; l < n; ++l)
      symmetric_rate_quadratic.col(l).template segment<6>(6 * k) = packed_symmetric(block(second_moment_quadratic, l * n + k));
  }
}

template <class S>
void ModalIntegrals<S>::in_frame(const Transform<S>& X, ModalIntegrals<S>& out) const {
  const Mat3<S>& R = X.rotation;
  const Vec3<S>& p = X.translation;
  const int n = n_modes;
  const auto congruence = [&](const S* from, S* to) {  // a 3x3 block B -> R B R'
    Eigen::Map<Mat3<S>>(to).noalias() = R * Eigen::Map<const Mat3<S>>(from) * R.transpose();
  };
  out.n_modes = n;
  out.mass = mass;
  const Vec3<S> first = R * first_moment;
  out.first_moment = first + mass * p;
  using flex_detail::symmetric_part;
  out.second_moment = symmetric_part<S>(R * second_moment * R.transpose() + first * p.transpose() +
                                        p * first.transpose() + mass * p * p.transpose());
  out.rotary_inertia = symmetric_part<S>(R * rotary_inertia * R.transpose());
  out.modal_first_moment.resize(3, n);
  out.angular_coupling.resize(3, n);
  out.second_moment_linear.resize(3, 3 * n);
  out.second_moment_quadratic.resize(3, 3 * n * n);
  out.angular_coupling_linear.resize(3, n * n);
  const Mat3<S> p_cross = skew(p);
  for (int k = 0; k < n; ++k) {
    const Vec3<S> s1 = R * modal_first_moment.col(k);
    out.modal_first_moment.col(k) = s1;
    out.angular_coupling.col(k) = R * angular_coupling.col(k) + p_cross * s1;
    congruence(second_moment_linear.data() + 9 * k, out.second_moment_linear.data() + 9 * k);
    out.second_moment_linear.template middleCols<3>(3 * k) += p * s1.transpose();
    for (int l = 0; l < n; ++l) congruence(second_moment_quadratic.data() + 9 * (k * n + l),
                                           out.second_moment_quadratic.data() + 9 * (k * n + l));
  }
  for (int c = 0; c < n * n; ++c) out.angular_coupling_linear.col(c) = R * angular_coupling_linear.col(c);
  out.modal_mass = modal_mass;
  out.modal_mass_inverse = modal_mass_inverse;
  out.modal_first_moment_gain.resize(n, 3);
  for (int r = 0; r < n; ++r)
    out.modal_first_moment_gain.row(r) = (R * modal_first_moment_gain.row(r).transpose()).transpose();
  const Mat3<S> translational = R * translational_appendage_inertia * R.transpose();
  out.translational_appendage_inertia = flex_detail::symmetric_part<S>(translational);
  out.refresh_symmetric_rates();
}

template <class S>
Vec3<S> ModalIntegrals<S>::first_moment_at(const Eigen::Ref<const VecX<S>>& eta) const {
  return first_moment + modal_first_moment * eta;  // Eq. (2)
}

template <class S>
Mat3<S> ModalIntegrals<S>::second_moment_at(const Eigen::Ref<const VecX<S>>& eta) const {
  // Eq. (3): E0 + sum_k eta_k (A_k + A_k') + sum_k eta_k sum_l eta_l B_kl,
  // 9 n_m^2 multiply-adds on fixed-size 9-vectors in contiguous memory.
  const int n = n_modes;
  using Vec9 = Eigen::Matrix<S, 9, 1>;
  Vec9 quadratic = Vec9::Zero();
  Mat3<S> linear = Mat3<S>::Zero();
  for (int k = 0; k < n; ++k) {
    linear += eta[k] * second_moment_linear.template middleCols<3>(3 * k);
    Vec9 row = Vec9::Zero();
    for (int l = 0; l < n; ++l) row += eta[l] * Eigen::Map<const Vec9>(second_moment_quadratic.data() + 9 * (k * n + l));
    quadratic += eta[k] * row;
  }
  const Mat3<S> E = second_moment + linear + linear.transpose() + Eigen::Map<const Mat3<S>>(quadratic.data());
  // E is symmetric (B_lk = B_kl'); averaging makes it so in floating point.
  return flex_detail::symmetric_part<S>(E);
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
S ModalIntegrals<S>::kinetic_energy_at(const Eigen::Ref<const VecX<S>>& eta, const Vec6<S>& V,
                                       const Eigen::Ref<const VecX<S>>& eta_dot) const {
  const int n = n_modes;
  const Vec3<S> omega = V.template head<3>(), v = V.template tail<3>();
  // Rigid block, Eqs. (2) and (4): omega' J omega + 2 omega . (c x v) + m |v|^2, J = tr(E) 1 - E + sum_j J_j.
  const Mat3<S> E = second_moment_at(eta);
  const Vec3<S> J_omega = E.trace() * omega - E * omega + rotary_inertia * omega;
  S twice = omega.dot(J_omega) + S(2) * omega.dot(first_moment_at(eta).cross(v)) + mass * v.squaredNorm();
  // Coupling: M_we eta_dot with M_we = H0 + sum_k eta_k Q_k (Eq. 5) and M_ve eta_dot = S1 eta_dot, column
  // by column; modal block eta_dot' M_ee eta_dot (Eq. 6).
  Vec3<S> angular = Vec3<S>::Zero(), linear = Vec3<S>::Zero();
  S modal(0);
  for (int c = 0; c < n; ++c) {
    Vec3<S> column = angular_coupling.col(c);
    for (int k = 0; k < n; ++k) column += eta[k] * angular_coupling_linear.template block<3, 1>(0, k * n + c);
    angular += column * eta_dot[c];
    linear += modal_first_moment.col(c) * eta_dot[c];
    S row(0);
    for (int r = 0; r < n; ++r) row += modal_mass(r, c) * eta_dot[r];
    modal += row * eta_dot[c];
  }
  twice += S(2) * (omega.dot(angular) + v.dot(linear)) + modal;
  return S(0.5) * twice;
}

template <class S>
template <int N>
void ModalIntegrals<S>::second_moment_rates(const Eigen::Ref<const VecX<S>>& eta, MatX<S>& out) const {
  // sym D_k = sym A_k + sum_l eta_l sym B_lk. With every sym D_k packed into
  // one 6 n_m-vector, [sym D_0 ... sym D_{n_m-1}] = [sym A_0 ...] + B eta for
  // the 6 n_m x n_m matrix B whose column l is [sym B_l0 ... sym B_l,n_m-1]:
  // one matrix-vector product on stored memory.
  affine_columns<times_mode_count(6, N), N>(symmetric_rate_linear.data(), symmetric_rate_quadratic.data(), 6 * n_modes,
                                            n_modes, eta.data(), out.data());
}

template <class S>
template <int N>
void ModalIntegrals<S>::inertial_bias(const Eigen::Ref<const VecX<S>>& eta_dot, const Vec6<S>& V,
                                      const Vec6<S>& momentum, const MatX<S>& rates, Eigen::Ref<VecX<S>> out) const {
  // Q_k e_l = sum_j m_j (Phi_t,j e_k) x (Phi_t,j e_l) = -Q_l e_k, so the term
  // sum_k eta_dot_k Q_k eta_dot of Eq. (8) vanishes, and the modal rows'
  // sum_k eta_dot_k Q_k' omega (Eq. 8) - omega' Q_m eta_dot (Eq. 9) are
  // 2 sum_k eta_dot_k (Q_k e_m).omega: one dot product per mode pair k < m.
  const int n = N == Eigen::Dynamic ? n_modes : N;
  const Vec3<S> omega = V.template head<3>(), v = V.template tail<3>();
  const Vec3<S> v_cross_omega = v.cross(omega);
  const S omega2 = omega.squaredNorm();
  // tr(D) |omega|^2 - omega' D omega = <sym D, |omega|^2 1 - omega omega'>, packed
  // with the off-diagonal weights doubled.
  Vec6<S> weights;
  weights << omega2 - omega.x() * omega.x(), omega2 - omega.y() * omega.y(), omega2 - omega.z() * omega.z(),
      S(-2) * omega.x() * omega.y(), S(-2) * omega.x() * omega.z(), S(-2) * omega.y() * omega.z();
  Vec6<S> G = Vec6<S>::Zero();       // sym of sum_k eta_dot_k D_k, packed
  Vec3<S> c_rate = Vec3<S>::Zero();  // S1 eta_dot
  // The modal rows gather in local storage when N is fixed (registers: no
  // store to `out` can alias the integrals read meanwhile), else in `out`.
  Eigen::Matrix<S, N, 1> local_rows;
  Eigen::Map<Eigen::Matrix<S, N, 1>> rows(N == Eigen::Dynamic ? out.data() + 6 : local_rows.data(), n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Map<const Vec6<S>> Dk(rates.data() + 6 * k);  // rates is 6 x n_m, contiguous
    G += eta_dot[k] * Dk;
    c_rate += eta_dot[k] * modal_first_moment.col(k);
    rows[k] = -(weights.dot(Dk) + modal_first_moment.col(k).dot(v_cross_omega));
  }
  for (int k = 0; k < n; ++k) {
    for (int l = k + 1; l < n; ++l) {
      const S t = S(2) * angular_coupling_linear.template block<3, 1>(0, k * n + l).dot(omega);
      rows[l] += eta_dot[k] * t;
      rows[k] -= eta_dot[l] * t;
    }
  }
  if constexpr (N != Eigen::Dynamic) out.template segment<N>(6) = local_rows;
  const Mat3<S> E_rate = S(2) * unpacked_symmetric(G);  // G + G'
  // Eq. (8), rigid rows, plus the gyroscopic term V x* (M w)_V.
  out.template head<3>() = E_rate.trace() * omega - E_rate * omega + c_rate.cross(v);
  out.template segment<3>(3) = omega.cross(c_rate);
  out.template head<6>() += force_cross(V, momentum);
}

}  // namespace soadyn
