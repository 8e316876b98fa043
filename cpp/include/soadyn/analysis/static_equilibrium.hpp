// Static equilibrium by Newton's method with the analytic stiffness
// ("Joint Coordinate Method, Part 1", Eqs. 1.33-1.34). With v = 0, qdd = 0
// inverse dynamics leaves the static force G(q) = ID(q, 0, 0) (gravity and
// every force element inverse dynamics includes). On the free DOFs f (those
// not held) the equilibrium solves
//   G_f(q) - C_f(q)' nu = 0,   Psi(q) = 0
// (trees: G_f(q) = 0), nu the multipliers of constrained_dynamics
// (M qdd + h = tau + C' nu). Newton's matrix
//   [ (dG/dq - d(C' nu)/dq)_ff   -C_f' ]
//   [  C_f                         0   ]
// comes from inverse_dynamics_derivatives at v = 0, qdd = 0 and
// loop_force_stiffness; steps are tangent vectors (integrate).
//
// Steps: the loops are closed from q0 (assemble_loops, held DOFs fixed); nu
// starts from the least-squares C_f C_f' nu = C_f G_f (the paper's
// C C' nu = -C B' g in this sign convention); each Newton step is the
// minimum-norm least-squares solution (complete orthogonal decomposition:
// redundant loop equations leave nu non-unique), followed by a backtracking
// line search on the residual norm. Converged when every residual entry is
// at most tol (1 + max |G(q0)|).
//
// Stability: the eigenvalues (ascending) of the symmetric part of the
// reduced stiffness N' (dG/dq - d(C' nu)/dq)_ff N, N an orthonormal basis of
// null(C_f) (N = I for a tree), in tangent units: the Hessian of the
// potential energy on the constraint manifold; stable iff all are > 0.
//
// Failures throw StaticEquilibriumError naming the DOF or loop at fault: no
// convergence within max_iterations, a step that cannot reduce the residual,
// an equilibrium that is not isolated (DOFs without stiffness: hold them),
// loops that cannot close. Bad arguments throw std::invalid_argument. This
// is an analysis call, not a real-time one: it may allocate (the
// decompositions); the workspace is built once per model and the per-
// iteration kernels (inverse_dynamics_derivatives, loop_force_stiffness)
// allocate nothing. Models with flexible bodies or point springs take the
// stiffness from the dual-number sweeps (StaticStiffness; double only: the
// float workspace refuses them by name).
#pragma once
#include "soadyn/core/interrupt.hpp"
#include <stdexcept>
#include <string>
#include <vector>

#include <memory>

#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/static_stiffness.hpp"

namespace soadyn {

struct StaticEquilibriumError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class S>
struct StaticEquilibriumTpl {
  explicit StaticEquilibriumTpl(const ModelTpl<S>& model);

  // Results.
  VecX<S> q;                      // the equilibrium (nq)
  VecX<S> multipliers;            // nu (nloop_equations), minimum norm
  VecX<S> generalized_force;      // G - C' nu at q (nv): the holding forces on held DOFs, ~0 on free ones
  VecX<S> stiffness_eigenvalues;  // reduced stiffness, ascending (size: the mobility with the holds)
  int iterations = 0;
  S residual_norm = S(0);         // max |residual| at q
  bool stable = false;

  // Scratch. Models with flexible bodies or point springs (double only) take
  // their stiffness from `dual_stiffness` (static_stiffness.hpp).
  DynamicsDerivativesTpl<S> derivatives;
  std::unique_ptr<StaticStiffness> dual_stiffness;
  MatX<S> loop_stiffness, newton;
  VecX<S> residual, trial_residual, step, tangent, q_trial, nu_trial, zero, mask;
  std::vector<Eigen::Index> free;  // velocity indices of the free DOFs
};

using StaticEquilibrium = StaticEquilibriumTpl<double>;
using StaticEquilibriumF = StaticEquilibriumTpl<float>;

// Solves for the equilibrium nearest q0 with the DOFs whose `free` entry is
// false held at their q0 values; results in `eq`. Throws (see above).
template <class S>
void static_equilibrium(const ModelTpl<S>& model, DataTpl<S>& data, StaticEquilibriumTpl<S>& eq,
                        const ConstVecRef<S>& q0, const std::vector<bool>& free, S tol, int max_iterations,
                        const Interrupt* interrupt = nullptr);

extern template struct StaticEquilibriumTpl<double>;
extern template struct StaticEquilibriumTpl<float>;

}  // namespace soadyn
