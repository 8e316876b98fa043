#include "soadyn/analysis/equilibrium_sensitivity.hpp"

#include <Eigen/QR>
#include <stdexcept>
#include <string>

#include "soadyn/analysis/static_stiffness.hpp"
#include "soadyn/constraints/loop_closure.hpp"
#include "soadyn/analysis/loop_force_stiffness.hpp"

namespace soadyn {

struct EquilibriumSensitivity::Factors {
  explicit Factors(const Model& model) : at_rest(model), dual(model) { at_rest.set_all_prescribed(true); }
  Model at_rest;  // every DOF prescribed: hybrid dynamics at v = u = 0 is inverse dynamics at rest
  ParameterSensitivity dual;
  MatX<double> stiffness, jacobian;  // K (nv x nv), C (nloop_equations x nv) at q
  Eigen::CompleteOrthogonalDecomposition<MatX<double>> newton, newton_transposed;  // J and J'
};

EquilibriumSensitivity::EquilibriumSensitivity(const Model& m, const ConstVecRef<double>& q,
                                               const ConstVecRef<double>& nu, const std::vector<bool>& free)
    : factors_(std::make_unique<Factors>(m)), q_(q) {
  if (q.size() != m.nq || nu.size() != m.nloop_equations || free.size() != static_cast<std::size_t>(m.nv))
    throw std::invalid_argument("equilibrium sensitivities: q, the multipliers or the free mask do not match the model");
  for (int k = 0; k < m.nv; ++k) (free[static_cast<std::size_t>(k)] ? free_ : held_).push_back(k);
  Data data(m);
  StaticStiffness static_stiffness(m);
  Factors& f = *factors_;
  f.stiffness.resize(m.nv, m.nv);
  Status status = static_stiffness.compute(m, data, q, f.stiffness);
  f.jacobian.setZero(m.nloop_equations, m.nv);
  if (status.ok() && m.nloops() > 0) {
    MatX<double> loop_stiffness(m.nv, m.nv);
    status = loop_force_stiffness<double>(m, data, q, nu, loop_stiffness);
    f.stiffness -= loop_stiffness;
    f.jacobian = data.loops.jacobian;
  }
  if (!status.ok() || !f.stiffness.allFinite())
    throw std::invalid_argument("equilibrium sensitivities: the stiffness at the equilibrium is not finite");
  const Eigen::Index nf = static_cast<Eigen::Index>(free_.size()), ne = m.nloop_equations;
  MatX<double> J = MatX<double>::Zero(nf + ne, nf + ne);  // [[K_ff, -C_f'], [C_f, 0]]
  for (Eigen::Index r = 0; r < nf; ++r) {
    for (Eigen::Index c = 0; c < nf; ++c) J(r, c) = f.stiffness(free_[r], free_[c]);
    J.col(r).tail(ne) = f.jacobian.col(free_[r]);
    J.row(r).tail(ne) = -f.jacobian.col(free_[r]).transpose();
  }
  if (J.size() > 0) {  // every DOF held and no loop: nothing to solve (Eigen's factorisations need a matrix)
    f.newton.compute(J);
    f.newton_transposed.compute(J.transpose());
  }
  adjoint_.setZero(nf + ne);
}

EquilibriumSensitivity::~EquilibriumSensitivity() = default;

Status EquilibriumSensitivity::static_force_derivative(const Model& m, const ParameterTable<double>& table, int k) {
  const std::string& name = table.entry(k).name;
  if (m.nloops() > 0 && name.size() > 10 && name.compare(name.size() - 10, 10, ".placement") == 0)
    throw std::invalid_argument("parameter '" + name +
                                "': a placement moves the loops' closure, whose dependence on it is not "
                                "differentiated (equilibrium sensitivities take masses, centres of mass, inertias, "
                                "springs and gravity)");
  const int n = parameter_directions(table.entry(k));
  const VecX<double> zero = VecX<double>::Zero(m.nv);
  MatX<double> dqdd(m.nv, n), dwrench(6 * m.nloops(), n);
  static_force_.resize(m.nv, n);
  return factors_->dual.compute(factors_->at_rest, table, k, q_, zero, zero, dqdd, static_force_, dwrench, true);
}

Status EquilibriumSensitivity::direct(const Model& m, const ParameterTable<double>& table, int k,
                                      Eigen::Ref<MatX<double>> dq, Eigen::Ref<MatX<double>> dnu,
                                      Eigen::Ref<MatX<double>> dholding) {
  const Status status = static_force_derivative(m, table, k);
  if (!status.ok()) return status;
  const Factors& f = *factors_;
  const Eigen::Index nf = static_cast<Eigen::Index>(free_.size()), ne = m.nloop_equations, n = static_force_.cols();
  MatX<double> rhs = MatX<double>::Zero(nf + ne, n);  // -[dG_f/dp; 0]
  for (Eigen::Index r = 0; r < nf; ++r) rhs.row(r) = -static_force_.row(free_[r]);
  const MatX<double> x = rhs.rows() > 0 ? MatX<double>(f.newton.solve(rhs)) : rhs;  // the minimum-norm solution
  dq.setZero();
  for (Eigen::Index r = 0; r < nf; ++r) dq.row(free_[r]) = x.row(r);
  dnu = x.bottomRows(ne);
  for (std::size_t h = 0; h < held_.size(); ++h) {  // dH/dp = dG_h/dp + K_hf dq_f/dp - C_h' dnu/dp
    const int dof = held_[h];
    auto row = dholding.row(static_cast<Eigen::Index>(h));
    row = static_force_.row(dof);
    for (Eigen::Index r = 0; r < nf; ++r) row += f.stiffness(dof, free_[r]) * x.row(r);
    row -= f.jacobian.col(dof).transpose() * x.bottomRows(ne);
  }
  return status;
}

void EquilibriumSensitivity::set_objective(const ConstVecRef<double>& dphi_dq, const ConstVecRef<double>& dphi_dnu) {
  const Eigen::Index nf = static_cast<Eigen::Index>(free_.size()), ne = adjoint_.size() - nf;
  VecX<double> g = VecX<double>::Zero(nf + ne);
  for (Eigen::Index r = 0; r < nf; ++r) g[r] = dphi_dq[free_[r]];
  if (dphi_dnu.size() == ne) g.tail(ne) = dphi_dnu;
  adjoint_ = g.size() > 0 ? VecX<double>(factors_->newton_transposed.solve(g)) : g;
}

Status EquilibriumSensitivity::objective_gradient(const Model& m, const ParameterTable<double>& table, int k,
                                                  Eigen::Ref<VecX<double>> out) {
  const Status status = static_force_derivative(m, table, k);
  if (!status.ok()) return status;
  out.setZero();
  for (std::size_t r = 0; r < free_.size(); ++r)  // dphi/dp = -lambda_f' dG_f/dp
    out -= adjoint_[static_cast<Eigen::Index>(r)] * static_force_.row(free_[r]).transpose();
  return status;
}

}  // namespace soadyn
