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

// In place: the entries (i, ancestor-or-self j) of M's lower triangle become
// L. Returns the first DOF (from the leaves) whose pivot is not positive, or -1.
template <class Derived>
int tree_ltl_in_place(Eigen::MatrixBase<Derived>& M, const std::vector<int>& parent) {
  using S = typename Derived::Scalar;
  using std::sqrt;
  for (Eigen::Index k = M.rows() - 1; k >= 0; --k) {
    if (!(M(k, k) > S(0))) return static_cast<int>(k);
    const S pivot = sqrt(M(k, k));
    M(k, k) = pivot;
    for (int i = parent[static_cast<std::size_t>(k)]; i >= 0; i = parent[static_cast<std::size_t>(i)]) M(k, i) /= pivot;
    for (int i = parent[static_cast<std::size_t>(k)]; i >= 0; i = parent[static_cast<std::size_t>(i)])
      for (int j = i; j >= 0; j = parent[static_cast<std::size_t>(j)]) M(i, j) -= M(k, i) * M(k, j);
  }
  return -1;
}

// x <- L'^-1 x (the first half of a solve), every column of x.
template <class FactorDerived, class Derived>
void tree_ltl_solve_transposed(const Eigen::MatrixBase<FactorDerived>& L, const std::vector<int>& parent,
                               Eigen::MatrixBase<Derived>& x) {
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    for (Eigen::Index i = L.rows() - 1; i >= 0; --i) {
      x(i, c) /= L(i, i);
      for (int j = parent[static_cast<std::size_t>(i)]; j >= 0; j = parent[static_cast<std::size_t>(j)])
        x(j, c) -= L(i, j) * x(i, c);
    }
}

// x <- L^-1 x (the second half), every column of x.
template <class FactorDerived, class Derived>
void tree_ltl_solve(const Eigen::MatrixBase<FactorDerived>& L, const std::vector<int>& parent,
                    Eigen::MatrixBase<Derived>& x) {
  for (Eigen::Index c = 0; c < x.cols(); ++c)
    for (Eigen::Index i = 0; i < L.rows(); ++i) {
      for (int j = parent[static_cast<std::size_t>(i)]; j >= 0; j = parent[static_cast<std::size_t>(j)])
        x(i, c) -= L(i, j) * x(j, c);
      x(i, c) /= L(i, i);
    }
}

}  // namespace soadyn
