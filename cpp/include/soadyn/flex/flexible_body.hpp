// Modal flexible body: a rigid reference frame at the body's inboard hinge
// plus n_m modal coordinates eta (small deformation, linear modes), as in
// Jain & Rodriguez, "Recursive flexible multibody system dynamics using
// spatial operators", JGCD 15(6), 1992.
//
// The body is a lumped model: nodes j = 0..N-1 (flexible_node.hpp) with
// point masses m_j, rotary inertias J_j and mode shapes Phi_j = [Phi_r,j;
// Phi_t,j]. At eta, node j sits at r_j + Phi_t,j eta and is rotated by
// exp([Phi_r,j eta]x). Its velocity relative to the reference frame is
// Phi_t,j eta_dot and its angular velocity Phi_r,j eta_dot.
//
// Modelling choice (rotary inertia): J_j keeps its undeformed orientation
// in the kinetic energy, i.e. the node spins with omega + Phi_r,j eta_dot
// but J_j is not rotated by exp([Phi_r,j eta]x). This is the first-order
// (small deformation) model consistent with linear modes; it makes the
// modal mass M_ee constant and the kinetic energy exactly quadratic in eta
// (modal_integrals.hpp, Eq. (1)).
//
// Generalized velocity of the body: [V; eta_dot], V = [omega; v] the
// body-frame spatial velocity of the reference frame (DESIGN.md Sec. 2).
// Its kinetic energy is 1/2 [V; eta_dot]' M(eta) [V; eta_dot] with M from
// the modal integrals, and its strain energy 1/2 eta' K eta.
//
// Attachment nodes are named nodes where children attach and loads apply;
// they may be massless.
#pragma once
#include <map>
#include <string>
#include <utility>
#include "soadyn/flex/modal_integrals.hpp"
#include "soadyn/spatial/transform.hpp"

namespace soadyn {

// Input of a flexible body: the lumped nodes, modal stiffness K and modal
// damping C (n_m x n_m, symmetric positive semidefinite), and the named
// attachment nodes. n_m is the size of K.
template <class S>
struct FlexibleBodyDescription {
  FlexibleNodes<S> nodes;
  MatX<S> stiffness;
  MatX<S> damping;
  std::map<std::string, int> attachments;

  int n_nodes() const { return static_cast<int>(nodes.size()); }
  int n_modes() const { return static_cast<int>(stiffness.rows()); }

  // Throws std::invalid_argument naming the item at fault (node, mode,
  // matrix or attachment): wrong sizes, non-finite numbers, negative mass,
  // a rotary inertia that is not symmetric positive semidefinite with
  // principal moments obeying the triangle inequality, K or C not symmetric
  // positive semidefinite, no node with mass, or a singular modal mass
  // (a mode that moves no mass, or linearly dependent modes).
  void validate() const;

  template <class T>
  FlexibleBodyDescription<T> cast() const {
    FlexibleBodyDescription<T> d;
    for (const FlexibleNode<S>& node : nodes) d.nodes.push_back(node.template cast<T>());
    d.stiffness = stiffness.template cast<T>();
    d.damping = damping.template cast<T>();
    d.attachments = attachments;
    return d;
  }
};

// A validated flexible body and its modal integrals, immutable once built
// (like ModelTpl: shareable between threads).
template <class S>
class FlexibleBodyTpl {
 public:
  // Validates `description` (see validate()) and computes the invariants.
  explicit FlexibleBodyTpl(FlexibleBodyDescription<S> description);

  int n_nodes() const { return description_.n_nodes(); }
  int n_modes() const { return description_.n_modes(); }
  const FlexibleBodyDescription<S>& description() const { return description_; }
  const FlexibleNode<S>& node(int j) const { return description_.nodes[static_cast<std::size_t>(j)]; }
  const MatX<S>& stiffness() const { return description_.stiffness; }
  const MatX<S>& damping() const { return description_.damping; }
  // Whether K and C are both diagonal to within rounding (modal damping of
  // uncoupled modes, as most modal models have; flexible_body.hxx): the
  // elastic forces then cost n_m, not n_m^2.
  bool diagonal_elastic_forces() const { return diagonal_elastic_forces_; }
  const std::map<std::string, int>& attachments() const { return description_.attachments; }
  // Node index of the attachment `name`, -1 when absent.
  int attachment_node(const std::string& name) const;

  const ModalIntegrals<S>& modal_integrals() const { return integrals_; }
  const MatX<S>& modal_mass() const { return integrals_.modal_mass; }

  // M(eta), (6 + n_m) square (modal_integrals.hpp). The Ref overload does
  // not allocate; `out` must already be (6 + n_m) x (6 + n_m).
  MatX<S> augmented_mass_matrix(const Eigen::Ref<const VecX<S>>& eta) const;
  void augmented_mass_matrix(const Eigen::Ref<const VecX<S>>& eta, Eigen::Ref<MatX<S>> out) const {
    integrals_.augmented_mass_matrix(eta, out);
  }

  // 1/2 eta' K eta.
  S strain_energy(const Eigen::Ref<const VecX<S>>& eta) const;

  // Pose of node j's frame in the body frame at eta: rotation
  // exp([Phi_r,j eta]x), translation r_j + Phi_t,j eta. The undeformed node
  // frame is parallel to the body frame. Requires 0 <= j < n_nodes().
  Transform<S> node_pose(int j, const Eigen::Ref<const VecX<S>>& eta) const;

  // Motion of node j relative to the body frame, as a child body placed on
  // the node sees it. With theta = Phi_r,j eta and R = exp([theta]x):
  //   relative velocity (node frame)  Psi_j(eta) eta_dot,
  //     Psi_j = [Jr(theta) Phi_r,j; R' Phi_t,j]                            (10)
  //   velocity-product part of the relative acceleration (node frame)
  //     [dJr/dt theta_dot; -(Jr theta_dot) x (R' Phi_t,j eta_dot)]         (11)
  // (Jr: right Jacobian of SO(3), spatial/lie.hpp). node_motion writes
  // Psi_j into `subspace` (6 x n_m), with `eta_dot` and `bias` non-null also
  // Eq. (11) into *bias, and returns node_pose(j, eta); the rotation and Jr
  // are computed once for both. No allocation.
  Transform<S> node_motion(int j, const Eigen::Ref<const VecX<S>>& eta, Eigen::Ref<ModeShape<S>> subspace,
                           const S* eta_dot = nullptr, Vec6<S>* bias = nullptr) const;

  // Generalized force of a wrench w = [torque; force] applied at node j and
  // expressed in the node frame, at eta: by virtual power with the node's
  // velocity X V + Psi_j eta_dot (Eq. 10), the body receives X* w about its
  // origin (body frame; add it to the body's external wrench) and the modes
  // Psi_j' w (add them to the modal DOFs' generalized forces). No allocation;
  // `modal` must have n_modes() entries.
  void node_load(int j, const Eigen::Ref<const VecX<S>>& eta, const Vec6<S>& w, Vec6<S>& body_wrench,
                 Eigen::Ref<VecX<S>> modal) const;

  // Natural frequencies (rad/s, ascending) of the body clamped at its
  // reference frame: sqrt of the generalized eigenvalues of K x = w^2 M_ee x.
  VecX<S> clamped_natural_frequencies() const;

  template <class T>
  FlexibleBodyTpl<T> cast() const {
    return FlexibleBodyTpl<T>(description_.template cast<T>());
  }

  // The same body in scalar T with its invariants converted, not recomputed
  // and not validated again (this body is valid): for scalars the
  // validation's eigen-decompositions do not serve, such as the
  // automatic-differentiation scalar of ModelTpl::cast.
  template <class T>
  FlexibleBodyTpl<T> converted() const {
    FlexibleBodyTpl<T> out;
    out.description_ = description_.template cast<T>();
    out.integrals_ = integrals_.template cast<T>();
    out.diagonal_elastic_forces_ = diagonal_elastic_forces_;
    return out;
  }

 private:
  template <class>
  friend class FlexibleBodyTpl;
  FlexibleBodyTpl() = default;
  FlexibleBodyDescription<S> description_;
  ModalIntegrals<S> integrals_;
  bool diagonal_elastic_forces_ = false;
};

using FlexibleBody = FlexibleBodyTpl<double>;

extern template struct FlexibleBodyDescription<double>;
extern template struct FlexibleBodyDescription<float>;
extern template class FlexibleBodyTpl<double>;
extern template class FlexibleBodyTpl<float>;

}  // namespace soadyn
