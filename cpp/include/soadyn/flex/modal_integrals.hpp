// Modal integrals of a lumped flexible body: the invariants from which its
// augmented mass matrix M(eta) is evaluated exactly, for any eta, in
// O(n_m^2) operations without visiting the nodes again.
//
// Kinetic energy of the lumped model. With V = [omega; v] the body-frame
// spatial velocity of the reference frame (v: velocity of its origin),
// p_j(eta) = r_j + Phi_t,j eta the deformed node position, and the rotary
// inertia J_j kept in its undeformed orientation (the modelling choice of
// flexible_body.hpp):
//   T = sum_j 1/2 m_j |v + omega x p_j + Phi_t,j eta_dot|^2
//     + 1/2 (omega + Phi_r,j eta_dot)' J_j (omega + Phi_r,j eta_dot)       (1)
//     = 1/2 [V; eta_dot]' M(eta) [V; eta_dot],
// which gives, blockwise over (omega, v, eta_dot):
//   M = [ M_ww(eta)   [c(eta)]x   M_we(eta) ]
//       [ -[c(eta)]x  m 1         S1        ]
//       [ M_we'       S1'         M_ee      ]
//   c(eta)    = sum_j m_j p_j = c0 + S1 eta                                 (2)
//   E(eta)    = sum_j m_j p_j p_j'
//             = E0 + sum_k eta_k (A_k + A_k') + sum_kl eta_k eta_l B_kl      (3)
//   M_ww(eta) = tr(E) 1 - E + sum_j J_j                                     (4)
//   M_we(eta) = sum_j m_j [p_j]x Phi_t,j + J_j Phi_r,j
//             = H0 + sum_k eta_k Q_k                                        (5)
//   M_ee      = sum_j m_j Phi_t,j' Phi_t,j + Phi_r,j' J_j Phi_r,j            (6)
// with the invariants (e_k: k-th unit vector of R^n_m)
//   m = sum m_j, c0 = sum m_j r_j, E0 = sum m_j r_j r_j', S1 = sum m_j Phi_t,j,
//   A_k  = sum_j m_j r_j (Phi_t,j e_k)'            (3 x 3 per mode)
//   B_kl = sum_j m_j (Phi_t,j e_k)(Phi_t,j e_l)'   (3 x 3 per mode pair)
//   H0   = sum_j m_j [r_j]x Phi_t,j + J_j Phi_r,j  (3 x n_m)
//   Q_k  = sum_j m_j [Phi_t,j e_k]x Phi_t,j        (3 x n_m per mode).
// T is a quadratic polynomial in eta, so (2)-(6) are exact for the lumped
// model, not a truncated expansion. These are the lumped-mass forms of the
// inertia shape integrals of floating-frame flexible bodies (Shabana,
// "Dynamics of Multibody Systems", ch. 5) and the modal mass integrals of
// Jain & Rodriguez, JGCD 15(6), 1992. The top-left 6x6 block is a rigid
// spatial inertia about the body origin (inertia.hpp) for the deformed
// shape; M_ee is constant because the modes are linear.
//
// Velocity terms. With w = [V; eta_dot], the body's equations of motion
// (Euler-Poincare for the reference frame, Lagrange for eta) are
//   M(eta) dw/dt + [dM/dt w + (V x* (M w)_V; 0)] - [0; dT/deta] = generalized force,
// where (dM/dt) and dT/deta follow from the derivatives of (2)-(5),
//   dE/deta_k = D_k + D_k',  D_k = sum_j m_j p_j (Phi_t,j e_k)' = A_k + sum_l eta_l B_lk,   (7)
//   dc/deta_k = S1 e_k,      dM_we/deta_k = Q_k,
// so that, with omega, v the halves of V and G = sum_k eta_dot_k D_k:
//   dM/dt w = [ (tr(G + G') 1 - G - G') omega + (S1 eta_dot) x v + sum_k eta_dot_k Q_k eta_dot ;
//               omega x (S1 eta_dot) ;
//               sum_k eta_dot_k Q_k' omega ]                                            (8)
//   dT/deta_k = tr(D_k) |omega|^2 - omega' D_k omega + (S1 e_k).(v x omega)
//             + omega' Q_k eta_dot.                                                     (9)
// Q_k e_l = -Q_l e_k, so sum_k eta_dot_k Q_k eta_dot = 0. Every use of D_k
// reads its symmetric part only (E is symmetric; (8) reads G + G' and (9) a
// trace and a quadratic form), so the rates are formed as
//   sym D_k = sym A_k + sum_l eta_l sym B_lk   (sym B_lk = sym B_kl),
// six entries each (packed_symmetric): 6 n_m^2 multiply-adds for the rates
// and about 2 n_m^2 for the rest.
//
// Storage: about 19 n_m^2 + 21 n_m scalars (B_kl and its packed symmetric
// parts dominate); evaluation of M(eta): about 12 n_m^2 multiply-adds plus
// copying the constant blocks.
#pragma once
#include "soadyn/flex/flexible_node.hpp"
#include "soadyn/spatial/transform.hpp"

namespace soadyn {

// The symmetric part of a 3x3 matrix packed as (xx, yy, zz, xy, xz, yz), and back.
template <class S>
inline Vec6<S> packed_symmetric(const Mat3<S>& A) {
  Vec6<S> out;
  out << A(0, 0), A(1, 1), A(2, 2), S(0.5) * (A(0, 1) + A(1, 0)), S(0.5) * (A(0, 2) + A(2, 0)),
      S(0.5) * (A(1, 2) + A(2, 1));
  return out;
}
template <class S>
inline Mat3<S> unpacked_symmetric(const Vec6<S>& p) {
  Mat3<S> A;
  A << p[0], p[3], p[4], p[3], p[1], p[5], p[4], p[5], p[2];
  return A;
}

// k N: the size of k blocks of N, Eigen::Dynamic when N is.
constexpr int times_mode_count(int k, int N) { return N == Eigen::Dynamic ? Eigen::Dynamic : k * N; }

// out = base + M x for a column-major rows x cols matrix M, all in
// contiguous memory (flattened modal invariants). No allocation. out may not
// overlap base, M or x. Rows, Cols: the sizes at compile time when known (a
// mode count known at compile time: each entry's sum over the columns is
// formed in registers, pairs of rows at a time), else Eigen::Dynamic: column
// by column, as a few modes are too few for a general matrix-vector kernel's
// set-up to pay.
template <int Rows, int Cols, class S>
inline void affine_columns(const S* base, const S* M, Eigen::Index rows, Eigen::Index cols, const S* x, S* out) {
  using Column = Eigen::Matrix<S, Rows, 1>;
  Eigen::Map<Column> result(out, rows);
  if constexpr (Rows != Eigen::Dynamic && Cols != Eigen::Dynamic) {
    result = Eigen::Map<const Column>(base) +
             Eigen::Map<const Eigen::Matrix<S, Rows, Cols>>(M).lazyProduct(Eigen::Map<const Eigen::Matrix<S, Cols, 1>>(x));
  } else {
    result = Eigen::Map<const Column>(base, rows);
    for (Eigen::Index c = 0; c < cols; ++c) result += x[c] * Eigen::Map<const Column>(M + c * rows, rows);
  }
}

template <class S>
struct ModalIntegrals {
  int n_modes = 0;
  S mass = S(0);                                     // m
  Vec3<S> first_moment = Vec3<S>::Zero();            // c0
  Mat3<S> second_moment = Mat3<S>::Zero();           // E0
  Mat3<S> rotary_inertia = Mat3<S>::Zero();          // sum_j J_j
  ModeShape3<S> modal_first_moment;                  // S1 (3 x n_m)
  MatX<S> second_moment_linear;     // [A_0 ... A_{n-1}], 3 x 3n_m
  MatX<S> second_moment_quadratic;  // B_kl at columns 3(k n_m + l), 3 x 3n_m^2
  ModeShape3<S> angular_coupling;                    // H0 (3 x n_m)
  MatX<S> angular_coupling_linear;  // [Q_0 ... Q_{n-1}], 3 x n_m^2
  // The symmetric parts, packed (packed_symmetric), from which the rates
  // are formed: sym A_k in column k (6 x n_m), and sym B_lk in rows 6k ..
  // 6k + 5 of column l (6 n_m x n_m).
  MatX<S> symmetric_rate_linear;
  MatX<S> symmetric_rate_quadratic;
  MatX<S> modal_mass;                                // M_ee (n_m x n_m)
  // For bodies that carry nothing on a node (sweeps/appendage_update.hpp):
  MatX<S> modal_mass_inverse;                        // M_ee^-1
  MatX<S> modal_first_moment_gain;                   // W = M_ee^-1 S1' (n_m x 3)
  Mat3<S> translational_appendage_inertia = Mat3<S>::Zero();  // m 1 - S1 W

  // One pass over the nodes; every node's mode_shape has n_modes columns.
  static ModalIntegrals from_nodes(const FlexibleNodes<S>& nodes, int n_modes);

  // c(eta), Eq. (2), and E(eta), Eq. (3).
  Vec3<S> first_moment_at(const Eigen::Ref<const VecX<S>>& eta) const;
  Mat3<S> second_moment_at(const Eigen::Ref<const VecX<S>>& eta) const;

  // out = M(eta), (6 + n_m) square, both triangles. O(n_m^2), no allocation:
  // the recursion calls this with a block of its preallocated Data.
  void augmented_mass_matrix(const Eigen::Ref<const VecX<S>>& eta, Eigen::Ref<MatX<S>> out) const;

  // 1/2 [V; eta_dot]' M(eta) [V; eta_dot], the body's kinetic energy (V body
  // frame), from the blocks of Eqs. (2)-(6) without forming M(eta). O(n_m^2),
  // no allocation.
  S kinetic_energy_at(const Eigen::Ref<const VecX<S>>& eta, const Vec6<S>& V,
                      const Eigen::Ref<const VecX<S>>& eta_dot) const;

  // out = [sym D_0 ... sym D_{n_m-1}] of Eq. (7), each packed
  // (packed_symmetric); `out` must already be 6 x n_m. No allocation. N: n_m
  // known at compile time (appendage_update.hpp), or Eigen::Dynamic.
  template <int N = Eigen::Dynamic>
  void second_moment_rates(const Eigen::Ref<const VecX<S>>& eta, MatX<S>& out) const;

  // out (6 + n_m) = dM/dt w + [V x* (M w)_V; 0] - [0; dT/deta], Eqs. (7)-(9),
  // given `momentum` = (M w)_V = M_VV V + M_Ve eta_dot and `rates` =
  // second_moment_rates at eta. No allocation. N as above.
  template <int N = Eigen::Dynamic>
  void inertial_bias(const Eigen::Ref<const VecX<S>>& eta_dot, const Vec6<S>& V, const Vec6<S>& momentum,
                     const MatX<S>& rates, Eigen::Ref<VecX<S>> out) const;

  // symmetric_rate_linear and _quadratic from second_moment_linear and
  // _quadratic.
  void refresh_symmetric_rates();

  // The same integrals for the body described in a frame where its own
  // frame has the pose X = (R, p): node positions R r + p, mode shapes
  // R Phi, rotary inertias R J R'. From these, without the nodes:
  //   c0' = R c0 + m p,  S1' = R S1,  sum J' = R (sum J) R',
  //   E0' = R E0 R' + (R c0) p' + p (R c0)' + m p p',
  //   A_k' = R A_k R' + p (R S1 e_k)',  B_kl' = R B_kl R',
  //   H0' = R H0 + [p]x R S1,  Q_k' = R Q_k  ([R r]x R = R [r]x),
  //   M_ee and M_ee^-1 unchanged,  W' = W R',  m 1 - S1' W' = R (m 1 - S1 W) R'.
  // `out` is overwritten; with this mode count already, without allocating.
  void in_frame(const Transform<S>& X, ModalIntegrals& out) const;
  // The same integrals in scalar T (e.g. an automatic-differentiation scalar).
  template <class T>
  ModalIntegrals<T> cast() const {
    ModalIntegrals<T> out;
    out.n_modes = n_modes;
    out.mass = T(mass);
    out.first_moment = first_moment.template cast<T>();
    out.second_moment = second_moment.template cast<T>();
    out.rotary_inertia = rotary_inertia.template cast<T>();
    out.modal_first_moment = modal_first_moment.template cast<T>();
    out.second_moment_linear = second_moment_linear.template cast<T>();
    out.second_moment_quadratic = second_moment_quadratic.template cast<T>();
    out.angular_coupling = angular_coupling.template cast<T>();
    out.angular_coupling_linear = angular_coupling_linear.template cast<T>();
    out.symmetric_rate_linear = symmetric_rate_linear.template cast<T>();
    out.symmetric_rate_quadratic = symmetric_rate_quadratic.template cast<T>();
    out.modal_mass = modal_mass.template cast<T>();
    out.modal_mass_inverse = modal_mass_inverse.template cast<T>();
    out.modal_first_moment_gain = modal_first_moment_gain.template cast<T>();
    out.translational_appendage_inertia = translational_appendage_inertia.template cast<T>();
    return out;
  }
};

// M_ee of Eq. (6) straight from the nodes (also used to validate them).
template <class S>
MatX<S> modal_mass_matrix(const FlexibleNodes<S>& nodes, int n_modes);

extern template struct ModalIntegrals<double>;
extern template struct ModalIntegrals<float>;
// The mode-count-generic rates and bias (flexible_body.cpp); the fixed
// counts are instantiated with the appendage update (appendage_update.cpp).
extern template void ModalIntegrals<double>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<double>>&,
                                                                                  MatX<double>&) const;
extern template void ModalIntegrals<float>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<float>>&,
                                                                                MatX<float>&) const;
extern template void ModalIntegrals<double>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<double>>&,
                                                                            const Vec6<double>&, const Vec6<double>&,
                                                                            const MatX<double>&,
                                                                            Eigen::Ref<VecX<double>>) const;
extern template void ModalIntegrals<float>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<float>>&,
                                                                           const Vec6<float>&, const Vec6<float>&,
                                                                           const MatX<float>&,
                                                                           Eigen::Ref<VecX<float>>) const;
extern template MatX<double> modal_mass_matrix<double>(const FlexibleNodes<double>&, int);
extern template MatX<float> modal_mass_matrix<float>(const FlexibleNodes<float>&, int);

}  // namespace soadyn
