// Exact linearizations of the dynamics: continuous (A, B) and the discrete map
// of one Simulator step.
//
// State x = (e, v): e (nv) perturbs q in the tangent space of integrate
// (q = integrate(q_bar, e)); input u as hybrid_dynamics (torque of regular
// DOFs, acceleration of prescribed DOFs).
//
// Continuous: dx/dt ~ f(x_bar, u_bar) + A dx + B du with
//   A = [[-1/2 ad_v, I], [dqdd/dq, dqdd/dv]],  B = [[0], [dqdd/du]]
// (analysis/dynamics_derivatives.hpp). The kinematic block: q = q_bar exp(e)
// moves with body velocity v = Jr(e) de/dt, so de/dt = v + 1/2 [e, v] + O(e^2),
// whose e-derivative is -1/2 ad_v: the joints' Lie brackets (so(3), se(3),
// se(2)), zero for vector-space joints and at rest.
//
// Discrete: the exact Jacobian of one step of the Simulator's explicit
// integrators (semi-implicit Euler and RK4; inputs held over the step), from
// (e, v) at q_bar to (e', v') at the step's end q_bar': the chain rule
// through the stages in the chart at the step's start (sim/chart.hpp), each
// stage with the analytic dynamics derivatives at the stage point and the
// chart's first-order maps (joints/vector_space.hpp and the curved spaces).
// Dormand-Prince adapts its sub-steps, so its step has no fixed map: refused.
//
// Models without loops. Rigid models take the analytic derivatives
// (DynamicsDerivativesTpl): everything is allocated in the constructor and
// the calls allocate nothing. Models with flexible bodies or point springs
// take the dual-number sweeps (ParameterSensitivity::state_derivatives,
// exact to rounding; analysis only: those calls allocate).
#pragma once
#include <memory>
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn {

template <class S>
struct LinearizationTpl {
  explicit LinearizationTpl(const ModelTpl<S>& model);

  MatX<S> A, B;  // (2nv x 2nv), (2nv x nv)
  DynamicsDerivativesTpl<S> derivatives;
  // The dual-number sweeps, for models the analytic ones do not take (null otherwise).
  std::unique_ptr<ParameterSensitivity> dual;

  // Scratch. One stage of an explicit Runge-Kutta step: its chart point xi,
  // velocity v, rate dxi/dt and acceleration, and their Jacobians with respect
  // to (e at the step's base, v, u) (nv x 3nv each).
  struct Stage {
    VecX<S> xi, v, rate, acceleration;
    MatX<S> d_xi, d_v, d_rate, d_acceleration;
  };
  std::vector<Stage> stages;  // four Runge-Kutta stages, then the step's end
  VecX<S> q_stage;
  MatX<S> base_transport, chart_transport, rate_base, rate_xi, rate_v, d_tangent, bracket;
};

using Linearization = LinearizationTpl<double>;

// Continuous (A, B) at (q, v, u) into lin.A, lin.B. Returns the status of
// dynamics_derivatives.
template <class S>
Status linearize(const ModelTpl<S>& model, DataTpl<S>& data, LinearizationTpl<S>& lin, const ConstVecRef<S>& q,
                 const ConstVecRef<S>& v, const ConstVecRef<S>& u, const S* f_ext = nullptr);

// (A, B) of one step of `integrator` of length dt from (q, v) with input u.
// Throws std::invalid_argument for Integrator::dopri5 or dt not finite and
// positive; otherwise returns the first failing status of the stages.
template <class S>
Status linearize_step(const ModelTpl<S>& model, DataTpl<S>& data, LinearizationTpl<S>& lin, const ConstVecRef<S>& q,
                      const ConstVecRef<S>& v, const ConstVecRef<S>& u, S dt, Integrator integrator,
                      const S* f_ext = nullptr);

extern template struct LinearizationTpl<double>;

}  // namespace soadyn
