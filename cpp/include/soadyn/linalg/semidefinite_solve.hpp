// Minimum-norm solution x = A^+ b of a symmetric positive semidefinite system
// (the Delassus matrix of the loop multipliers, possibly rank deficient), by
// a pivoted Cholesky factorisation P A P' = L L' (L: m x k, k = rank) and
// A^+ = P' L (L'L)^-2 L' P, working in A's lower triangle (the upper one
// is not read). Pivots not above `relative_threshold` times the
// largest diagonal entry end the factorisation (they count as zero). Plain
// loops: no allocation, with the scratch passed in (sized m x m and m).
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>
#include "soadyn/linalg/small_cholesky.hpp"

namespace soadyn {

template <class S>
struct SemidefiniteSolveScratch {
  explicit SemidefiniteSolveScratch(int m)
      : factor(MatX<S>::Zero(m, m)), gram(MatX<S>::Zero(m, m)), work(VecX<S>::Zero(m)),
        permuted(VecX<S>::Zero(m)), permutation(static_cast<std::size_t>(m), 0) {}
  MatX<S> factor, gram;
  VecX<S> work, permuted;
  std::vector<int> permutation;
  int rank = 0;
};

// x = A^+ b; A is read, not changed. Returns the rank found.
// Flat loops over the column-major factor (column j at F + j m): at the
// sizes of a few loops, Eigen's dynamic-size block expressions cost more in
// set-up than in arithmetic, and the forward substitution runs column-wise
// (independent updates instead of one chain of dependent products; the sums
// are taken in the same order as the row-wise form).
template <class S>
int semidefinite_min_norm_solve(const MatX<S>& A, const VecX<S>& b, S relative_threshold,
                                SemidefiniteSolveScratch<S>& s, VecX<S>& x) {
  using std::sqrt;
  const Eigen::Index m = A.rows();
  s.factor = A;  // the working matrix: its lower part becomes L column by column
  S* const F = s.factor.data();
  const auto column = [F, m](Eigen::Index j) { return F + j * m; };
  int* const permutation = s.permutation.data();
  for (Eigen::Index i = 0; i < m; ++i) permutation[i] = static_cast<int>(i);
  S largest = m > 0 ? F[0] : S(0);
  for (Eigen::Index i = 1; i < m; ++i) largest = std::max(largest, column(i)[i]);
  const S threshold = relative_threshold * largest;
  Eigen::Index k = 0;
  for (; k < m; ++k) {
    // Pivot: the largest remaining diagonal of the Schur complement.
    Eigen::Index p = k;
    for (Eigen::Index i = k + 1; i < m; ++i)
      if (column(i)[i] > column(p)[p]) p = i;
    if (!(column(p)[p] > threshold)) break;
    S* const Lk = column(k);
    if (p != k) {  // symmetric swap of rows and columns k and p, in the lower triangle
      S* const Lp = column(p);
      for (Eigen::Index j = 0; j < k; ++j) std::swap(column(j)[k], column(j)[p]);  // L's finished columns
      std::swap(Lk[k], Lp[p]);
      for (Eigen::Index i = k + 1; i < p; ++i) std::swap(Lk[i], column(i)[p]);
      for (Eigen::Index i = p + 1; i < m; ++i) std::swap(Lk[i], Lp[i]);
      std::swap(permutation[k], permutation[p]);
    }
    const S pivot = sqrt(Lk[k]);
    Lk[k] = pivot;
    for (Eigen::Index i = k + 1; i < m; ++i) Lk[i] /= pivot;
    for (Eigen::Index j = k + 1; j < m; ++j) {  // Schur complement, lower part and diagonal, a column at a time
      S* const Lj = column(j);
      const S f = Lk[j];
      for (Eigen::Index i = j; i < m; ++i) Lj[i] -= f * Lk[i];
    }
  }
  s.rank = static_cast<int>(k);
  S* const y = s.permuted.data();
  for (Eigen::Index i = 0; i < m; ++i) y[i] = b[permutation[i]];
  x.setZero();
  if (k == 0) return 0;
  if (k == m) {  // full rank: x_p = (L L')^-1 b_p
    for (Eigen::Index i = 0; i < m; ++i) {  // L z = b_p, column by column
      const S* const Li = column(i);
      y[i] *= S(1) / Li[i];
      for (Eigen::Index r = i + 1; r < m; ++r) y[r] -= Li[r] * y[i];
    }
    for (Eigen::Index i = m; i-- > 0;) {  // L' x_p = z
      const S* const Li = column(i);
      S t = y[i];
      for (Eigen::Index r = i + 1; r < m; ++r) t -= Li[r] * y[r];
      y[i] = t * (S(1) / Li[i]);
    }
    for (Eigen::Index r = 0; r < m; ++r) x[permutation[r]] = y[r];
    return s.rank;
  }
  // G = L'L (k x k), y = L' b_p, w = G^-2 y, x_p = L w.
  for (Eigen::Index i = 0; i < k; ++i) {
    const S* const Li = column(i);
    for (Eigen::Index j = 0; j <= i; ++j) {
      const S* const Lj = column(j);
      S g = S(0);
      for (Eigen::Index r = i; r < m; ++r) g += Li[r] * Lj[r];  // L is lower trapezoidal
      s.gram(i, j) = g;
      s.gram(j, i) = g;
    }
    S t = S(0);
    for (Eigen::Index r = i; r < m; ++r) t += Li[r] * y[r];
    s.work[i] = t;
  }
  auto G = s.gram.topLeftCorner(k, k);
  if (cholesky_in_place(G, S(0)) >= 0) return -1;
  auto w = s.work.head(k);
  cholesky_solve_in_place(G, w);
  cholesky_solve_in_place(G, w);
  for (Eigen::Index r = 0; r < m; ++r) {
    S xr = S(0);
    for (Eigen::Index i = 0; i < k && i <= r; ++i) xr += column(i)[r] * w[i];
    x[permutation[r]] = xr;
  }
  return s.rank;
}

}  // namespace soadyn
