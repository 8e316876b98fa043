// Per-body updates for flexible bodies (flex/flexible_body.hpp) in the sweeps
// of body_updates.hpp (body frames) and tree_frame_updates.hpp (tree frames). The
// algorithms instantiate their sweeps with Flex = false (no flexible body in
// the model: every function below reduces to its rigid counterpart at
// compile time, so rigid scenes pay nothing) and Flex = true. Bodies placed on
// a node of a flexible body (J_c below) run in body frames only.
//
// A flexible body k carries the augmented velocity w = [V; eta_dot] and the
// augmented equations of motion M(eta) dw/dt + b = [f; u_modal]
// (modal_integrals.hpp, Eqs. 7-9), with the elastic forces K eta + C eta_dot
// in the modal rows of b. A child c placed on node j of k moves with
//   V(c) = X(c,k) V(k) + Psi_c eta_dot(k) + H*(c) qdot(c),
// Psi_c the node's deformation subspace (flexible_body.hpp, Eq. 10) in c's
// frame, so the inter-body operator of Eq. 1 of Jain & Rodriguez 1993 becomes
// J_c = [X(c,k), Psi_c] and the Coriolis term a(c) gains
// (X(c,k) V(k)) x (Psi_c eta_dot) plus the node's own velocity-product
// acceleration (Eq. 11). This is the augmented-body recursion of Jain &
// Rodriguez, JGCD 15(6), 1992: in the inward sweep the children's articulated
// inertias enter k's augmented (6 + n_m) articulated inertia through J_c'
// P+ J_c, the modal DOFs (always regular) are eliminated first,
//   P^ = P_VV - P_Ve P_ee^-1 P_eV,  z^ = z_V + P_Ve P_ee^-1 (u_modal - z_e),
// and the hinge is then processed exactly as for a rigid body with (P^, z^);
// in the outward sweep eta_ddot = P_ee^-1 (u_modal - z_e) - P_ee^-1 P_eV alpha(k).
#pragma once
#include "soadyn/linalg/small_cholesky.hpp"
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

template <class S>
inline Eigen::Map<const VecX<S>> modal_coordinates(const ModelTpl<S>& m, int body, const S* q) {
  return Eigen::Map<const VecX<S>>(q + m.modal_q_index(body), m.n_modes[static_cast<std::size_t>(body)]);
}
template <class S>
inline Eigen::Map<const VecX<S>> modal_velocities(const ModelTpl<S>& m, int body, const S* v) {
  return Eigen::Map<const VecX<S>>(v + m.modal_v_index(body), m.n_modes[static_cast<std::size_t>(body)]);
}
template <class S>
inline FlexibleBodyData<S>& flexible_data(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t body) {
  return d.sweep.flexible[static_cast<std::size_t>(m.flexible_index[body])];
}

// Node kinematics of body i placed on a flexible parent's node: on entry
// pose_in_parent[i] holds the pose in the node frame; on return the pose in
// the parent's body frame, sweep.attachment_subspace[i] = Psi (Eq. 10) and,
// with velocities, sweep.attachment_bias[i] (Eq. 11), both in body i's frame.
template <class S>
inline void attachment_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  const int p = m.parent[i];
  const FlexibleBodyTpl<S>& parent = m.flexible_body(p);
  const auto eta = modal_coordinates(m, p, q);
  Mat6X<S>& shape = d.sweep.attachment_subspace[i];
  Vec6<S> node_bias;
  const Transform<S> node =
      parent.node_motion(m.attachment_node[i], eta, shape, v ? v + m.modal_v_index(p) : nullptr, &node_bias);
  const Transform<S> in_node = d.pose_in_parent[i];
  for (Eigen::Index c = 0; c < shape.cols(); ++c) shape.col(c) = in_node.motion_to_child(Vec6<S>(shape.col(c)));
  if (v) d.sweep.attachment_bias[i] = in_node.motion_to_child(node_bias);
  d.pose_in_parent[i] = node * in_node;
}

template <bool Flex, class S>
inline void body_joint_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v) {
  detail::joint_update(m, d, i, q, v);
  if constexpr (Flex)
    if (m.attachment_node[i] >= 0) attachment_update(m, d, i, q, v);
}

// Velocity and Coriolis term of body i, body frame (Jain & Rodriguez 1993,
// Eq. 1, with J_c for a body on a node).
template <bool Flex, class S>
inline void body_velocity_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* v) {
  if constexpr (Flex) {
    if (m.attachment_node[i] >= 0) {
      SweepData<S>& w = d.sweep;
      const int p = m.parent[i];
      const Vec6<S> joint_velocity = detail::subspace_times(w.body_subspace[i], v + m.v_index[i]);
      const Vec6<S> carried = d.pose_in_parent[i].motion_to_child(d.body_velocity[static_cast<std::size_t>(p)]);
      Vec6<S> deformation;
      deformation.noalias() = w.attachment_subspace[i] * modal_velocities(m, p, v);
      d.body_velocity[i] = carried + deformation + joint_velocity;
      w.body_coriolis[i] = w.body_joint_bias[i] + motion_cross(d.body_velocity[i], joint_velocity) +
                           motion_cross(carried, deformation) + w.attachment_bias[i];
      return;
    }
  }
  detail::velocity_update(m, d, i, v);
}

// M(eta) of flexible body i into its FlexibleBodyData.
template <class S>
inline void flexible_inertia_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q) {
  m.flexible_body(static_cast<int>(i)).augmented_mass_matrix(modal_coordinates(m, static_cast<int>(i), q), flexible_data(m, d, i).mass);
}

// Modal rows of the bias of a flexible body: the inertial bias's (the tail of
// `bias`, modal_integrals.hpp) plus the elastic forces K eta + C eta_dot,
// by columns (n_m is small: no matrix-vector kernel). N: n_m at compile time,
// or Eigen::Dynamic.
template <int N = Eigen::Dynamic, class S, class Eta, class EtaDot>
inline void modal_bias_with_elastic_forces(const FlexibleBodyTpl<S>& body, const VecX<S>& bias, const Eta& eta,
                                           const EtaDot& eta_dot, VecX<S>& modal_bias) {
  const int n = N == Eigen::Dynamic ? body.n_modes() : N;
  const MatX<S>& K = body.stiffness();
  const MatX<S>& C = body.damping();
  for (int k = 0; k < n; ++k) modal_bias[k] = bias[6 + k];
  if (body.diagonal_elastic_forces()) {
    for (int k = 0; k < n; ++k) modal_bias[k] += K(k, k) * eta[k] + C(k, k) * eta_dot[k];
    return;
  }
  for (int l = 0; l < n; ++l)
    for (int k = 0; k < n; ++k) modal_bias[k] += K(k, l) * eta[l] + C(k, l) * eta_dot[l];
}

// Bias of flexible body i: sweep.body_bias_force[i] = b_V - f_ext and
// modal_bias = b_e + K eta + C eta_dot (Eqs. 8-9), in the body frame, given the body-frame
// velocity; zero velocity (v null) leaves only -f_ext (impulse problems and
// mass-matrix columns: no elastic impulse).
template <class S>
inline void flexible_bias_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                               const Vec6<S>& body_velocity, const S* f_ext) {
  const int b = static_cast<int>(i);
  FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  if (v) {
    const FlexibleBodyTpl<S>& body = m.flexible_body(b);
    const auto eta = modal_coordinates(m, b, q);
    const auto eta_dot = modal_velocities(m, b, v);
    const ModalIntegrals<S>& mi = body.modal_integrals();
    mi.second_moment_rates(eta, fd.second_moment_rates);
    Vec6<S> momentum;  // (M w)_V
    momentum.noalias() = fd.mass.template topLeftCorner<6, 6>() * body_velocity;
    momentum.noalias() += fd.mass.topRightCorner(6, body.n_modes()) * eta_dot;
    mi.inertial_bias(eta_dot, body_velocity, momentum, fd.second_moment_rates, fd.bias);
    d.sweep.body_bias_force[i] = fd.bias.template head<6>();
    modal_bias_with_elastic_forces(body, fd.bias, eta, eta_dot, fd.modal_bias);
  } else {
    d.sweep.body_bias_force[i].setZero();
    fd.modal_bias.setZero();
  }
  if (f_ext) d.sweep.body_bias_force[i] -= Eigen::Map<const Vec6<S>>(f_ext + 6 * i);
}

// Velocity, Coriolis term and bias of body i (motion_update with flexible bodies).
template <bool Flex, class S>
inline void body_motion_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* q, const S* v,
                             const S* f_ext) {
  if constexpr (Flex) {
    if (m.is_flexible(static_cast<int>(i))) {
      if (v)
        body_velocity_update<true>(m, d, i, v);
      else
        d.body_velocity[i].setZero(), d.sweep.body_coriolis[i].setZero();
      flexible_inertia_update(m, d, i, q);
      flexible_bias_update(m, d, i, q, v, d.body_velocity[i], f_ext);
      return;
    }
    if (v) {
      body_velocity_update<true>(m, d, i, v);
      detail::bias_force_update(m, d, i, f_ext);
      return;
    }
  }
  detail::motion_update(m, d, i, v, f_ext);
}

// Starts body i's articulated inertia and bias from its own mass and bias, body frame.
template <bool Flex, class S>
inline void init_articulated(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i) {
  d.sweep.body_bias_and_children_z[i] = d.sweep.body_bias_force[i];
  if constexpr (Flex) {
    if (m.is_flexible(static_cast<int>(i))) {
      FlexibleBodyData<S>& fd = flexible_data(m, d, i);
      const Eigen::Index n = fd.modal_bias.size();
      d.sweep.body_articulated_inertia[i] = fd.mass.template topLeftCorner<6, 6>();
      fd.coupling = fd.mass.topRightCorner(6, n);
      fd.modal_inertia = fd.mass.bottomRightCorner(n, n);
      fd.modal_bias_and_children_z = fd.modal_bias;
      return;
    }
  }
  d.sweep.body_articulated_inertia[i] = m.inertia[i];
}

// Adds body i's P+ and z+ to its parent: J' P+ J and J' z+ (Jain & Rodriguez
// 1993, Eq. 14, with J), body frames.
template <bool Flex, class S>
inline void push_articulated(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Mat6<S>& P_plus,
                             const Vec6<S>& z_plus) {
  detail::push_articulated_to_parent(m, d, i, P_plus, z_plus);
  if constexpr (Flex) {
    if (m.attachment_node[i] >= 0) {
      FlexibleBodyData<S>& fp = flexible_data(m, d, static_cast<std::size_t>(m.parent[i]));
      const Mat6X<S>& psi = d.sweep.attachment_subspace[i];
      for (Eigen::Index c = 0; c < psi.cols(); ++c) {
        const Vec6<S> f = P_plus * psi.col(c);
        fp.coupling.col(c) += d.pose_in_parent[i].force_to_parent(f);
        fp.modal_inertia.col(c).noalias() += psi.transpose() * f;
      }
      fp.modal_bias_and_children_z.noalias() += psi.transpose() * z_plus;
    }
  }
}

// Eliminates the modal DOFs of flexible body i (they are regular): replaces
// its articulated inertia and bias by P^ and z^ (see the top of this file).
// `u` holds the modal forces at body i's modal DOFs. Returns the DOF of a
// singular modal block, or -1.
template <class S>
inline int eliminate_modal_coordinates(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u) {
  FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  const int first = m.modal_v_index(static_cast<int>(i));
  const Eigen::Index n = fd.modal_bias.size();
  const S threshold = S(16) * std::numeric_limits<S>::epsilon() * fd.modal_inertia.diagonal().cwiseAbs().maxCoeff();
  const int bad = cholesky_in_place(fd.modal_inertia, threshold);  // P_ee = L L', in place
  if (bad >= 0) return first + bad;
  fd.gain_transpose = fd.coupling.transpose();
  cholesky_solve_in_place(fd.modal_inertia, fd.gain_transpose);
  fd.innovation = Eigen::Map<const VecX<S>>(u + first, n) - fd.modal_bias_and_children_z;
  cholesky_solve_in_place(fd.modal_inertia, fd.innovation);
  for (Eigen::Index k = 0; k < n; ++k) {  // P -= coupling gain' and z += coupling innovation, as 6-vector updates
    const Vec6<S> g = fd.gain_transpose.row(k).transpose();
    d.sweep.body_articulated_inertia[i].noalias() -= fd.coupling.col(k) * g.transpose();
    d.sweep.body_bias_and_children_z[i] += fd.innovation[k] * fd.coupling.col(k);
  }
  return -1;
}

// Modal accelerations of flexible body i once its acceleration alpha (body
// frame) is known, for both kinds of sweep: eta_ddot = nu - G' alpha, i.e.
// P_ee^-1 (u_modal - z_e) - P_ee^-1 P_eV alpha; the modal forces are u's.
template <class S>
inline void modal_accelerations(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                const Vec6<S>& alpha) {
  const FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  const int first = m.modal_v_index(static_cast<int>(i));
  const Eigen::Index n = fd.innovation.size();
  for (Eigen::Index r = 0; r < n; ++r) {
    d.qdd[first + r] = fd.innovation[r] - fd.gain_transpose.row(r).dot(alpha.transpose());
    d.tau[first + r] = u[first + r];
  }
}

// Parent acceleration seen by body i: X alpha(parent), plus Psi eta_ddot(parent)
// on a flexible parent's node (`qdd` null: zero accelerations).
template <bool Flex, class S>
inline Vec6<S> body_parent_acceleration(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i,
                                        const Vec6<S>& world_acc, const S* qdd) {
  Vec6<S> a = detail::parent_acceleration(m, d, i, world_acc);
  if constexpr (Flex)
    if (qdd && m.attachment_node[i] >= 0)
      a.noalias() += d.sweep.attachment_subspace[i] * modal_velocities(m, m.parent[i], qdd);
  return a;
}

// Newton-Euler force of flexible body i from alpha(i) and eta_ddot, body
// frame: [f; modal force] = M(eta) [alpha; eta_ddot] + bias. The modal force
// accumulates the children's Psi' f (push_body_force) until the inward sweep
// reaches body i.
template <class S>
inline void flexible_newton_euler(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* qdd) {
  FlexibleBodyData<S>& fd = flexible_data(m, d, i);
  const Eigen::Index n = fd.modal_bias.size();
  const Vec6<S>& alpha = d.body_acceleration[i];
  d.hinge_force[i] = d.sweep.body_bias_force[i];
  d.hinge_force[i].noalias() += fd.mass.template topLeftCorner<6, 6>() * alpha;
  fd.modal_force = fd.modal_bias;
  fd.modal_force.noalias() += fd.mass.bottomLeftCorner(n, 6) * alpha;
  if (qdd) {
    const auto eta_ddot = modal_velocities(m, static_cast<int>(i), qdd);
    d.hinge_force[i].noalias() += fd.mass.topRightCorner(6, n) * eta_ddot;
    fd.modal_force.noalias() += fd.mass.bottomRightCorner(n, n) * eta_ddot;
  }
}

// Adds body i's hinge force f to its parent: X* f, and Psi' f to the
// parent's modal force when i sits on a node.
template <bool Flex, class S>
inline void push_body_force(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const Vec6<S>& f) {
  detail::push_force_to_parent(m, d, i, f);
  if constexpr (Flex)
    if (m.attachment_node[i] >= 0)
      flexible_data(m, d, static_cast<std::size_t>(m.parent[i])).modal_force.noalias() +=
          d.sweep.attachment_subspace[i].transpose() * f;
}

}  // namespace soadyn
