// Local coordinates for integrating q on the joint manifolds (Runge-Kutta-
// Munthe-Kaas). Around a base configuration q0 every joint has a chart of
// dimension nv: q = retract(q0, xi). Classical Runge-Kutta on xi and v is
// then of full order and keeps every quaternion exactly on the unit sphere
// (it only ever multiplies by exact exponentials). Each joint's
// configuration space (its `Space`: joints/vector_space.hpp, planar.hpp,
// spherical.hpp, free.hpp) defines its chart.
#pragma once
#include "soadyn/joints/joint.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {

template <class S>
void chart_retract(const JointModel<S>& j, const S* q0, const S* xi, S* q) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::retract(q0, xi, q); }, j);
}

// dxi/dt at the configuration q = retract(q0, xi) for velocity v.
template <class S>
void chart_rate(const JointModel<S>& j, const S* q, const S* xi, const S* v, S* rate) {
  std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::chart_rate(q, xi, v, rate); }, j);
}

}  // namespace soadyn

namespace soadyn {

// The chart's first-order maps of every joint (joints/vector_space.hpp
// documents them) into nv x nv matrices; modal coordinates are flat charts.
// `q0` the base, `q` = retract(q0, xi).
template <class S>
void chart_transports(const ModelTpl<S>& m, const S* q0, const S* q, const S* xi, MatX<S>& base, MatX<S>& chart) {
  base.setIdentity();
  chart.setIdentity();
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int iq = m.q_index[bi], iv = m.v_index[bi];
    std::visit([&](const auto& jj) {
      using Space = typename detail::joint_type<decltype(jj)>::Space;
      Space::base_transport(q0 + iq, q + iq, xi + iv, base, iv);
      Space::chart_transport(q0 + iq, q + iq, xi + iv, chart, iv);
    }, m.joints[bi]);
  }
}

// d chart_rate / d(tangent at q0), / d xi, / d v at (q0, xi, v).
template <class S>
void chart_rate_jacobians(const ModelTpl<S>& m, const S* q0, const S* q, const S* xi, const S* v, MatX<S>& d_base,
                          MatX<S>& d_xi, MatX<S>& d_v) {
  d_base.setZero();
  d_xi.setZero();
  d_v.setIdentity();
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int iq = m.q_index[bi], iv = m.v_index[bi];
    std::visit([&](const auto& jj) {
      detail::joint_type<decltype(jj)>::Space::rate_jacobians(q0 + iq, q + iq, xi + iv, v + iv, d_base, d_xi, d_v, iv);
    }, m.joints[bi]);
  }
}

// ad_v (nv x nv): the Lie bracket [v, .] of the joints' groups, zero for flat ones.
template <class S>
void lie_bracket_matrix(const ModelTpl<S>& m, const S* v, MatX<S>& ad) {
  ad.setZero();
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int iv = m.v_index[bi];
    std::visit([&](const auto& jj) { detail::joint_type<decltype(jj)>::Space::bracket(v + iv, ad, iv); }, m.joints[bi]);
  }
}

// q = retract(q0, xi) and dxi/dt = chart_rate for the whole model (modal
// coordinates flat), as the Simulator steps.
template <class S>
void model_chart_retract(const ModelTpl<S>& m, const S* q0, const S* xi, S* q) {
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    chart_retract(m.joints[bi], q0 + m.q_index[bi], xi + m.v_index[bi], q + m.q_index[bi]);
    for (int k = 0; k < m.n_modes[bi]; ++k) q[m.modal_q_index(b) + k] = q0[m.modal_q_index(b) + k] + xi[m.modal_v_index(b) + k];
  }
}

template <class S>
void model_chart_rate(const ModelTpl<S>& m, const S* q, const S* xi, const S* v, S* rate) {
  for (int k = 0; k < m.nv; ++k) rate[k] = v[k];
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int iv = m.v_index[bi];
    chart_rate(m.joints[bi], q + m.q_index[bi], xi + iv, v + iv, rate + iv);
  }
}

}  // namespace soadyn
