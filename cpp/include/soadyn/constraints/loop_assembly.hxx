#pragma once
#include <Eigen/LU>
#include <cmath>
#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/constraints/constrained_dynamics.hpp"
#include "soadyn/constraints/loop_assembly.hpp"
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/linalg/semidefinite_solve.hpp"
#include "soadyn/core/interrupt.hpp"

namespace soadyn {

namespace detail {

template <class S>
S largest_residual(const VecX<S>& r, int* row) {
  S largest(0);
  *row = 0;
  using std::abs;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const S a = abs(r[i]);
    if (!(a <= largest)) {  // a NaN residual counts as the largest
      largest = a;
      *row = static_cast<int>(i);
    }
  }
  return largest;
}

template <class S>
int loop_of_row(const ModelTpl<S>& m, int row) {
  for (std::size_t l = 0; l < m.loops.size(); ++l)
    if (row < m.loops[l].first_row + m.loops[l].rows()) return static_cast<int>(l);
  return -1;
}

// correction = -C_f' (C_f C_f')^+ r, from C in data.loops.jacobian.
template <class S>
bool minimum_norm_correction(LoopData<S>& ld, const ConstVecRef<S>& free, const VecX<S>& r) {
  restrict_jacobian_columns(ld.jacobian, [&](Eigen::Index k) { return free[k] != S(0); }, ld.constraint_jacobian_regular);
  ld.delassus.noalias() = ld.constraint_jacobian_regular.lazyProduct(ld.constraint_jacobian_regular.transpose());
  ld.rhs = -r;
  if (semidefinite_min_norm_solve(ld.delassus, ld.rhs, delassus_threshold<S>(), ld.delassus_solve,
                                  ld.projection_multipliers) < 0)
    return false;
  ld.correction.noalias() = ld.constraint_jacobian_regular.transpose() * ld.projection_multipliers;
  return ld.correction.allFinite();
}

}  // namespace detail

template <class S>
Status assemble_loops(const ModelTpl<S>& m, DataTpl<S>& d, VecRef<S> q, const ConstVecRef<S>& free, S tolerance,
                      int max_iterations, int* iterations, const Interrupt* interrupt) {
  LoopData<S>& ld = d.loops;
  int steps = 0, row = 0, steps_without_progress = 0, last_halving = 0;
  if (iterations) *iterations = 0;
  if (m.nloops() == 0) return Status{};
  loop_residual<S>(m, d, q, nullptr);
  S error = detail::largest_residual(ld.residual, &row);
  S halving_reference = error;  // the residual the next halving is counted from
  while (!(error <= tolerance)) {
    if (steps == max_iterations || !std::isfinite(scalar_value(error)) ||
        !detail::minimum_norm_correction<S>(ld, free, ld.residual))
      return Status{StatusCode::loop_not_closed, detail::loop_of_row(m, row)};
    if (steps_without_progress == assembly_stall_steps || steps - last_halving == assembly_halving_steps)
      return Status{StatusCode::loop_assembly_stalled, detail::loop_of_row(m, row)};
    if (interrupt_requested(interrupt)) return Status{StatusCode::interrupted, -1};
    ++steps;
    // Gauss-Newton step, halved while the largest residual grows (far from closure).
    ld.q_start = q;
    S scale(1);
    for (int halving = 0;; ++halving) {
      integrate<S>(m, ld.q_start, ld.correction, scale, q);
      loop_residual<S>(m, d, q, nullptr);
      int trial_row = 0;
      const S trial = detail::largest_residual(ld.residual, &trial_row);
      if (trial < error || halving == 20) {
        steps_without_progress = trial < error ? 0 : steps_without_progress + 1;
        error = trial;
        row = trial_row;
        if (error <= halving_reference / S(2)) {
          halving_reference = error;
          last_halving = steps;
        }
        break;
      }
      scale *= S(0.5);
    }
    if (iterations) *iterations = steps;
  }
  return Status{};
}

template <class S>
Status project_loop_velocity(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, VecRef<S> v,
                             const ConstVecRef<S>& free) {
  if (m.nloops() == 0) return Status{};
  LoopData<S>& ld = d.loops;
  loop_residual<S>(m, d, q, v.data());
  int row = 0;
  if (!detail::minimum_norm_correction<S>(ld, free, ld.velocity_residual))
    return Status{StatusCode::loop_not_closed, detail::loop_of_row(m, row)};
  v += ld.correction;
  return Status{};
}

template <class S>
std::vector<int> independent_coordinates(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  loop_residual<S>(m, d, q, nullptr);
  std::vector<bool> dependent(static_cast<std::size_t>(m.nv), false);
  if (m.nloop_equations > 0) {
    Eigen::FullPivLU<MatX<S>> lu(d.loops.jacobian);
    lu.setThreshold(loop_rank_threshold<S>());
    const auto& columns = lu.permutationQ().indices();
    for (Eigen::Index k = 0; k < lu.rank(); ++k) dependent[static_cast<std::size_t>(columns[k])] = true;
  }
  std::vector<int> independent;
  for (int k = 0; k < m.nv; ++k)
    if (!dependent[static_cast<std::size_t>(k)]) independent.push_back(k);
  return independent;
}

}  // namespace soadyn
