// Factor and solves of a free root's 6x6 articulated inertia. A Cholesky
// factor waits on a square root and a division per column in turn;
// P = L D L' (L unit lower triangular) needs no square root, and with the
// reciprocals of D's pivots stored, a solve is two substitutions and a
// scaling with no division. Backward stable for a positive definite P: the
// solution's error stays of the order of the rounding unit times P's
// condition number. The sweeps need one solve per call, not an inverse
// (an explicit inverse costs about twice the factor again, and an inverse
// by 3x3 adjugates loses accuracy).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// P = L D L' of a symmetric positive definite 6x6 P, reading its lower
// triangle: `factor` holds L strictly below its diagonal and 1/d_j on it
// (above it, scratch). Returns the index of the first pivot d_j not above
// `threshold` (P not positive definite to within rounding; the pivots are the
// squares of the Cholesky factor's), or -1.
template <class S>
int spd_factor6(const Mat6<S>& P, S threshold, Mat6<S>& factor) {
  Mat6<S>& L = factor;  // E(i, k) = L(i, k) d_k kept in the upper part as E(k, i)
  for (int j = 0; j < 6; ++j) {
    S pivot = P(j, j);
    for (int k = 0; k < j; ++k) pivot -= L(j, k) * L(k, j);
    if (!(pivot > threshold)) return j;
    const S reciprocal = S(1) / pivot;
    for (int i = j + 1; i < 6; ++i) {
      S x = P(i, j);
      for (int k = 0; k < j; ++k) x -= L(i, k) * L(k, j);
      L(j, i) = x;  // E(i, j) = L(i, j) d_j
      L(i, j) = x * reciprocal;
    }
    L(j, j) = reciprocal;
  }
  return -1;
}

// P^-1 b from spd_factor6's factor: L y = b, then z = D^-1 y, then L' x = z;
// both substitutions by columns of L, so that the updates a solved entry
// makes to the others are independent of one another.
template <class S>
Vec6<S> spd_solve6(const Mat6<S>& factor, const Vec6<S>& b) {
  Vec6<S> x = b;
  for (int k = 0; k < 5; ++k)
    for (int i = k + 1; i < 6; ++i) x[i] -= factor(i, k) * x[k];
  for (int k = 0; k < 6; ++k) x[k] *= factor(k, k);
  for (int k = 5; k > 0; --k)
    for (int i = 0; i < k; ++i) x[i] -= factor(k, i) * x[k];
  return x;
}

}  // namespace soadyn
