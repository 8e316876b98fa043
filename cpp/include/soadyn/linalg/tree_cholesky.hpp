// The mass matrix of a tree factored with its branch-induced sparsity:
// M = L' L, L lower triangular with L(i, j) != 0 only when DOF j is DOF i or
// one of its ancestors (Model::dof_parent). Factoring costs O(n d^2) and a
// solve O(n d) for tree depth d, against O(n^3) and O(n^2) dense, and fill-in
// never leaves the pattern (Featherstone, "Efficient Factorization of the
// Joint-Space Inertia Matrix for Branched Kinematic Trees", IJRR 24(6),
// 2005, the LTL factorisation). Rows and columns replaced by the identity
// (prescribed DOFs) keep the pattern. Plain loops: no allocation.
#pragma once
#include <cmath>
#include <vector>
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// The factor is kept in the upper triangle as U = L' (U(j, k) = L(k, j), j
// an ancestor-or-self of k): row k of L is then column k of U. A DOF's
// ancestors are walked as runs of consecutive DOFs (run_start[i]: the first
// DOF of the unbranched run ending at i, Model::dof_run_start), so the inner
// loops run over contiguous stretches of one column (plain pointer loops the
// compiler vectorises; column-major storage with unit inner stride, as MatX
// and VecX have), not a chase through the parent array.

// Calls fn(first, last) for each run of consecutive DOFs that together are
// `i` and its ancestors (i itself included when include_self).
template <class Fn>
void for_each_ancestor_run(int i, bool include_self, const std::vector<int>& parent, const std::vector<int>& run_start,
                           Fn&& fn) {
  int top = include_self ? i : parent[static_cast<std::size_t>(i)];
  while (top >= 0) {
    const int first = run_start[static_cast<std::size_t>(top)];
    fn(first, top);
    top = parent[static_cast<std::size_t>(first)];
  }
}

// In place: the entries (ancestor-or-self j, k) of M's upper triangle become
// U = L'. Returns the first DOF (from the leaves) whose pivot is not positive, or -1.
template <class Derived>
int tree_ltl_in_place(Eigen::MatrixBase<Derived>& M, const std::vector<int>& parent,
                      const std::vector<int>& run_start) {
  using S = typename Derived::Scalar;
  using std::sqrt;
  for (int k = static_cast<int>(M.rows()) - 1; k >= 0; --k) {
    if (!(M(k, k) > S(0))) return k;
    const S pivot = sqrt(M(k, k));
    M(k, k) = pivot;
    S* const column_k = &M(0, k);
    for_each_ancestor_run(k, false, parent, run_start, [&](int first, int last) {
      for (int j = first; j <= last; ++j) column_k[j] /= pivot;
    });
    for_each_ancestor_run(k, false, parent, run_start, [&](int first, int last) {
      for (int i = first; i <= last; ++i) {
        const S a = column_k[i];
        if (a == S(0)) continue;  // a structural zero (a prescribed DOF's identity row in M~): nothing to update
        S* const column_i = &M(0, i);
        for_each_ancestor_run(i, true, parent, run_start, [&](int f, int l) {
          for (int j = f; j <= l; ++j) column_i[j] -= a * column_k[j];
        });
      }
    });
  }
  return -1;
}

// x <- L'^-1 x = U^-1 x (the first half of a solve), every column of x. A
// column nonzero only on some DOFs and their ancestors (a row of a loop's
// constraint Jacobian) stays so, and costs only those DOFs.
template <class FactorDerived, class Derived>
void tree_ltl_solve_transposed(const Eigen::MatrixBase<FactorDerived>& U, const std::vector<int>& parent,
                               const std::vector<int>& run_start, Eigen::MatrixBase<Derived>& x) {
  using S = typename Derived::Scalar;
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    for (int i = static_cast<int>(U.rows()) - 1; i >= 0; --i) {
      S* const xc = &x(0, c);
      if (xc[i] == S(0)) continue;  // the solve keeps x's support within its ancestors: skip the zeros
      const auto* const column_i = &U(0, i);
      const S xi = xc[i] /= column_i[i];
      for_each_ancestor_run(i, false, parent, run_start, [&](int first, int last) {
        for (int j = first; j <= last; ++j) xc[j] -= xi * column_i[j];
      });
    }
}

// x <- L^-1 x = U'^-1 x (the second half), every column of x.
template <class FactorDerived, class Derived>
void tree_ltl_solve(const Eigen::MatrixBase<FactorDerived>& U, const std::vector<int>& parent,
                    const std::vector<int>& run_start, Eigen::MatrixBase<Derived>& x) {
  using S = typename Derived::Scalar;
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    for (int i = 0; i < static_cast<int>(U.rows()); ++i) {
      S* const xc = &x(0, c);
      const auto* const column_i = &U(0, i);
      S xi = xc[i];
      for_each_ancestor_run(i, false, parent, run_start, [&](int first, int last) {
        for (int j = first; j <= last; ++j) xi -= column_i[j] * xc[j];
      });
      xc[i] = xi / column_i[i];
    }
}

// W = U^-1, upper triangular with the tree's pattern: column c is nonzero on
// c and its ancestors only, so it is found walking up c's chain of ancestors
// (each entry final once every descendant on the chain is done), without
// visiting the zeros. O(sum over DOFs of depth^2).
template <class FactorDerived, class Derived>
void tree_ltl_inverse_factor(const Eigen::MatrixBase<FactorDerived>& U, const std::vector<int>& parent,
                             const std::vector<int>& run_start, Eigen::MatrixBase<Derived>& W) {
  using S = typename Derived::Scalar;
  W.setZero();
  for (int c = 0; c < static_cast<int>(U.rows()); ++c) {
    S* const w = &W(0, c);
    w[c] = S(1);
    for (int i = c; i >= 0; i = parent[static_cast<std::size_t>(i)]) {
      const auto* const column_i = &U(0, i);
      const S wi = w[i] /= column_i[i];
      if (wi == S(0)) continue;  // a structural zero: nothing to subtract
      for_each_ancestor_run(i, false, parent, run_start, [&](int first, int last) {
        for (int j = first; j <= last; ++j) w[j] -= wi * column_i[j];
      });
    }
  }
}

}  // namespace soadyn
