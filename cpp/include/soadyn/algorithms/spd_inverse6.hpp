// Inverse of a free root's 6x6 articulated inertia. A Cholesky factor
// waits on a square root and a division per column in turn, and every
// solve with it on two chains of substitutions; P = L D L' (L unit lower
// triangular) needs no square root, and the inverse formed from it,
// P^-1 = L^-T D^-1 L^-1, turns every solve into one matrix-vector product
// whose entries are independent. Both are backward stable for a positive
// definite P, so the inverse's error stays of the order of the rounding
// unit times P's condition number (an inverse by 3x3 adjugates loses far
// more: up to 1e-11 times the condition on random matrices).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// P^-1 of a symmetric positive definite 6x6 P, reading its lower triangle.
// Returns the index of the first LDL' pivot not above `threshold` (P not
// positive definite to within rounding; the pivots are the squares of the
// Cholesky factor's), or -1.
template <class S>
int spd_inverse6(const Mat6<S>& P, S threshold, Mat6<S>& inverse) {
  Mat6<S> L;      // strictly lower part: L; E(i, k) = L(i, k) d_k kept in the upper part as E(k, i)
  S reciprocal[6];
  for (int j = 0; j < 6; ++j) {
    S pivot = P(j, j);
    for (int k = 0; k < j; ++k) pivot -= L(j, k) * L(k, j);
    if (!(pivot > threshold)) return j;
    reciprocal[j] = S(1) / pivot;
    for (int i = j + 1; i < 6; ++i) {
      S x = P(i, j);
      for (int k = 0; k < j; ++k) x -= L(i, k) * L(k, j);
      L(j, i) = x;  // E(i, j) = L(i, j) d_j
      L(i, j) = x * reciprocal[j];
    }
  }
  // W = L^-1 (unit lower triangular), column by column.
  Mat6<S> W = Mat6<S>::Identity();
  for (int c = 0; c < 6; ++c)
    for (int i = c + 1; i < 6; ++i) {
      S x = -L(i, c);
      for (int k = c + 1; k < i; ++k) x -= L(i, k) * W(k, c);
      W(i, c) = x;
    }
  // P^-1 = W' D^-1 W: entry (i, j), i <= j, sums over k >= j.
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i <= j; ++i) {
      S x(0);
      for (int k = j; k < 6; ++k) x += W(k, i) * reciprocal[k] * W(k, j);
      inverse(i, j) = inverse(j, i) = x;
    }
  return -1;
}

}  // namespace soadyn
