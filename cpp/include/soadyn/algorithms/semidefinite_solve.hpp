// Minimum-norm solution x = A^+ b of a symmetric positive semidefinite system
// (the Delassus matrix of the loop multipliers, possibly rank deficient), by
// a pivoted Cholesky factorisation P A P' = L L' (L: m x k, k = rank) and
// A^+ = P' L (L'L)^-2 L' P, working in A's lower triangle (the upper one
// is not read). Pivots not above `relative_threshold` times the
// largest diagonal entry end the factorisation (they count as zero). Plain
// loops: no allocation, with the scratch passed in (sized m x m and m).
#pragma once
#include <cmath>
#include <utility>
#include <vector>
#include "soadyn/algorithms/small_cholesky.hpp"

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
template <class S>
int semidefinite_min_norm_solve(const MatX<S>& A, const VecX<S>& b, S relative_threshold,
                                SemidefiniteSolveScratch<S>& s, VecX<S>& x) {
  using std::sqrt;
  const Eigen::Index m = A.rows();
  MatX<S>& L = s.factor;
  L = A;  // the working matrix: its lower part becomes L column by column
  for (Eigen::Index i = 0; i < m; ++i) s.permutation[static_cast<std::size_t>(i)] = static_cast<int>(i);
  const S largest = m > 0 ? A.diagonal().maxCoeff() : S(0);
  const S threshold = relative_threshold * largest;
  Eigen::Index k = 0;
  for (; k < m; ++k) {
    // Pivot: the largest remaining diagonal of the Schur complement.
    Eigen::Index p = k;
    for (Eigen::Index i = k + 1; i < m; ++i)
      if (L(i, i) > L(p, p)) p = i;
    if (!(L(p, p) > threshold)) break;
    if (p != k) {  // symmetric swap of rows and columns k and p, in the lower triangle
      for (Eigen::Index j = 0; j < k; ++j) std::swap(L(k, j), L(p, j));  // L's finished columns
      std::swap(L(k, k), L(p, p));
      for (Eigen::Index i = k + 1; i < p; ++i) std::swap(L(i, k), L(p, i));
      for (Eigen::Index i = p + 1; i < m; ++i) std::swap(L(i, k), L(i, p));
      std::swap(s.permutation[static_cast<std::size_t>(k)], s.permutation[static_cast<std::size_t>(p)]);
    }
    const S pivot = sqrt(L(k, k));
    L(k, k) = pivot;
    L.col(k).tail(m - k - 1) /= pivot;
    for (Eigen::Index j = k + 1; j < m; ++j)  // Schur complement, lower part and diagonal, a column at a time
      L.col(j).tail(m - j) -= L(j, k) * L.col(k).tail(m - j);
  }
  s.rank = static_cast<int>(k);
  for (Eigen::Index i = 0; i < m; ++i) s.permuted[i] = b[s.permutation[static_cast<std::size_t>(i)]];
  x.setZero();
  if (k == 0) return 0;
  if (k == m) {  // full rank: x_p = (L L')^-1 b_p
    auto y = s.permuted.head(m);
    cholesky_solve_in_place(L, y);
    for (Eigen::Index r = 0; r < m; ++r) x[s.permutation[static_cast<std::size_t>(r)]] = y[r];
    return s.rank;
  }
  // G = L'L (k x k), y = L' b_p, w = G^-2 y, x_p = L w.
  for (Eigen::Index i = 0; i < k; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) {
      S g = S(0);
      for (Eigen::Index r = i; r < m; ++r) g += L(r, i) * L(r, j);  // L is lower trapezoidal
      s.gram(i, j) = g;
      s.gram(j, i) = g;
    }
  for (Eigen::Index i = 0; i < k; ++i) {
    S y = S(0);
    for (Eigen::Index r = i; r < m; ++r) y += L(r, i) * s.permuted[r];
    s.work[i] = y;
  }
  auto G = s.gram.topLeftCorner(k, k);
  if (cholesky_in_place(G, S(0)) >= 0) return -1;
  auto w = s.work.head(k);
  cholesky_solve_in_place(G, w);
  cholesky_solve_in_place(G, w);
  for (Eigen::Index r = 0; r < m; ++r) {
    S xr = S(0);
    for (Eigen::Index i = 0; i < k && i <= r; ++i) xr += L(r, i) * w[i];
    x[s.permutation[static_cast<std::size_t>(r)]] = xr;
  }
  return s.rank;
}

}  // namespace soadyn
