// The cross-product matrix of a motion vector and the Coriolis factor of a
// spatial inertia, shared by the Coriolis matrix (algorithms/equation_terms)
// and the derivatives of the dynamics (algorithms/dynamics_derivatives).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// crm(V) m = V x m; the force cross product is crf(V) = -crm(V)'.
template <class S>
Mat6<S> motion_cross_matrix(const Vec6<S>& V) {
  Mat6<S> x = Mat6<S>::Zero();
  x.template topLeftCorner<3, 3>() = x.template bottomRightCorner<3, 3>() = skew(Vec3<S>(V.template head<3>()));
  x.template bottomLeftCorner<3, 3>() = skew(Vec3<S>(V.template tail<3>()));
  return x;
}

// The Coriolis factor of a spatial inertia (Echeandia & Wensing, "Numerical
// Methods to Compute the Coriolis Matrix and Christoffel Symbols for
// Rigid-Body Systems", ASME J. Computational and Nonlinear Dynamics 16(9),
// 2021, Eq. 20, after Niemeyer & Slotine):
//   B(I, V) = 1/2 [ (V x*) I + ((I V) xbar*) - I (V x) ],  (f xbar*) V = V x* f.
// B V = V x* (I V) (the gyroscopic force); B + B' = (V x*) I - I (V x) = dI/dt;
// and 2 B W = d/dV [V x* (I V)] W + I (W x V): the change of the gyroscopic
// force along W plus the inertia times the velocity product W x V.
template <class S>
Mat6<S> coriolis_inertia(const Mat6<S>& inertia, const Vec6<S>& V) {
  const Mat6<S> crm = motion_cross_matrix(V);
  const Vec6<S> h = inertia * V;  // momentum
  Mat6<S> momentum_cross = Mat6<S>::Zero();  // V -> V x* h
  const Mat3<S> n_x = skew(Vec3<S>(h.template head<3>())), f_x = skew(Vec3<S>(h.template tail<3>()));
  momentum_cross.template topLeftCorner<3, 3>() = -n_x;
  momentum_cross.template topRightCorner<3, 3>() = -f_x;
  momentum_cross.template bottomLeftCorner<3, 3>() = -f_x;
  return S(0.5) * (-crm.transpose() * inertia + momentum_cross - inertia * crm);  // crf(V) = -crm(V)'
}

}  // namespace soadyn
