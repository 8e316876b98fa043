// The Coriolis factor of a spatial inertia, shared by the Coriolis matrix
// (algorithms/equation_terms) and the derivatives of the dynamics
// (algorithms/dynamics_derivatives).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// The Coriolis factor of a spatial inertia (Echeandia & Wensing, "Numerical
// Methods to Compute the Coriolis Matrix and Christoffel Symbols for
// Rigid-Body Systems", ASME J. Computational and Nonlinear Dynamics 16(9),
// 2021, Eq. 20, after Niemeyer & Slotine):
//   B(I, V) = 1/2 [ (V x*) I + ((I V) xbar*) - I (V x) ],  (f xbar*) V = V x* f.
// B V = V x* (I V) (the gyroscopic force); B + B' = (V x*) I - I (V x) = dI/dt;
// and 2 B W = d/dV [V x* (I V)] W + I (W x V): the change of the gyroscopic
// force along W plus the inertia times the velocity product W x V.
// With I symmetric, (V x*) I = -(V x)' I = -(I (V x))': one product,
// P = I (V x), gives both inertia terms, B = 1/2 [(I V) xbar* - P - P'].
// P by 3x3 blocks, I = [A X; Y D] and (V x) = [w^ 0; v^ w^]:
// P = [A w^ + X v^, X w^; Y w^ + D v^, D w^] (a block times a cross-product
// matrix: 18 multiplications, times_cross_matrix).
template <class S>
Mat3<S> times_cross_matrix(const Mat3<S>& M, const Vec3<S>& w) {
  Mat3<S> out;  // column j of M w^ is M (w x e_j)
  out.col(0) = w[2] * M.col(1) - w[1] * M.col(2);
  out.col(1) = w[0] * M.col(2) - w[2] * M.col(0);
  out.col(2) = w[1] * M.col(0) - w[0] * M.col(1);
  return out;
}

template <class S>
Mat6<S> coriolis_inertia(const Mat6<S>& inertia, const Vec6<S>& V) {
  const Vec3<S> w = V.template head<3>(), v = V.template tail<3>();
  const Mat3<S> A = inertia.template topLeftCorner<3, 3>(), X = inertia.template topRightCorner<3, 3>();
  const Mat3<S> Y = inertia.template bottomLeftCorner<3, 3>(), D = inertia.template bottomRightCorner<3, 3>();
  Mat6<S> P;
  P.template topLeftCorner<3, 3>() = times_cross_matrix(A, w) + times_cross_matrix(X, v);
  P.template topRightCorner<3, 3>() = times_cross_matrix(X, w);
  P.template bottomLeftCorner<3, 3>() = times_cross_matrix(Y, w) + times_cross_matrix(D, v);
  P.template bottomRightCorner<3, 3>() = times_cross_matrix(D, w);
  const Vec6<S> h = inertia * V;  // momentum
  Mat6<S> B = -S(0.5) * (P + P.transpose());
  const Mat3<S> n_x = skew(Vec3<S>(S(0.5) * h.template head<3>())), f_x = skew(Vec3<S>(S(0.5) * h.template tail<3>()));
  B.template topLeftCorner<3, 3>() -= n_x;  // V -> V x* h
  B.template topRightCorner<3, 3>() -= f_x;
  B.template bottomLeftCorner<3, 3>() -= f_x;
  return B;
}

}  // namespace soadyn
