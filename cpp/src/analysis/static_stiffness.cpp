#include "soadyn/analysis/static_stiffness.hpp"

#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/rnea.hpp"

namespace soadyn {

StaticStiffness::StaticStiffness(const Model& m) : zero_(VecX<double>::Zero(m.nv)) {
  if (!needs_dual_derivatives(m)) {
    analytic_ = std::make_unique<DynamicsDerivatives>(m);
    return;
  }
  dual_ = std::make_unique<ParameterSensitivity>(m);
  for (MatX<double>* x : {&dqdd_dq_, &dqdd_dv_, &dqdd_du_, &dtau_dq_, &dtau_dv_, &dtau_du_}) x->setZero(m.nv, m.nv);
}

StaticStiffness::~StaticStiffness() = default;

Status StaticStiffness::compute(const Model& m, Data& d, const ConstVecRef<double>& q, Eigen::Ref<MatX<double>> out) {
  if (analytic_) {
    const Status status = inverse_dynamics_derivatives<double>(m, d, *analytic_, q, zero_, zero_);
    out = analytic_->inverse_dq;
    return status;
  }
  Status status = inverse_dynamics<double>(m, d, q, zero_, zero_);
  if (!status.ok()) return status;
  static_force_ = d.tau;
  regular_ = m;  // the current parameters, every DOF regular
  regular_.set_all_prescribed(false);
  status = dual_->state_derivatives(regular_, q, zero_, static_force_, nullptr, dqdd_dq_, dqdd_dv_, dqdd_du_,
                                    dtau_dq_, dtau_dv_, dtau_du_);
  if (!status.ok()) return status;
  status = mass_matrix<double>(m, d, q);
  if (!status.ok()) return status;
  out.noalias() = -d.mass_matrix * dqdd_dq_;  // dG/dq = -M dFD/dq at tau = G
  d.tau = static_force_;
  return status;
}

}  // namespace soadyn
