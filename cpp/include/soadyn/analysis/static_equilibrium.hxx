#pragma once
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/constraints/loop_assembly.hpp"
#include "soadyn/constraints/loop_closure.hpp"
#include "soadyn/analysis/loop_force_stiffness.hpp"
#include "soadyn/algorithms/rnea.hpp"
#include "soadyn/analysis/static_equilibrium.hpp"

namespace soadyn {

namespace detail {
template <class S>
bool stiffness_by_dual_numbers(const ModelTpl<S>& m) {
  return std::is_same_v<S, double> && needs_dual_derivatives(m);
}
}  // namespace detail

template <class S>
StaticEquilibriumTpl<S>::StaticEquilibriumTpl(const ModelTpl<S>& m)
    : q(VecX<S>::Zero(m.nq)), multipliers(VecX<S>::Zero(m.nloop_equations)), generalized_force(VecX<S>::Zero(m.nv)),
      derivatives(detail::stiffness_by_dual_numbers(m) ? DynamicsDerivativesTpl<S>(m, OutputsOnly{})
                                                       : DynamicsDerivativesTpl<S>(m)),
      loop_stiffness(MatX<S>::Zero(m.nv, m.nv)), tangent(VecX<S>::Zero(m.nv)),
      q_trial(VecX<S>::Zero(m.nq)), nu_trial(VecX<S>::Zero(m.nloop_equations)), zero(VecX<S>::Zero(m.nv)),
      mask(VecX<S>::Zero(m.nv)) {
  if constexpr (std::is_same_v<S, double>)
    if (detail::stiffness_by_dual_numbers(m)) dual_stiffness = std::make_unique<StaticStiffness>(m);
}

namespace detail {

template <class S>
std::string equilibrium_equation_name(const ModelTpl<S>& m, const StaticEquilibriumTpl<S>& eq, Eigen::Index row) {
  const Eigen::Index nf = static_cast<Eigen::Index>(eq.free.size());
  if (row < nf) return "DOF '" + m.dof_names[static_cast<std::size_t>(eq.free[static_cast<std::size_t>(row)])] + "'";
  const int r = static_cast<int>(row - nf);
  for (const LoopTpl<S>& loop : m.loops)
    if (r < loop.first_row + loop.rows())
      return "loop '" + loop.name + "' (equation " + std::to_string(r - loop.first_row) + ")";
  return "equation " + std::to_string(row);
}

// [G_f - C_f' nu; Psi] at (q, nu) into `out`; G (all DOFs) into eq.generalized_force.
template <class S>
void equilibrium_residual(const ModelTpl<S>& m, DataTpl<S>& d, StaticEquilibriumTpl<S>& eq, const VecX<S>& q,
                          const VecX<S>& nu, VecX<S>& out) {
  inverse_dynamics<S>(m, d, q, eq.zero, eq.zero);
  eq.generalized_force = d.tau;
  if (m.nloop_equations > 0) {
    loop_residual<S>(m, d, q, static_cast<const S*>(nullptr));
    eq.generalized_force.noalias() -= d.loops.jacobian.transpose() * nu;
  }
  const Eigen::Index nf = static_cast<Eigen::Index>(eq.free.size());
  for (Eigen::Index i = 0; i < nf; ++i) out[i] = eq.generalized_force[eq.free[static_cast<std::size_t>(i)]];
  if (m.nloop_equations > 0) out.tail(m.nloop_equations) = d.loops.residual;
}

// (dG/dq - d(C' nu)/dq) into eq.loop_stiffness (all DOFs) and C into data.loops.jacobian.
template <class S>
void equilibrium_stiffness(const ModelTpl<S>& m, DataTpl<S>& d, StaticEquilibriumTpl<S>& eq, const VecX<S>& q,
                           const VecX<S>& nu) {
  bool by_dual = false;
  if constexpr (std::is_same_v<S, double>) {
    if (eq.dual_stiffness) {
      eq.dual_stiffness->compute(m, d, q, eq.derivatives.inverse_dq);
      by_dual = true;
    }
  }
  if (!by_dual) inverse_dynamics_derivatives<S>(m, d, eq.derivatives, q, eq.zero, eq.zero);
  if (m.nloop_equations > 0) {
    loop_force_stiffness<S>(m, d, q, nu, eq.loop_stiffness);
    eq.loop_stiffness = eq.derivatives.inverse_dq - eq.loop_stiffness;
  } else {
    eq.loop_stiffness = eq.derivatives.inverse_dq;
  }
}

template <class S>
MatX<S> free_columns(const MatX<S>& A, const std::vector<Eigen::Index>& free) {
  MatX<S> out(A.rows(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t j = 0; j < free.size(); ++j) out.col(static_cast<Eigen::Index>(j)) = A.col(free[j]);
  return out;
}

// Reduced stiffness N' H_ff N (symmetric part) and N; fills the eigenvalues.
template <class S>
MatX<S> reduced_stiffness_modes(const ModelTpl<S>& m, DataTpl<S>& d, StaticEquilibriumTpl<S>& eq, MatX<S>& vectors) {
  equilibrium_stiffness(m, d, eq, eq.q, eq.multipliers);
  const MatX<S> H_cols = free_columns<S>(eq.loop_stiffness, eq.free);
  const Eigen::Index nf = static_cast<Eigen::Index>(eq.free.size());
  MatX<S> H(nf, nf);
  for (Eigen::Index i = 0; i < nf; ++i) H.row(i) = H_cols.row(eq.free[static_cast<std::size_t>(i)]);
  MatX<S> N = MatX<S>::Identity(nf, nf);
  if (m.nloop_equations > 0 && nf > 0) {
    const MatX<S> Cf = free_columns<S>(d.loops.jacobian, eq.free);
    Eigen::JacobiSVD<MatX<S>> svd(Cf, Eigen::ComputeFullV);
    const VecX<S>& s = svd.singularValues();
    Eigen::Index rank = 0;
    const S floor = S(1e-10) * std::max(S(1), s.size() ? s[0] : S(0));
    while (rank < s.size() && s[rank] > floor) ++rank;
    N = svd.matrixV().rightCols(nf - rank);
  }
  MatX<S> R = N.transpose() * H * N;
  R = (S(0.5) * (R + R.transpose())).eval();
  if (R.size() == 0) {  // no free motion: nothing to be stiff or soft
    eq.stiffness_eigenvalues.resize(0);
    vectors.resize(nf, 0);
    return N;
  }
  Eigen::SelfAdjointEigenSolver<MatX<S>> eig(R);
  eq.stiffness_eigenvalues = eig.eigenvalues();
  vectors = N * eig.eigenvectors();
  return N;
}

// Throws StaticEquilibriumError naming the first equation whose residual (or
// whose forces, when the threshold they set is not finite) is not finite.
template <class S>
void require_finite_residual(const ModelTpl<S>& m, const StaticEquilibriumTpl<S>& eq) {
  for (Eigen::Index row = 0; row < eq.residual.size(); ++row)
    if (!std::isfinite(static_cast<double>(eq.residual[row])))
      throw StaticEquilibriumError("static_equilibrium: the residual of " + equilibrium_equation_name(m, eq, row) +
                                   " is not finite (an input is too large for floating point)");
  for (Eigen::Index dof = 0; dof < eq.generalized_force.size(); ++dof)
    if (!std::isfinite(static_cast<double>(eq.generalized_force[dof])))
      throw StaticEquilibriumError("static_equilibrium: the static force on DOF '" +
                                   m.dof_names[static_cast<std::size_t>(dof)] +
                                   "' is not finite (an input is too large for floating point)");
}

// max |x_i|, 0 for an empty x (a model without DOFs, or with every DOF held).
template <class S>
S largest_magnitude(const VecX<S>& x) {
  return x.size() > 0 ? x.cwiseAbs().maxCoeff() : S(0);
}

// Names of the free DOFs moving along zero modes of the reduced stiffness ("" if none).
template <class S>
std::string dofs_without_stiffness(const ModelTpl<S>& m, DataTpl<S>& d, StaticEquilibriumTpl<S>& eq) {
  MatX<S> vectors;
  reduced_stiffness_modes(m, d, eq, vectors);
  const VecX<S>& values = eq.stiffness_eigenvalues;
  if (values.size() == 0) return "";
  const S scale = std::max(S(1), values.cwiseAbs().maxCoeff());
  std::string names;
  for (Eigen::Index i = 0; i < vectors.rows(); ++i) {
    bool zero_mode = false;
    for (Eigen::Index k = 0; k < values.size(); ++k)
      if (std::abs(values[k]) <= S(1e-9) * scale && std::abs(vectors(i, k)) > S(1e-6)) zero_mode = true;
    if (zero_mode)
      names += (names.empty() ? "'" : ", '") + m.dof_names[static_cast<std::size_t>(eq.free[static_cast<std::size_t>(i)])] + "'";
  }
  return names;
}

template <class S>
void check_equilibrium_arguments(const ModelTpl<S>& m, const ConstVecRef<S>& q0, const std::vector<bool>& free, S tol,
                                 int max_iterations) {
  if (!(tol > S(0)) || !std::isfinite(tol))
    throw std::invalid_argument("static_equilibrium: tol must be positive and finite");
  if (max_iterations < 1) throw std::invalid_argument("static_equilibrium: max_iterations must be >= 1");
  if (q0.size() != m.nq || free.size() != static_cast<std::size_t>(m.nv))
    throw std::invalid_argument("static_equilibrium: q0 needs nq entries and the free mask nv");
  for (Eigen::Index i = 0; i < q0.size(); ++i)
    if (!std::isfinite(q0[i]))
      throw std::invalid_argument("static_equilibrium: q0 entry " + std::to_string(i) + " ('" +
                                  m.coordinate_names[static_cast<std::size_t>(i)] + "') is not finite");
}

}  // namespace detail

template <class S>
void static_equilibrium(const ModelTpl<S>& m, DataTpl<S>& d, StaticEquilibriumTpl<S>& eq, const ConstVecRef<S>& q0,
                        const std::vector<bool>& free, S tol, int max_iterations, const Interrupt* interrupt) {
  detail::check_equilibrium_arguments(m, q0, free, tol, max_iterations);
  eq.free.clear();
  for (int k = 0; k < m.nv; ++k) {
    eq.mask[k] = free[static_cast<std::size_t>(k)] ? S(1) : S(0);
    if (free[static_cast<std::size_t>(k)]) eq.free.push_back(k);
  }
  const Eigen::Index nf = static_cast<Eigen::Index>(eq.free.size()), nl = m.nloop_equations, n = nf + nl;
  eq.q = q0;
  if (nl > 0) {
    const Status closed = assemble_loops<S>(m, d, eq.q, eq.mask, tol, 50, nullptr, interrupt);
    if (closed.code == StatusCode::interrupted) throw StaticEquilibriumError("static_equilibrium: interrupted");
    if (!closed.ok())
      throw StaticEquilibriumError("static_equilibrium: loop '" + m.loops[static_cast<std::size_t>(closed.index)].name +
                                   "' cannot close from q0 with the DOFs not held");
  }
  eq.residual.resize(n);
  eq.trial_residual.resize(n);
  eq.newton.resize(n, n);
  // nu from the least-squares C_f' nu = G_f.
  eq.multipliers.setZero();
  detail::equilibrium_residual(m, d, eq, eq.q, eq.multipliers, eq.residual);
  const S threshold = tol * (S(1) + detail::largest_magnitude<S>(eq.generalized_force));
  if (!std::isfinite(static_cast<double>(threshold))) detail::require_finite_residual(m, eq);
  if (nl > 0 && nf > 0) {
    const MatX<S> Cf = detail::free_columns<S>(d.loops.jacobian, eq.free);
    eq.multipliers = Eigen::CompleteOrthogonalDecomposition<MatX<S>>(Cf.transpose()).solve(eq.residual.head(nf));
    detail::equilibrium_residual(m, d, eq, eq.q, eq.multipliers, eq.residual);
  }
  eq.iterations = 0;
  Eigen::CompleteOrthogonalDecomposition<MatX<S>> solver(n, n);
  while (!(detail::largest_magnitude<S>(eq.residual) <= threshold)) {  // a NaN residual enters, and is refused
    detail::require_finite_residual(m, eq);
    Eigen::Index worst;
    eq.residual.cwiseAbs().maxCoeff(&worst);
    if (eq.iterations == max_iterations) {
      std::ostringstream msg;
      msg << "static_equilibrium did not converge in " << max_iterations << " iterations: "
          << detail::equilibrium_equation_name(m, eq, worst) << " has residual " << eq.residual[worst];
      throw StaticEquilibriumError(msg.str());
    }
    if (interrupt_requested(interrupt)) throw StaticEquilibriumError("static_equilibrium: interrupted");
    detail::equilibrium_stiffness(m, d, eq, eq.q, eq.multipliers);
    // Newton's matrix (Eq. 1.34), restricted to the free DOFs.
    eq.newton.setZero();
    for (Eigen::Index i = 0; i < nf; ++i) {
      const Eigen::Index fi = eq.free[static_cast<std::size_t>(i)];
      for (Eigen::Index j = 0; j < nf; ++j) eq.newton(i, j) = eq.loop_stiffness(fi, eq.free[static_cast<std::size_t>(j)]);
      for (Eigen::Index r = 0; r < nl; ++r) {
        eq.newton(i, nf + r) = -d.loops.jacobian(r, fi);
        eq.newton(nf + r, i) = d.loops.jacobian(r, fi);
      }
    }
    solver.compute(eq.newton);
    eq.step = -solver.solve(eq.residual);
    const S norm = eq.residual.norm();
    S fraction = S(1), trial_norm = S(0);
    for (;;) {  // backtracking on the residual norm
      eq.tangent.setZero();
      for (Eigen::Index i = 0; i < nf; ++i) eq.tangent[eq.free[static_cast<std::size_t>(i)]] = fraction * eq.step[i];
      integrate<S>(m, eq.q, eq.tangent, S(1), eq.q_trial);
      eq.nu_trial = eq.multipliers + fraction * eq.step.tail(nl);
      detail::equilibrium_residual(m, d, eq, eq.q_trial, eq.nu_trial, eq.trial_residual);
      trial_norm = eq.trial_residual.norm();
      if (trial_norm < norm || fraction <= S(1) / S(1024)) break;
      fraction /= S(2);
    }
    if (!(trial_norm < norm)) {
      const std::string missing = detail::dofs_without_stiffness(m, d, eq);
      std::ostringstream msg;
      msg << "static_equilibrium: Newton step cannot reduce the residual of "
          << detail::equilibrium_equation_name(m, eq, worst) << " (" << eq.residual[worst] << ")";
      if (!missing.empty()) msg << "; no stiffness along [" << missing << "] (hold them)";
      throw StaticEquilibriumError(msg.str());
    }
    eq.q = eq.q_trial;
    eq.multipliers = eq.nu_trial;
    eq.residual = eq.trial_residual;
    ++eq.iterations;
  }
  detail::equilibrium_residual(m, d, eq, eq.q, eq.multipliers, eq.residual);
  eq.residual_norm = detail::largest_magnitude<S>(eq.residual);
  const VecX<S> force = eq.generalized_force;
  const std::string missing = detail::dofs_without_stiffness(m, d, eq);
  if (!missing.empty())
    throw StaticEquilibriumError("static_equilibrium: the equilibrium is not isolated: no stiffness along [" + missing +
                                 "] (hold them, or add springs)");
  eq.generalized_force = force;
  eq.stable = eq.stiffness_eigenvalues.size() == 0 || eq.stiffness_eigenvalues[0] > S(0);
}

}  // namespace soadyn
