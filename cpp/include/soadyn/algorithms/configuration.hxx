#pragma once
#include <cmath>
#include "soadyn/algorithms/configuration.hpp"

namespace soadyn {

template <class S>
void neutral_configuration(const ModelTpl<S>& m, VecRef<S> q) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    joint_neutral(m.joints[i], q.data() + m.q_index[i]);
    q.segment(m.modal_q_index(static_cast<int>(i)), m.n_modes[i]).setZero();  // undeformed
  }
}

template <class S>
void random_configuration(const ModelTpl<S>& m, std::uint64_t seed, VecRef<S> q) {
  CoordinateSampler draw(seed);
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    joint_random(m.joints[i], draw, q.data() + m.q_index[i]);
    for (int k = 0; k < m.n_modes[i]; ++k) q[m.modal_q_index(static_cast<int>(i)) + k] = S(draw.uniform(-0.1, 0.1));
  }
}

template <class S>
void integrate(const ModelTpl<S>& m, const ConstVecRef<S>& q, const ConstVecRef<S>& v, S dt, VecRef<S> q_out) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    joint_integrate(m.joints[i], q.data() + m.q_index[i], v.data() + m.v_index[i], dt, q_out.data() + m.q_index[i]);
    const int b = static_cast<int>(i);
    q_out.segment(m.modal_q_index(b), m.n_modes[i]) =
        q.segment(m.modal_q_index(b), m.n_modes[i]) + dt * v.segment(m.modal_v_index(b), m.n_modes[i]);
  }
}

template <class S>
bool unit_quaternion(const S* x, S tolerance, S* norm) {
  using std::abs;
  const S n = Eigen::Map<const VecX<S>>(x, 4).norm();
  if (norm) *norm = n;
  return abs(n - S(1)) <= tolerance;  // false for a NaN norm
}

template <class S>
std::vector<int> quaternion_coordinates(const ModelTpl<S>& m) {
  std::vector<int> starts;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int qo = joint_quaternion_offset(m.joints[i]);
    if (qo >= 0) starts.push_back(m.q_index[i] + qo);
  }
  return starts;
}

template <class S>
int first_non_unit_quaternion(const ModelTpl<S>& m, const ConstVecRef<S>& q, S tolerance, S* norm) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int qo = joint_quaternion_offset(m.joints[i]);
    if (qo >= 0 && !unit_quaternion(q.data() + m.q_index[i] + qo, tolerance, norm)) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace soadyn
