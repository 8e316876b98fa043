// Articulated terms of a flexible appendage: a flexible body with no body on
// its nodes (booms, antennas, solar arrays), for the tree-frame sweeps
// (tree_frame_updates.hpp). Equation numbers refer to flex/modal_integrals.hpp.
//
// With nothing on its nodes, the modal block of the body's articulated
// inertia is the constant M_ee, so its modal DOFs (always regular) are
// eliminated at once, in the body frame (Jain & Rodriguez, JGCD 15(6), 1992;
// flexible_updates.hpp):
//   G' = M_ee^-1 M_eV,  nu = M_ee^-1 (u_e - b_e),
//   P^ = M_VV - M_Ve G',  z^ = b_V + M_Ve nu.
// M(eta) is never assembled. Its blocks have structure that the general
// elimination ignores:
//   - M_Ve = [M_we(eta); S1] with S1 constant, so G' = [Y W] with
//     Y = M_ee^-1 M_we' (n_m x 3) and the constant W = M_ee^-1 S1';
//   - the translational block of P^ is the constant m 1 - S1 W;
//   - E(eta) of Eq. (3) follows from the rates D_k of Eq. (7) the bias needs
//     anyway: E = E0 + sum_k eta_k (A_k + D_k'), since
//     sum_k eta_k D_k' = sum_k eta_k A_k' + sum_kl eta_k eta_l B_kl; E being
//     symmetric, E = E0 + sum_k eta_k (sym A_k + sym D_k), on the packed
//     symmetric parts the rates are formed as.
// Every product is a loop over modes of fixed-size 3- and 6-vector and 3x3
// updates. The update is compiled for each mode count from 1 to
// max_fixed_appendage_modes (appendage_update.cpp), where those loops unroll
// and the flattened invariants' products keep their sums in registers;
// other counts and non-floating-point scalars take the generic code. For
// double it is compiled twice, for x86-64's baseline and for AVX2 with FMA,
// and the processor chooses on the first call (appendage_kernel below).
#pragma once
#include <type_traits>
#include <vector>
#include "soadyn/sweeps/flexible_updates.hpp"
#include "soadyn/sweeps/packet_appendage_update.hpp"

namespace soadyn {

// Mode counts with a compiled update of their own (above).
constexpr int max_fixed_appendage_modes = 6;

namespace detail {

// appendage_update (below) with n_m = N, or Eigen::Dynamic for any n_m.
template <int N, class S>
inline void appendage_terms(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const ModalIntegrals<S>& mi, const S* q,
                     const S* v, const S* u, const Vec6<S>* external, const Vec6<S>& V, Mat6<S>& P, Vec6<S>& z) {
  const int body = static_cast<int>(i);
  FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  const int n = N == Eigen::Dynamic ? mi.n_modes : N;
  using Modes = Eigen::Matrix<S, N, 1>;
  const Eigen::Map<const Modes> eta(q + m.modal_q_index(body), n);
  mi.template second_moment_rates<N>(modal_coordinates(m, body, q), fd.second_moment_rates);  // sym D_k, Eq. (7)
  const Eigen::Map<const Eigen::Matrix<S, 6, N>> D(fd.second_moment_rates.data(), 6, n);
  const Eigen::Map<const Eigen::Matrix<S, 6, N>> A(mi.symmetric_rate_linear.data(), 6, n);
  const Eigen::Map<const Eigen::Matrix<S, 3, N>> S1(mi.modal_first_moment.data(), 3, n);
  // c(eta), E(eta) (Eqs. 2, 3), M_we(eta) = H0 + sum_k eta_k Q_k (Eq. 5).
  Vec3<S> c = mi.first_moment;
  Vec6<S> E_change = Vec6<S>::Zero();
  for (int k = 0; k < n; ++k) {
    c += eta[k] * S1.col(k);
    E_change += eta[k] * (A.col(k) + D.col(k));
  }
  // M_we flattened: Q_k = angular_coupling_linear's columns k n_m .. k n_m +
  // n_m - 1 are 3 n_m contiguous values, so vec(M_we) = vec(H0) + [vec(Q_0)
  // ... vec(Q_n-1)] eta, one matrix-vector product.
  // With N fixed, M_we, G' and nu live in local storage (registers or the
  // stack, where no store to Data's heap memory can alias them) and G' and
  // nu are stored once at the end; without, in Data (no allocation).
  constexpr bool fixed = N != Eigen::Dynamic;
  Eigen::Matrix<S, 3, N> local_coupling;  // N dynamic: empty
  Eigen::Matrix<S, N, 6> local_gain;
  Modes local_innovation;
  S* const coupling = fixed ? local_coupling.data() : fd.deformed_angular_coupling.data();
  affine_columns<times_mode_count(3, N), N>(mi.angular_coupling.data(), mi.angular_coupling_linear.data(), 3 * n, n,
                                            eta.data(), coupling);
  const Eigen::Map<const Eigen::Matrix<S, 3, N>> M_we(coupling, 3, n);
  const Mat3<S> E = mi.second_moment + unpacked_symmetric(E_change);
  const Mat3<S> M_ww = E.trace() * Mat3<S>::Identity() - E + mi.rotary_inertia;  // Eq. (4)

  // Bias b = [b_V; b_e]: Eqs. (8), (9) and the gyroscopic term, plus K eta + C eta_dot.
  Vec6<S>& b = d.sweep.body_bias_force[i];
  VecX<S>& b_e = fd.modal_bias;
  if (v) {
    const Eigen::Map<const Modes> eta_dot(v + m.modal_v_index(body), n);
    const Vec3<S> omega = V.template head<3>(), vel = V.template tail<3>();
    Vec6<S> momentum;  // (M w)_V = M_VV V + M_Ve eta_dot
    momentum.template head<3>() = M_ww * omega + c.cross(vel);
    momentum.template tail<3>() = mi.mass * vel - c.cross(omega);
    for (int k = 0; k < n; ++k) {
      momentum.template head<3>() += eta_dot[k] * M_we.col(k);
      momentum.template tail<3>() += eta_dot[k] * S1.col(k);
    }
    mi.template inertial_bias<N>(modal_velocities(m, body, v), V, momentum, fd.second_moment_rates, fd.bias);
    b = fd.bias.template head<6>();
    modal_bias_with_elastic_forces<N>(m.flexible_body(body), fd.bias, eta, eta_dot, b_e);
  } else {
    b.setZero();
    b_e.setZero();
  }
  if (external) b -= *external;

  // Elimination: G' = [Y W], nu, P^ and z^.
  const Eigen::Map<const Eigen::Matrix<S, N, N>> M_inv(mi.modal_mass_inverse.data(), n, n);
  const Eigen::Map<const Eigen::Matrix<S, N, 3>> W(mi.modal_first_moment_gain.data(), n, 3);
  Eigen::Map<Eigen::Matrix<S, N, 6>> gain_transpose(fixed ? local_gain.data() : fd.gain_transpose.data(), n, 6);
  Eigen::Map<Modes> nu(fixed ? local_innovation.data() : fd.innovation.data(), n);
  const S* modal_force = u + m.modal_v_index(body);
  for (int r = 0; r < n; ++r) {
    Vec3<S> y = Vec3<S>::Zero();
    S x(0);
    for (int k = 0; k < n; ++k) {
      y += M_inv(r, k) * M_we.col(k);
      x += M_inv(r, k) * (modal_force[k] - b_e[k]);
    }
    gain_transpose.template block<1, 3>(r, 0) = y.transpose();
    gain_transpose.template block<1, 3>(r, 3) = W.row(r);
    nu[r] = x;
  }
  Mat3<S> angular = M_ww, cross = skew(c);
  Vec3<S> z_angular = b.template head<3>(), z_linear = b.template tail<3>();
  for (int k = 0; k < n; ++k) {
    const Vec3<S> m_k = M_we.col(k);
    angular.noalias() -= m_k * gain_transpose.template block<1, 3>(k, 0);
    cross.noalias() -= m_k * W.row(k);
    z_angular += nu[k] * m_k;
    z_linear += nu[k] * S1.col(k);
  }
  P.template topLeftCorner<3, 3>() = angular;
  P.template topRightCorner<3, 3>() = cross;
  P.template bottomLeftCorner<3, 3>() = cross.transpose();
  P.template bottomRightCorner<3, 3>() = mi.translational_appendage_inertia;
  z << z_angular, z_linear;
  if constexpr (fixed) {
    fd.gain_transpose = local_gain;
    fd.innovation = local_innovation;
  }
}

// Calls f(std::integral_constant<int, N>) with N = n when 1 <= n <= Max, else
// with N = Eigen::Dynamic.
template <int Count, int Max, class F>
SOADYN_ALWAYS_INLINE void with_mode_count(int n, F&& f) {
  if constexpr (Count > Max)
    f(std::integral_constant<int, Eigen::Dynamic>{});
  else if (n == Count)
    f(std::integral_constant<int, Count>{});
  else
    with_mode_count<Count + 1, Max>(n, f);
}

}  // namespace detail

// The update's signature (appendage_update below).
template <class S>
using AppendageUpdateFunction = void(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const ModalIntegrals<S>& mi,
                                   const S* q, const S* v, const S* u, const Vec6<S>* external, const Vec6<S>& V,
                                   Mat6<S>& P, Vec6<S>& z);

// The double-precision kernel of the appendages' update on this processor:
// "AVX2 FMA" (the same code compiled for AVX2 with fused multiply-adds,
// where the processor has them: its 4-wide registers hold four modes) or
// "baseline" (x86-64's SSE2, or any other target). Chosen on the first call,
// or by this question if no call came first, as the mass matrix's
// (crba.hpp): results agree bit for bit only between processes that use the
// same one.
const char* appendage_kernel();

namespace detail {
// The update for double and float, compiled in appendage_update.cpp (double:
// the chosen kernel).
AppendageUpdateFunction<double> compiled_appendage_update;
AppendageUpdateFunction<float> compiled_appendage_update;

// A kernel of the update for double.
struct AppendageKernel {
  const char* name;
  AppendageUpdateFunction<double>* run;
};
// Every kernel of this build that this processor can run, the chosen one
// first (the tests compare them all).
std::vector<AppendageKernel> available_appendage_kernels();
}  // namespace detail

// P^ and z^ of flexible appendage i in the frame of its modal integrals
// `mi` (the body's own, or the same body described in its root's frame:
// ModelTpl::root_frame_integrals), given its velocity V and the external
// wrench on it (null: none) in that frame; leaves b_V - f_ext in
// sweep.body_bias_force[i], and G' in gain_transpose and nu in innovation
// of its FlexibleBodyData (modal_accelerations reads them, with the
// acceleration in the same frame). `v` null: zero velocity with no elastic
// force (impulse problems), as flexible_bias_update. On packets, each lane
// runs the double kernel (packet_appendage_update.hpp).
template <class S>
inline void appendage_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const ModalIntegrals<S>& mi,
                           const S* q, const S* v, const S* u, const Vec6<S>* external, const Vec6<S>& V, Mat6<S>& P,
                           Vec6<S>& z) {
  if constexpr (std::is_same_v<S, double> || std::is_same_v<S, float>)
    detail::compiled_appendage_update(m, d, i, mi, q, v, u, external, V, P, z);
  else if constexpr (is_packet_scalar_v<S>)
    detail::packet_appendage_update(m, d, i, mi, q, v, u, external, V, P, z);
  else
    detail::appendage_terms<Eigen::Dynamic>(m, d, i, mi, q, v, u, external, V, P, z);
}

}  // namespace soadyn
