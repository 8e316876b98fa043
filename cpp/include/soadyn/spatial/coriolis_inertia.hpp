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
// For a rigid body's spatial inertia about a point, or a sum of them,
// I = [A h^; h^' m 1] (h = m c, [angular; linear] as everywhere), with
// V = [w; v], n = A w + h x v and f = m v + w x h its momentum, the blocks
// work out to
//   B = [ 1/2 (-n^ - P - P') + (h.v) 1    0 ]
//       [ -f^                              0 ],   P = A w^ + v h',
// so B W reads only W's angular part (coriolis_times) and B' W gives only
// an angular part (coriolis_transpose_times). Checks: B V = [w x n + v x f;
// w x f] = V x* (I V); B + B' = dI/dt.
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
  const Mat3<S> A = inertia.template topLeftCorner<3, 3>();
  const Vec3<S> h(inertia(2, 4), inertia(0, 5), inertia(1, 3));  // the top-right block is h^
  const S mass = inertia(5, 5);
  const Vec3<S> n = A * w + h.cross(v), f = mass * v + w.cross(h);
  const Mat3<S> P = times_cross_matrix(A, w) + v * h.transpose();
  Mat6<S> B;
  B.template topLeftCorner<3, 3>() = S(-0.5) * (skew(n) + P + P.transpose());
  B.template topLeftCorner<3, 3>().diagonal().array() += h.dot(v);
  B.template bottomLeftCorner<3, 3>() = -skew(f);
  B.template rightCols<3>().setZero();
  return B;
}

// B W and B' W for a Coriolis factor B (or a sum of them), whose right
// column of blocks is zero (coriolis_inertia).
template <class S>
Vec6<S> coriolis_times(const Mat6<S>& B, const Vec6<S>& W) {
  return B.template leftCols<3>() * W.template head<3>();
}

template <class S>
Vec6<S> coriolis_transpose_times(const Mat6<S>& B, const Vec6<S>& W) {
  Vec6<S> out;
  out.template head<3>() = B.template leftCols<3>().transpose() * W;
  out.template tail<3>().setZero();
  return out;
}

}  // namespace soadyn
