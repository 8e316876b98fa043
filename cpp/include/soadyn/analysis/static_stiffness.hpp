// The stiffness at rest K = dG/dq, G(q) = ID(q, 0, 0) the static force
// (gravity and the force elements), in the tangent space of integrate, for
// every model: the analytic sweeps (inverse_dynamics_derivatives) for the
// models they take, the dual-number sweeps for models with flexible bodies
// or point springs (needs_dual_derivatives). Modal DOFs cannot be prescribed,
// so the dual path differentiates forward dynamics at tau = G:
// FD(q, 0, G(q)) = 0 gives dG/dq = -M dFD/dq. Used by static_equilibrium and
// EquilibriumSensitivity. The analytic path allocates nothing; the dual
// path is analysis only and allocates.
#pragma once
#include <memory>

#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"

namespace soadyn {

class StaticStiffness {
 public:
  explicit StaticStiffness(const Model& model);
  ~StaticStiffness();
  StaticStiffness(const StaticStiffness&) = delete;
  StaticStiffness& operator=(const StaticStiffness&) = delete;

  // K at q into `out` (nv x nv); data.tau holds G(q) afterwards.
  Status compute(const Model& model, Data& data, const ConstVecRef<double>& q, Eigen::Ref<MatX<double>> out);

 private:
  std::unique_ptr<DynamicsDerivatives> analytic_;
  std::unique_ptr<ParameterSensitivity> dual_;
  Model regular_;  // the dual path's model with every DOF regular
  MatX<double> dqdd_dq_, dqdd_dv_, dqdd_du_, dtau_dq_, dtau_dv_, dtau_du_;
  VecX<double> zero_, static_force_;
};

}  // namespace soadyn
