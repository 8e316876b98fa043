// Cholesky factorisation and solves for the small blocks of the recursion (a
// flexible body's modal block, n_m x n_m; a free root's 6x6 articulated
// inertia): plain loops, no allocation, none of the dispatch overhead general
// solvers carry for blocked right-hand sides at these sizes. With a
// fixed-size matrix the loops unroll.
#pragma once
#include <limits>
#include <cmath>
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// In place: the lower triangle of A becomes L with A = L L'. Returns the
// index of the first pivot whose square is not above `threshold` (A not
// positive definite to within rounding), or -1.
template <class Derived>
int cholesky_in_place(Eigen::MatrixBase<Derived>& A, typename Derived::Scalar threshold) {
  using S = typename Derived::Scalar;
  using std::sqrt;
  const Eigen::Index n = A.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    S d = A(j, j);
    for (Eigen::Index k = 0; k < j; ++k) d -= A(j, k) * A(j, k);
    if (!(d > threshold)) return static_cast<int>(j);
    const S pivot = sqrt(d), inverse_pivot = S(1) / pivot;  // one division per column, not per entry
    A(j, j) = pivot;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      S x = A(i, j);
      for (Eigen::Index k = 0; k < j; ++k) x -= A(i, k) * A(j, k);
      A(i, j) = x * inverse_pivot;
    }
  }
  return -1;
}

// X <- (L L')^-1 X for the factor of cholesky_in_place, every column of X
// (L.rows() rows) at once, row by row. A factor of fixed size has its
// inverse pivots formed first, all at once: the substitutions then wait on
// multiplications only, not on a division per row (the free root's 6x6).
// Otherwise one division per pivot and pass.
template <class FactorDerived, class Derived>
void cholesky_solve_in_place(const Eigen::MatrixBase<FactorDerived>& L, Eigen::MatrixBase<Derived>& X) {
  using S = typename Derived::Scalar;
  constexpr int fixed_rows = FactorDerived::RowsAtCompileTime;
  const Eigen::Index n = L.rows(), m = X.cols();
  S inverse_pivots[fixed_rows > 0 ? fixed_rows : 1];
  if constexpr (fixed_rows > 0)
    for (int i = 0; i < fixed_rows; ++i) inverse_pivots[i] = S(1) / L(i, i);
  const auto inverse_pivot_of = [&](Eigen::Index i) {
    if constexpr (fixed_rows > 0)
      return inverse_pivots[i];
    else
      return S(S(1) / L(i, i));
  };
  for (Eigen::Index i = 0; i < n; ++i) {  // L Y = X
    const S inverse_pivot = inverse_pivot_of(i);
    for (Eigen::Index c = 0; c < m; ++c) {
      S y = X(i, c);
      for (Eigen::Index k = 0; k < i; ++k) y -= L(i, k) * X(k, c);
      X(i, c) = y * inverse_pivot;
    }
  }
  for (Eigen::Index i = n; i-- > 0;) {  // L' X = Y
    const S inverse_pivot = inverse_pivot_of(i);
    for (Eigen::Index c = 0; c < m; ++c) {
      S y = X(i, c);
      for (Eigen::Index k = i + 1; k < n; ++k) y -= L(k, i) * X(k, c);
      X(i, c) = y * inverse_pivot;
    }
  }
}

namespace detail {

// Smallest pivot of D = S' P S accepted as nonsingular, relative to |P|:
// below it D is zero to within the rounding of its own computation.
template <class S>
inline S singular_pivot_threshold(const Mat6<S>& P) {
  return S(16) * std::numeric_limits<S>::epsilon() * P.diagonal().cwiseAbs().maxCoeff();
}

}  // namespace detail
}  // namespace soadyn
