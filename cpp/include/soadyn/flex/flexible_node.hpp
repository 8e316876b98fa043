// One lumped node of a modal flexible body (see flexible_body.hpp).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// Per-mode arrays: 6 x n_m mode shapes ([rotation; translation] rows, the
// spatial-vector order) and their 3 x n_m halves.
template <class S> using ModeShape = Eigen::Matrix<S, 6, Eigen::Dynamic>;
template <class S> using ModeShape3 = Eigen::Matrix<S, 3, Eigen::Dynamic>;

// Node j of the lumped model, in the body (reference) frame:
//   r_j   `position`, undeformed;
//   m_j   `mass` >= 0, a point mass at the node;
//   J_j   `rotary_inertia`, about the node, may be zero;
//   Phi_j `mode_shape` (6 x n_m): rows 0-2 Phi_r,j, the small rotation vector
//         per unit modal coordinate, rows 3-5 Phi_t,j, the translation.
// At modal coordinates eta the node sits at r_j + Phi_t,j eta, rotated by
// exp([Phi_r,j eta]x) from the body frame's orientation.
template <class S>
struct FlexibleNode {
  Vec3<S> position = Vec3<S>::Zero();
  S mass = S(0);
  Mat3<S> rotary_inertia = Mat3<S>::Zero();
  ModeShape<S> mode_shape;

  auto rotation_shape() const { return mode_shape.template topRows<3>(); }
  auto translation_shape() const { return mode_shape.template bottomRows<3>(); }

  template <class T>
  FlexibleNode<T> cast() const {
    FlexibleNode<T> n;
    n.position = position.template cast<T>();
    n.mass = static_cast<T>(mass);
    n.rotary_inertia = rotary_inertia.template cast<T>();
    n.mode_shape = mode_shape.template cast<T>();
    return n;
  }
};

template <class S> using FlexibleNodes = aligned_vector<FlexibleNode<S>>;

}  // namespace soadyn
