#pragma once
#include <cmath>
#include <type_traits>

#include "soadyn/analysis/dynamics_derivatives.hxx"
#include "soadyn/sim/chart.hpp"
#include "soadyn/analysis/linearization.hpp"

namespace soadyn {

template <class S>
LinearizationTpl<S>::LinearizationTpl(const ModelTpl<S>& m)
    : derivatives(needs_dual_derivatives(m) ? DynamicsDerivativesTpl<S>(m, OutputsOnly{})
                                                    : DynamicsDerivativesTpl<S>(m)) {
  static_assert(std::is_same_v<S, double>, "the dual-number sweeps are instantiated for double");
  if (needs_dual_derivatives(m)) dual = std::make_unique<ParameterSensitivity>(m);
  const Eigen::Index nv = m.nv;
  A.setZero(2 * nv, 2 * nv);
  B.setZero(2 * nv, nv);
  stages.resize(5);  // four Runge-Kutta stages and the step's end
  for (Stage& s : stages) {
    for (VecX<S>* x : {&s.xi, &s.v, &s.rate, &s.acceleration}) x->setZero(nv);
    for (MatX<S>* x : {&s.d_xi, &s.d_v, &s.d_rate, &s.d_acceleration}) x->setZero(nv, 3 * nv);
  }
  q_stage.setZero(m.nq);
  for (MatX<S>* x : {&base_transport, &chart_transport, &rate_base, &rate_xi, &rate_v, &bracket}) x->setZero(nv, nv);
  d_tangent.setZero(nv, 3 * nv);
}

namespace detail {

// The hybrid dynamics (d.qdd, d.tau) and its six derivatives (w.derivatives)
// at (q, v, u): analytic, or by the dual-number sweeps (see linearization.hpp).
template <class S>
Status hybrid_derivatives(const ModelTpl<S>& m, DataTpl<S>& d, LinearizationTpl<S>& w, const ConstVecRef<S>& q,
                          const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  if (!w.dual) return dynamics_derivatives(m, d, w.derivatives, q, v, u, f_ext);
  const Status status = hybrid_dynamics(m, d, q, v, u, f_ext);
  if (!status.ok()) return status;
  DynamicsDerivativesTpl<S>& x = w.derivatives;
  return w.dual->state_derivatives(m, q, v, u, f_ext, x.dqdd_dq, x.dqdd_dv, x.dqdd_du, x.dtau_dq, x.dtau_dv,
                                   x.dtau_du);
}

// The stage at (retract(q0, xi), v) with the Jacobians d_xi, d_v already in
// `s`: its acceleration, rate and their Jacobians. Columns: (e, v, u).
template <class S>
Status linearization_stage(const ModelTpl<S>& m, DataTpl<S>& d, LinearizationTpl<S>& w,
                           typename LinearizationTpl<S>::Stage& s, const S* q0, const ConstVecRef<S>& u,
                           const S* f_ext) {
  const Eigen::Index nv = m.nv;
  model_chart_retract(m, q0, s.xi.data(), w.q_stage.data());
  const Status status = hybrid_derivatives(m, d, w, w.q_stage, s.v, u, f_ext);
  if (!status.ok()) return status;
  s.acceleration = d.qdd;
  chart_transports(m, q0, w.q_stage.data(), s.xi.data(), w.base_transport, w.chart_transport);
  // d(tangent at the stage point) = base_transport de + chart_transport dxi.
  w.d_tangent.noalias() = w.chart_transport * s.d_xi;
  w.d_tangent.leftCols(nv) += w.base_transport;
  s.d_acceleration.noalias() = w.derivatives.dqdd_dq * w.d_tangent;
  s.d_acceleration.noalias() += w.derivatives.dqdd_dv * s.d_v;
  s.d_acceleration.rightCols(nv) += w.derivatives.dqdd_du;
  model_chart_rate(m, w.q_stage.data(), s.xi.data(), s.v.data(), s.rate.data());
  chart_rate_jacobians(m, q0, w.q_stage.data(), s.xi.data(), s.v.data(), w.rate_base, w.rate_xi, w.rate_v);
  s.d_rate.noalias() = w.rate_xi * s.d_xi;
  s.d_rate.noalias() += w.rate_v * s.d_v;
  s.d_rate.leftCols(nv) += w.rate_base;
  return Status{};
}

// (A, B) from the chart value xi at the step's end and the Jacobians of xi
// and of the final velocity (in `end`).
template <class S>
void linearization_end(const ModelTpl<S>& m, LinearizationTpl<S>& w, const S* q0,
                       const typename LinearizationTpl<S>::Stage& end) {
  const Eigen::Index nv = m.nv;
  model_chart_retract(m, q0, end.xi.data(), w.q_stage.data());
  chart_transports(m, q0, w.q_stage.data(), end.xi.data(), w.base_transport, w.chart_transport);
  w.d_tangent.noalias() = w.chart_transport * end.d_xi;
  w.d_tangent.leftCols(nv) += w.base_transport;
  w.A.topRows(nv) = w.d_tangent.leftCols(2 * nv);
  w.B.topRows(nv) = w.d_tangent.rightCols(nv);
  w.A.bottomRows(nv) = end.d_v.leftCols(2 * nv);
  w.B.bottomRows(nv) = end.d_v.rightCols(nv);
}

template <class S>
void start_stage(const ModelTpl<S>& m, typename LinearizationTpl<S>::Stage& s, const ConstVecRef<S>& v) {
  const Eigen::Index nv = m.nv;
  s.xi.setZero();
  s.v = v;
  s.d_xi.setZero();
  s.d_v.setZero();
  s.d_v.middleCols(nv, nv).setIdentity();
}

}  // namespace detail

template <class S>
Status linearize(const ModelTpl<S>& m, DataTpl<S>& d, LinearizationTpl<S>& w, const ConstVecRef<S>& q,
                 const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext) {
  const Status status = detail::hybrid_derivatives(m, d, w, q, v, u, f_ext);
  if (!status.ok()) return status;
  const Eigen::Index nv = m.nv;
  lie_bracket_matrix(m, v.data(), w.bracket);
  w.A.topLeftCorner(nv, nv) = S(-0.5) * w.bracket;
  w.A.topRightCorner(nv, nv).setIdentity();
  w.A.bottomLeftCorner(nv, nv) = w.derivatives.dqdd_dq;
  w.A.bottomRightCorner(nv, nv) = w.derivatives.dqdd_dv;
  w.B.topRows(nv).setZero();
  w.B.bottomRows(nv) = w.derivatives.dqdd_du;
  return status;
}

template <class S>
Status linearize_step(const ModelTpl<S>& m, DataTpl<S>& d, LinearizationTpl<S>& w, const ConstVecRef<S>& q,
                      const ConstVecRef<S>& v, const ConstVecRef<S>& u, S dt, Integrator integrator,
                      const S* f_ext) {
  using std::isfinite;
  if (!(isfinite(static_cast<double>(dt)) && dt > S(0)))
    throw std::invalid_argument("linearize: the step dt must be finite and positive");
  using Stage = typename LinearizationTpl<S>::Stage;
  const S* q0 = q.data();
  if (integrator == Integrator::dopri5)
    throw std::invalid_argument("linearize: integrator 'dopri5' adapts its sub-steps, so its step has no fixed "
                                "discrete map (choose 'rk4' or 'euler', or the continuous system)");
  if (integrator == Integrator::semi_implicit_euler) {
    // v' = v + dt qdd(q, v, u); q' = retract(q, dt rate(q, 0, v')).
    Stage& s = w.stages[0];
    detail::start_stage(m, s, v);
    Status status = detail::linearization_stage(m, d, w, s, q0, u, f_ext);
    if (!status.ok()) return status;
    Stage& end = w.stages[4];
    end.v = s.v + dt * s.acceleration;
    end.d_v = s.d_v + dt * s.d_acceleration;
    end.xi.setZero();
    chart_rate_jacobians(m, q0, q0, end.xi.data(), end.v.data(), w.rate_base, w.rate_xi, w.rate_v);
    model_chart_rate(m, q0, end.xi.data(), end.v.data(), end.rate.data());
    end.d_xi.noalias() = dt * (w.rate_v * end.d_v);
    end.d_xi.leftCols(m.nv) += dt * w.rate_base;
    end.xi = dt * end.rate;
    detail::linearization_end(m, w, q0, end);
    return status;
  }
  // Classical RK4 (the Simulator's tableau, simulator.hxx).
  static constexpr double a[4][4] = {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1, 0}};
  static constexpr double b[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  for (int k = 0; k < 4; ++k) {
    Stage& s = w.stages[static_cast<std::size_t>(k)];
    detail::start_stage(m, s, v);
    for (int j = 0; j < k; ++j) {
      if (a[k][j] == 0.0) continue;
      const Stage& p = w.stages[static_cast<std::size_t>(j)];
      const S h = dt * S(a[k][j]);
      s.xi += h * p.rate;
      s.v += h * p.acceleration;
      s.d_xi += h * p.d_rate;
      s.d_v += h * p.d_acceleration;
    }
    const Status status = detail::linearization_stage(m, d, w, s, q0, u, f_ext);
    if (!status.ok()) return status;
  }
  Stage& end = w.stages[4];
  detail::start_stage(m, end, v);
  for (int k = 0; k < 4; ++k) {
    const Stage& s = w.stages[static_cast<std::size_t>(k)];
    const S h = dt * S(b[k]);
    end.xi += h * s.rate;
    end.d_xi += h * s.d_rate;
    end.v += h * s.acceleration;
    end.d_v += h * s.d_acceleration;
  }
  detail::linearization_end(m, w, q0, end);
  return Status{};
}

}  // namespace soadyn
