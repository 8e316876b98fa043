// Flexible body validation and evaluation (templated implementation of
// flexible_body.hpp).
#pragma once
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include "soadyn/flex/flexible_body.hpp"
#include "soadyn/flex/modal_integrals.hxx"
#include "soadyn/spatial/lie.hpp"
#include "soadyn/core/validation.hpp"

namespace soadyn {

namespace flex_detail {

[[noreturn]] inline void fail(const std::string& what) {
  throw std::invalid_argument("flexible body: " + what);
}

inline std::string node_name(int j) { return "node " + std::to_string(j); }

template <class S>
std::string str(const S& x) {
  return detail::to_text(x);
}

template <class S>
S tolerance() {
  return detail::validation_tolerance<S>();
}

template <class Derived>
void check_finite(const Eigen::MatrixBase<Derived>& a, const std::string& what) {
  for (Eigen::Index c = 0; c < a.cols(); ++c)
    for (Eigen::Index r = 0; r < a.rows(); ++r)
      if (!std::isfinite(static_cast<double>(a(r, c))))
        fail(what + " entry " +
             (a.cols() == 1 ? std::to_string(r) : "(" + std::to_string(r) + ", " + std::to_string(c) + ")") +
             " is " + (std::isnan(static_cast<double>(a(r, c))) ? "NaN" : "infinite"));
}

template <class S>
S largest_magnitude(const MatX<S>& a) {
  return a.size() ? a.cwiseAbs().maxCoeff() : S(0);
}

template <class S>
void check_symmetric(const MatX<S>& a, const std::string& what) {
  const S tol = tolerance<S>() * largest_magnitude(a);
  for (Eigen::Index c = 0; c < a.cols(); ++c)
    for (Eigen::Index r = c + 1; r < a.rows(); ++r) {
      using std::abs;
      if (abs(a(r, c) - a(c, r)) > tol)
        fail(what + " is not symmetric: entry (" + std::to_string(r) + ", " + std::to_string(c) + ") = " +
             str(a(r, c)) + " but (" + std::to_string(c) + ", " + std::to_string(r) + ") = " + str(a(c, r)));
    }
}

// Eigenvalues (ascending) of the symmetric part of a.
template <class S>
VecX<S> symmetric_eigenvalues(const MatX<S>& a) {
  const MatX<S> sym = S(0.5) * (a + a.transpose());
  return Eigen::SelfAdjointEigenSolver<MatX<S>>(sym, Eigen::EigenvaluesOnly).eigenvalues();
}

// A square, finite, symmetric positive semidefinite n x n matrix.
template <class S>
void check_symmetric_psd(const MatX<S>& a, int n, const std::string& what) {
  if (a.rows() != n || a.cols() != n)
    fail(what + " has shape (" + std::to_string(a.rows()) + ", " + std::to_string(a.cols()) + "), expected (" +
         std::to_string(n) + ", " + std::to_string(n) + ")");
  check_finite(a, what);
  check_symmetric(a, what);
  if (n == 0) return;
  const VecX<S> lambda = symmetric_eigenvalues(a);
  if (lambda[0] < -tolerance<S>() * largest_magnitude(a))
    fail(what + " is not positive semidefinite: smallest eigenvalue " + str(lambda[0]));
}

// Rotary inertia of node j: symmetric, principal moments >= 0 and obeying
// the triangle inequality I_a + I_b >= I_c of every real mass distribution.
template <class S>
void check_rotary_inertia(int j, const Mat3<S>& J) {
  const std::string what = node_name(j) + " rotary inertia";
  check_finite(J, what);
  const MatX<S> dynamic = J;
  check_symmetric(dynamic, what);
  const VecX<S> moments = symmetric_eigenvalues(dynamic);
  const S tol = tolerance<S>() * largest_magnitude(dynamic);
  if (moments[0] < -tol) fail(what + " has a negative principal moment " + str(moments[0]));
  if (moments[0] + moments[1] < moments[2] - tol)
    fail(what + " violates the triangle inequality: principal moments " + str(moments[0]) + ", " +
         str(moments[1]) + ", " + str(moments[2]));
}

template <class S>
void check_node(int j, const FlexibleNode<S>& node, int n_modes) {
  const std::string name = node_name(j);
  check_finite(node.position, name + " position");
  if (!std::isfinite(static_cast<double>(node.mass))) fail(name + " mass is not finite");
  if (node.mass < S(0)) fail(name + " has negative mass " + str(node.mass));
  check_rotary_inertia(j, node.rotary_inertia);
  if (node.mode_shape.cols() != n_modes)
    fail(name + " mode shape has " + std::to_string(node.mode_shape.cols()) + " columns, expected n_modes = " +
         std::to_string(n_modes) + " (the size of the stiffness matrix)");
  for (int k = 0; k < n_modes; ++k)
    for (int row = 0; row < 6; ++row)
      if (!std::isfinite(static_cast<double>(node.mode_shape(row, k))))
        fail(name + " mode shape of mode " + std::to_string(k) + " is not finite in row " + std::to_string(row) +
             (row < 3 ? " (rotation)" : " (translation)"));
}

// The modal mass must be positive definite: the clamped eigenproblem and
// the recursion's modal pivot (D = M_ee - ...) invert it.
template <class S>
void check_modal_mass(const FlexibleNodes<S>& nodes, int n_modes) {
  if (n_modes == 0) return;
  const MatX<S> mass = modal_mass_matrix(nodes, n_modes);
  const S scale = largest_magnitude(mass);
  for (int k = 0; k < n_modes; ++k)
    if (!(mass(k, k) > tolerance<S>() * scale))
      fail("mode " + std::to_string(k) + " has no modal mass: it moves no node with mass or rotary inertia");
  const VecX<S> lambda = symmetric_eigenvalues(mass);
  if (!(lambda[0] > tolerance<S>() * lambda[n_modes - 1]))
    fail("modal mass matrix is singular (smallest eigenvalue " + str(lambda[0]) +
         "): the mode shapes are linearly dependent over the nodes with mass");
}

// Replaces the rotary inertias, K and C by their symmetric parts (they are
// symmetric to the validation tolerance), so that M(eta) is exactly symmetric.
// Halved before they are added: (a + a')/2 would overflow for entries past
// half the largest double.
template <class S>
void symmetrize(FlexibleBodyDescription<S>& d) {
  for (FlexibleNode<S>& node : d.nodes) {
    const Mat3<S> J = node.rotary_inertia;
    node.rotary_inertia = S(0.5) * J + S(0.5) * J.transpose();
  }
  d.stiffness = (S(0.5) * d.stiffness + S(0.5) * d.stiffness.transpose()).eval();
  d.damping = (S(0.5) * d.damping + S(0.5) * d.damping.transpose()).eval();
}

inline void check_attachments(const std::map<std::string, int>& attachments, int n_nodes) {
  for (const auto& [name, j] : attachments) {
    if (name.empty()) fail("an attachment has an empty name");
    if (j < 0 || j >= n_nodes)
      fail("attachment '" + name + "' refers to node " + std::to_string(j) + ", but the body has " +
           std::to_string(n_nodes) + " nodes");
  }
}

}  // namespace flex_detail

template <class S>
void FlexibleBodyDescription<S>::validate() const {
  using namespace flex_detail;
  if (nodes.empty()) fail("needs at least one node");
  if (stiffness.rows() != stiffness.cols())
    fail("stiffness matrix K has shape (" + std::to_string(stiffness.rows()) + ", " +
         std::to_string(stiffness.cols()) + "), expected square");
  const int n = n_modes();
  for (int j = 0; j < n_nodes(); ++j) check_node(j, nodes[static_cast<std::size_t>(j)], n);
  check_symmetric_psd(stiffness, n, "stiffness matrix K");
  check_symmetric_psd(damping, n, "damping matrix C");
  S total_mass(0);
  for (const FlexibleNode<S>& node : nodes) total_mass += node.mass;
  if (!(total_mass > S(0))) fail("no node has mass");
  check_modal_mass(nodes, n);
  check_attachments(attachments, n_nodes());
}

namespace flex_detail {

// Whether the symmetric positive semidefinite x couples no two modes beyond
// rounding: |x_kl| <= 64 eps sqrt(x_kk x_ll) for k != l (|x_kl| / sqrt(x_kk
// x_ll) is at most 1 for such a matrix). Modal stiffness and damping from a
// quadrature or an eigensolver carry couplings of a few eps there (the
// cantilever beam's K: 5e-16); dropping one changes the elastic force on
// mode k by at most 64 eps sqrt(x_kk x_ll) |eta_l|.
template <class S>
bool uncoupled_at_rounding_level(const MatX<S>& x) {
  using std::abs;
  using std::sqrt;
  const S tolerance = S(64) * std::numeric_limits<S>::epsilon();
  for (Eigen::Index l = 0; l < x.cols(); ++l)
    for (Eigen::Index k = 0; k < x.rows(); ++k)
      if (k != l && abs(x(k, l)) > tolerance * sqrt(abs(x(k, k) * x(l, l)))) return false;
  return true;
}

}  // namespace flex_detail

template <class S>
FlexibleBodyTpl<S>::FlexibleBodyTpl(FlexibleBodyDescription<S> description)
    : description_(std::move(description)) {
  description_.validate();
  flex_detail::symmetrize(description_);
  integrals_ = ModalIntegrals<S>::from_nodes(description_.nodes, n_modes());
  diagonal_elastic_forces_ =
      flex_detail::uncoupled_at_rounding_level(description_.stiffness) &&
      flex_detail::uncoupled_at_rounding_level(description_.damping);
}

template <class S>
int FlexibleBodyTpl<S>::attachment_node(const std::string& name) const {
  const auto it = description_.attachments.find(name);
  return it == description_.attachments.end() ? -1 : it->second;
}

template <class S>
MatX<S> FlexibleBodyTpl<S>::augmented_mass_matrix(const Eigen::Ref<const VecX<S>>& eta) const {
  MatX<S> out(6 + n_modes(), 6 + n_modes());
  integrals_.augmented_mass_matrix(eta, out);
  return out;
}

template <class S>
S FlexibleBodyTpl<S>::strain_energy(const Eigen::Ref<const VecX<S>>& eta) const {
  return S(0.5) * eta.dot(description_.stiffness * eta);
}

template <class S>
Transform<S> FlexibleBodyTpl<S>::node_pose(int j, const Eigen::Ref<const VecX<S>>& eta) const {
  const FlexibleNode<S>& n = node(j);
  const Vec3<S> rotation_vector = n.rotation_shape() * eta;
  Transform<S> pose;
  pose.rotation = quaternion_rotation(quaternion_exp(rotation_vector).data());
  pose.translation = n.position + n.translation_shape() * eta;
  return pose;
}

template <class S>
Transform<S> FlexibleBodyTpl<S>::node_motion(int j, const Eigen::Ref<const VecX<S>>& eta,
                                             Eigen::Ref<ModeShape<S>> subspace, const S* eta_dot, Vec6<S>* bias) const {
  const FlexibleNode<S>& n = node(j);
  Vec3<S> theta;
  theta.noalias() = n.rotation_shape() * eta;
  Transform<S> pose;
  pose.rotation = quaternion_rotation(quaternion_exp(theta).data());
  pose.translation = n.position;
  pose.translation.noalias() += n.translation_shape() * eta;
  const Mat3<S> Jr = so3_right_jacobian(theta);
  subspace.template topRows<3>().noalias() = Jr * n.rotation_shape();  // Eq. (10)
  subspace.template bottomRows<3>().noalias() = pose.rotation.transpose() * n.translation_shape();
  if (eta_dot && bias) {  // Eq. (11)
    const Eigen::Map<const VecX<S>> rate(eta_dot, n_modes());
    Vec3<S> theta_dot, p_dot;
    theta_dot.noalias() = n.rotation_shape() * rate;
    p_dot.noalias() = n.translation_shape() * rate;
    const Vec3<S> omega = Jr * theta_dot;
    *bias << so3_right_jacobian_rate(theta, theta_dot), -omega.cross(pose.rotation.transpose() * p_dot);
  }
  return pose;
}

template <class S>
void FlexibleBodyTpl<S>::node_load(int j, const Eigen::Ref<const VecX<S>>& eta, const Vec6<S>& w, Vec6<S>& body_wrench,
                                   Eigen::Ref<VecX<S>> modal) const {
  const FlexibleNode<S>& n = node(j);
  const Transform<S> pose = node_pose(j, eta);
  body_wrench = pose.force_to_parent(w);
  const Mat3<S> Jr = so3_right_jacobian(Vec3<S>(n.rotation_shape() * eta));
  const Vec3<S> torque_in_modes = Jr.transpose() * w.template head<3>();  // Psi_j' w, Eq. (10)
  const Vec3<S> force_in_body = pose.rotation * w.template tail<3>();
  for (int k = 0; k < n_modes(); ++k)
    modal[k] = n.rotation_shape().col(k).dot(torque_in_modes) + n.translation_shape().col(k).dot(force_in_body);
}

template <class S>
VecX<S> FlexibleBodyTpl<S>::clamped_natural_frequencies() const {
  using std::sqrt;
  if (n_modes() == 0) return VecX<S>();
  // K x = w^2 M_ee x; M_ee is positive definite (validated).
  const Eigen::GeneralizedSelfAdjointEigenSolver<MatX<S>> solver(stiffness(), modal_mass(), Eigen::EigenvaluesOnly);
  VecX<S> omega(n_modes());
  for (int k = 0; k < n_modes(); ++k) omega[k] = sqrt(std::max(S(0), solver.eigenvalues()[k]));
  return omega;
}

}  // namespace soadyn
