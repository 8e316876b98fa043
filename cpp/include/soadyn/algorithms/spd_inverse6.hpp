// Inverse of a free root's 6x6 articulated inertia, by 3x3 blocks. A 6x6
// Cholesky factorisation waits on six square roots and six divisions in
// turn, and its substitutions on each other; the block inverse takes two
// divisions and otherwise products that run side by side, and every later
// solve with it is one matrix-vector product.
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

namespace detail {

// Inverse of a symmetric 3x3 matrix by its adjugate, if its LDL' pivots are
// all above `threshold`; otherwise the index of the first that is not (in
// exact arithmetic the pivots are the ratios of leading principal minors,
// m1, m2 / m1, m3 / m2, compared here without dividing).
template <class S>
SOADYN_ALWAYS_INLINE int symmetric_inverse3(const Mat3<S>& A, S threshold, Mat3<S>& inverse) {
  const S a = A(0, 0), b = A(1, 0), c = A(2, 0), dd = A(1, 1), e = A(2, 1), f = A(2, 2);
  const S c00 = dd * f - e * e, c01 = c * e - b * f, c02 = b * e - c * dd;
  const S c11 = a * f - c * c, c12 = b * c - a * e, c22 = a * dd - b * b;
  const S det = a * c00 + b * c01 + c * c02;
  if (!(a > threshold)) return 0;
  if (!(c22 > threshold * a)) return 1;
  if (!(det > threshold * c22)) return 2;
  const S r = S(1) / det;
  inverse << c00 * r, c01 * r, c02 * r, c01 * r, c11 * r, c12 * r, c02 * r, c12 * r, c22 * r;
  return -1;
}

}  // namespace detail

// P^-1 of a symmetric positive definite P = [A B; B' C] (3x3 blocks):
//   Y = A^-1 B,  K = C - B' Y (the Schur complement),
//   P^-1 = [A^-1 + Y K^-1 Y', -Y K^-1; -K^-1 Y', K^-1].
// Returns the index of the first pivot of P's LDL' factorisation not above
// `threshold` (P not positive definite to within rounding: K's pivots are
// P's last three), or -1. Reads P's lower triangle only.
template <class S>
int spd_inverse6(const Mat6<S>& P, S threshold, Mat6<S>& inverse) {
  Mat3<S> A_inverse, K_inverse;
  const int bad_a = detail::symmetric_inverse3<S>(P.template topLeftCorner<3, 3>(), threshold, A_inverse);
  if (bad_a >= 0) return bad_a;
  const Mat3<S> B_transpose = P.template bottomLeftCorner<3, 3>();
  const Mat3<S> Y = A_inverse * B_transpose.transpose();
  const Mat3<S> K = P.template bottomRightCorner<3, 3>() - B_transpose * Y;
  const int bad_k = detail::symmetric_inverse3<S>(K, threshold, K_inverse);
  if (bad_k >= 0) return 3 + bad_k;
  const Mat3<S> Z = Y * K_inverse;  // -(P^-1)'s top-right block
  inverse.template topLeftCorner<3, 3>() = A_inverse + Z * Y.transpose();
  inverse.template topRightCorner<3, 3>() = -Z;
  inverse.template bottomLeftCorner<3, 3>() = -Z.transpose();
  inverse.template bottomRightCorner<3, 3>() = K_inverse;
  return -1;
}

}  // namespace soadyn
