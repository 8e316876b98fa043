// Design sensitivities of a static equilibrium ("Joint Coordinate Method,
// Part 1", Sects. 6-7, Eqs. 1.37-1.41), for an equilibrium found by
// static_equilibrium (static_equilibrium.hpp).
//
// At an equilibrium (q*, nu*) the residual R(q, nu; p) = [G_f(q; p) - C_f(q)' nu; Psi(q)]
// vanishes (G the static force, inverse dynamics at rest; f the free DOFs;
// C the loop Jacobian; Psi the closure). Differentiating R(q*(p), nu*(p); p) = 0
// gives the direct method
//   J [dq_f/dp; dnu/dp] = -[dG_f/dp; 0],   J = [[K_ff, -C_f'], [C_f, 0]],
// K = dG/dq - d(C' nu)/dq (inverse_dynamics_derivatives at rest and
// loop_force_stiffness, analytic) and dG/dp by forward-mode automatic
// differentiation of inverse dynamics at rest (ParameterSensitivity on the
// spanning tree with every DOF prescribed). J is singular when the loop
// equations are redundant (a planar four-bar's 3-D cut joint): the minimum-
// norm solution is taken (complete orthogonal decomposition, as for nu
// itself), so dq/dp is exact and dnu/dp is the derivative of the minimum-
// norm multipliers within the equations' range. The adjoint method gives the
// gradient of a scalar objective phi(q, nu) with one solve for every
// parameter: J' lambda = [dphi/dq_f; dphi/dnu], dphi/dp = -lambda_f' dG_f/dp.
// Holding forces H = G_h - C_h' nu of the held DOFs h:
// dH/dp = dG_h/dp + K_hf dq_f/dp - C_h' dnu/dp.
//
// Parameters whose change moves the loops' closure (a body's placement on a
// loop model) are refused (std::invalid_argument naming the parameter): the
// closure's own dependence on them is not differentiated here. Analysis, not
// real time: construction and the calls allocate.
#pragma once
#include <memory>
#include <vector>

#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/model/data.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {

class EquilibriumSensitivity {
 public:
  // At the equilibrium (q, multipliers) of `model` with the DOFs whose `free`
  // entry is false held (static_equilibrium's arguments and results). Forms
  // K, C and J and factors J. Throws std::invalid_argument for sizes that do
  // not match the model and for a non-finite stiffness.
  EquilibriumSensitivity(const Model& model, const ConstVecRef<double>& q, const ConstVecRef<double>& multipliers,
                         const std::vector<bool>& free);
  ~EquilibriumSensitivity();
  EquilibriumSensitivity(const EquilibriumSensitivity&) = delete;
  EquilibriumSensitivity& operator=(const EquilibriumSensitivity&) = delete;

  // Direct method for entry k of `table`: dq (nv x directions, tangent
  // space, zero on held DOFs), dmultipliers (nloop_equations x directions),
  // dholding (one row per held DOF, in increasing DOF order). Returns the
  // status of the dual-number inverse dynamics.
  Status direct(const Model& model, const ParameterTable<double>& table, int k, Eigen::Ref<MatX<double>> dq,
                Eigen::Ref<MatX<double>> dmultipliers, Eigen::Ref<MatX<double>> dholding);

  // Adjoint method: sets the objective's gradients dphi/dq (nv, tangent
  // space; held DOFs' entries are ignored) and dphi/dnu (nloop_equations, or
  // empty) and solves J' lambda once; then objective_gradient gives
  // dphi/dp (directions) for each entry.
  void set_objective(const ConstVecRef<double>& dphi_dq, const ConstVecRef<double>& dphi_dnu);
  Status objective_gradient(const Model& model, const ParameterTable<double>& table, int k,
                            Eigen::Ref<VecX<double>> out);

  const std::vector<int>& held() const { return held_; }

 private:
  // dG/dp of entry k (nv x directions) into static_force_.
  Status static_force_derivative(const Model& model, const ParameterTable<double>& table, int k);
  struct Factors;
  std::unique_ptr<Factors> factors_;
  std::vector<int> free_, held_;
  VecX<double> q_, adjoint_;
  MatX<double> static_force_;
};

}  // namespace soadyn
