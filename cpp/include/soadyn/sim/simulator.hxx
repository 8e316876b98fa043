#pragma once
#include <cmath>
#include <stdexcept>
#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/algorithms/energy.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/sim/chart.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn {

namespace tableau {
// Classical Runge-Kutta.
constexpr double rk4_a[16] = {0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1, 0};
constexpr double rk4_b[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
constexpr double rk4_c[4] = {0, 0.5, 0.5, 1};
// Dormand-Prince 5(4): 5th-order solution b, 4th-order embedded e.
constexpr double dp_a[49] = {
    0, 0, 0, 0, 0, 0, 0,
    1.0 / 5, 0, 0, 0, 0, 0, 0,
    3.0 / 40, 9.0 / 40, 0, 0, 0, 0, 0,
    44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0, 0,
    19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0, 0,
    9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0, 0,
    35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
constexpr double dp_b[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
constexpr double dp_e[7] = {5179.0 / 57600, 0, 7571.0 / 16695, 393.0 / 640, -92097.0 / 339200, 187.0 / 2100, 1.0 / 40};
constexpr double dp_c[7] = {0, 0.2, 0.3, 0.8, 8.0 / 9, 1, 1};
}  // namespace tableau

template <class S>
SimulatorTpl<S>::SimulatorTpl(const ModelTpl<S>& model, S dt, Integrator integrator, int event_capacity)
    : model_(model), data_(model_), dt_(dt), adaptive_h_(dt), integrator_(integrator) {
  if (!(dt > S(0)) || !std::isfinite(static_cast<double>(dt))) throw std::invalid_argument("dt must be positive");
  if (event_capacity < 0) throw std::invalid_argument("event capacity must be >= 0");
  const int nv = model_.nv, nq = model_.nq;
  q_.resize(nq);
  neutral_configuration<S>(model_, q_);
  for (VecX<S>* x : {&v_, &inputs_, &forces_, &u_, &source_offset_, &held_position_, &xi_, &vs_, &xi_err_, &v_err_,
                     &v0_, &v_save_})
    x->setZero(nv);
  for (VecX<S>* x : {&q0_, &qs_, &q_save_}) x->setZero(nq);
  k_xi_.assign(7, VecX<S>::Zero(nv));
  k_v_.assign(7, VecX<S>::Zero(nv));
  drive_.assign(static_cast<std::size_t>(nv), Drive::regular);
  source_of_.assign(static_cast<std::size_t>(nv), -1);
  coordinate_of_.assign(static_cast<std::size_t>(nv), -1);
  for (int b = 0; b < model_.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const bool scalar = joint_has_scalar_coordinates(model_.joints[bi]);
    if (!scalar) curved_chart_bodies_.push_back(b);
    for (int k = 0; k < model_.nv_body[bi]; ++k) {
      const std::size_t dof = static_cast<std::size_t>(model_.v_index[bi] + k);
      coordinate_of_[dof] = scalar ? model_.q_index[bi] + k : -1;
    }
    for (int k = 0; k < model_.n_modes[bi]; ++k) {  // modal coordinates: q' = v
      const std::size_t dof = static_cast<std::size_t>(model_.modal_v_index(b) + k);
      coordinate_of_[dof] = model_.modal_q_index(b) + k;
    }
  }
  for (int dof = 0; dof < nv; ++dof)
    if (model_.is_prescribed(dof)) drive_[static_cast<std::size_t>(dof)] = Drive::held;
  events_.reserve(static_cast<std::size_t>(event_capacity));
  event_capacity_ = static_cast<std::size_t>(event_capacity);
}

template <class S>
void SimulatorTpl<S>::check_dof(int dof) const {
  if (dof < 0 || dof >= model_.nv) throw std::invalid_argument("DOF index " + std::to_string(dof) + " is out of range");
}

template <class S>
void SimulatorTpl<S>::check_drivable(int dof) const {
  check_dof(dof);
  if (model_.is_modal(dof))
    throw std::invalid_argument("DOF '" + model_.dof_names[static_cast<std::size_t>(dof)] +
                                "' is a modal coordinate: modal DOFs are always regular and cannot be driven");
}

template <class S>
void SimulatorTpl<S>::set_state(const ConstVecRef<S>& q, const ConstVecRef<S>& v, S time) {
  if (q.size() != model_.nq || v.size() != model_.nv) throw std::invalid_argument("state has the wrong size");
  q_ = q;
  v_ = v;
  time_ = time;
  for (int dof = 0; dof < model_.nv; ++dof) {  // held DOFs hold where they are put, at rest
    const std::size_t d = static_cast<std::size_t>(dof);
    if (drive_[d] == Drive::held) {
      v_[dof] = S(0);
      if (coordinate_of_[d] >= 0) held_position_[dof] = q_[coordinate_of_[d]];
    } else if (drive_[d] == Drive::sourced && coordinate_of_[d] >= 0) {
      const MotionSample<S> s = sample_source(sources_[static_cast<std::size_t>(source_of_[d])], time_);
      source_offset_[dof] = q_[coordinate_of_[d]] - s.position;
      v_[dof] = s.velocity;
    }
  }
}

template <class S>
void SimulatorTpl<S>::set_input(int dof, S torque) {
  check_dof(dof);
  inputs_[dof] = torque;
}

template <class S>
void SimulatorTpl<S>::check_sourceable(int dof) const {
  check_drivable(dof);
  if (coordinate_of_[static_cast<std::size_t>(dof)] < 0)
    throw std::invalid_argument("DOF '" + model_.dof_names[static_cast<std::size_t>(dof)] +
                                "' has no scalar coordinate (planar, spherical or free joint): it can be locked or "
                                "released, not given a motion source");
}

template <class S>
void SimulatorTpl<S>::prescribe(int dof, MotionSource<S> source) {
  check_sourceable(dof);
  sources_.push_back(std::move(source));
  const Status s = switch_mode(dof, Drive::sourced, static_cast<int>(sources_.size()) - 1, true);
  if (!s.ok()) throw std::runtime_error(std::string("prescribe: ") + status_message(s.code));
}

template <class S>
int SimulatorTpl<S>::schedule(S time, EventKind kind, int dof) {
  check_drivable(dof);
  if (kind == EventKind::prescribe) throw std::invalid_argument("use schedule_prescribe for prescribe events");
  if (events_.size() >= event_capacity_) throw std::invalid_argument("event capacity exhausted");
  Event<S> e;
  e.time = time;
  e.kind = kind;
  e.dof = dof;
  auto at = events_.begin();
  while (at != events_.end() && at->time <= time) ++at;  // keep time order (stable)
  return static_cast<int>(events_.insert(at, e) - events_.begin());
}

template <class S>
int SimulatorTpl<S>::schedule_prescribe(S time, int dof, MotionSource<S> source) {
  check_sourceable(dof);
  sources_.push_back(std::move(source));
  const int index = schedule(time, EventKind::lock, dof);
  events_[static_cast<std::size_t>(index)].kind = EventKind::prescribe;
  events_[static_cast<std::size_t>(index)].source = static_cast<int>(sources_.size()) - 1;
  return index;
}

template <class S>
Status SimulatorTpl<S>::lock(int dof) {
  if (dof < 0 || dof >= model_.nv || model_.is_modal(dof)) return Status{StatusCode::invalid_dof, dof};
  return switch_mode(dof, Drive::held, -1, true);
}

template <class S>
Status SimulatorTpl<S>::release(int dof) {
  if (dof < 0 || dof >= model_.nv || model_.is_modal(dof)) return Status{StatusCode::invalid_dof, dof};
  return switch_mode(dof, Drive::regular, -1, false);
}

// Switches a DOF's drive. Becoming driven at a velocity other than its own is
// an impact: the hybrid algorithm in impulse form gives the velocity jumps of
// every DOF when the switching DOF's jump is prescribed, the other driven
// DOFs keep theirs, and the regular DOFs receive no impulse.
template <class S>
Status SimulatorTpl<S>::switch_mode(int dof, Drive drive, int source, bool impulse) {
  const std::size_t d = static_cast<std::size_t>(dof);
  const int coordinate = coordinate_of_[d];
  drive_[d] = drive;
  source_of_[d] = source;
  model_.set_prescribed(dof, drive != Drive::regular);
  if (drive == Drive::regular) return Status{};
  S target_velocity(0);
  if (drive == Drive::sourced) {
    const MotionSample<S> s = sample_source(sources_[static_cast<std::size_t>(source)], time_);
    target_velocity = s.velocity;
    if (coordinate >= 0) source_offset_[dof] = q_[coordinate] - s.position;
  } else if (coordinate >= 0) {
    held_position_[dof] = q_[coordinate];
  }
  if (!impulse || target_velocity == v_[dof]) return Status{};
  // Only a lock's energy change is recorded (see below): skip the sweep otherwise.
  const S energy_before = drive == Drive::held ? kinetic_energy<S>(model_, data_, q_, v_) : S(0);
  u_.setZero();
  u_[dof] = target_velocity - v_[dof];
  const Status s = hybrid_impulse<S>(model_, data_, q_, u_);
  if (!s.ok()) return s;
  v_ += data_.qdd;
  v_[dof] = target_velocity;  // exact, not up to round-off
  // A lock is a plastic impact and only loses energy; a source's velocity
  // jump is work done by the drive, not counted as lost.
  if (drive == Drive::held) energy_lost_ += energy_before - kinetic_energy<S>(model_, data_, q_, v_);
  return Status{};
}

template <class S>
Status SimulatorTpl<S>::fire_due_events() {
  const S due = time_ + S(1e-9) * dt_;
  for (Event<S>& e : events_) {
    if (e.fired || e.time > due) continue;
    e.fired = true;
    Status s;
    if (e.kind == EventKind::lock) s = lock(e.dof);
    else if (e.kind == EventKind::release) s = release(e.dof);
    else s = switch_mode(e.dof, Drive::sourced, e.source, true);
    if (!s.ok()) return s;
  }
  return Status{};
}

// u: torque of regular DOFs, acceleration of driven ones; qdd out.
template <class S>
Status SimulatorTpl<S>::evaluate(S t, const VecX<S>& q, const VecX<S>& v, VecX<S>& qdd) {
  // Regular DOFs take their inputs; the prescribed ones (a DOF is prescribed
  // in the model exactly when it is held or sourced) are then overwritten.
  u_ = inputs_;
  for (int k = 0; k < model_.n_prescribed; ++k) {
    const std::size_t d = static_cast<std::size_t>(model_.prescribed_dofs[static_cast<std::size_t>(k)]);
    u_[static_cast<Eigen::Index>(d)] = drive_[d] == Drive::held
                                          ? S(0)
                                          : sample_source(sources_[static_cast<std::size_t>(source_of_[d])], t).acceleration;
  }
  const Status s = hybrid_dynamics<S>(model_, data_, q, v, u_);
  qdd = data_.qdd;
  return s;
}

template <class S>
void SimulatorTpl<S>::chart_rates(const VecX<S>& q, const VecX<S>& xi, const VecX<S>& v, VecX<S>& rate) const {
  rate = v;  // scalar joints and modal coordinates: dxi/dt = v
  for (const int b : curved_chart_bodies_) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int iv = model_.v_index[bi];
    chart_rate(model_.joints[bi], q.data() + model_.q_index[bi], xi.data() + iv, v.data() + iv, rate.data() + iv);
  }
}

template <class S>
void SimulatorTpl<S>::retract(const VecX<S>& xi, VecX<S>& q) const {
  for (std::size_t dof = 0; dof < coordinate_of_.size(); ++dof) {  // flat charts: q = q0 + xi
    const int coordinate = coordinate_of_[dof];
    if (coordinate >= 0) q[coordinate] = q0_[coordinate] + xi[static_cast<Eigen::Index>(dof)];
  }
  for (const int b : curved_chart_bodies_) {
    const std::size_t bi = static_cast<std::size_t>(b);
    chart_retract(model_.joints[bi], q0_.data() + model_.q_index[bi], xi.data() + model_.v_index[bi],
                  q.data() + model_.q_index[bi]);
  }
}

// One explicit Runge-Kutta step of size h from (q_, v_) in the chart at q_
// (Runge-Kutta-Munthe-Kaas). With `b_error`, also the scaled RMS norm of the
// difference to the embedded solution.
template <class S>
Status SimulatorTpl<S>::runge_kutta(int stages, const S* a, const S* b, const S* c, S h, const S* b_error,
                                    S* error_norm) {
  q0_ = q_;
  v0_ = v_;
  for (int s = 0; s < stages; ++s) {
    xi_.setZero();
    vs_ = v0_;
    for (int j = 0; j < s; ++j) {
      const S w = h * a[s * stages + j];
      if (w == S(0)) continue;
      xi_ += w * k_xi_[static_cast<std::size_t>(j)];
      vs_ += w * k_v_[static_cast<std::size_t>(j)];
    }
    if (s == 0)
      qs_ = q0_;  // xi = 0: the chart's centre
    else
      retract(xi_, qs_);
    const Status st = evaluate(time_ + c[s] * h, qs_, vs_, k_v_[static_cast<std::size_t>(s)]);
    if (!st.ok()) return st;
    if (s == 0) forces_ = data_.tau;
    chart_rates(qs_, xi_, vs_, k_xi_[static_cast<std::size_t>(s)]);
  }
  xi_.setZero();
  v_ = v0_;
  xi_err_.setZero();
  v_err_.setZero();
  for (int s = 0; s < stages; ++s) {
    xi_ += h * b[s] * k_xi_[static_cast<std::size_t>(s)];
    v_ += h * b[s] * k_v_[static_cast<std::size_t>(s)];
    if (b_error) {
      xi_err_ += h * (b[s] - b_error[s]) * k_xi_[static_cast<std::size_t>(s)];
      v_err_ += h * (b[s] - b_error[s]) * k_v_[static_cast<std::size_t>(s)];
    }
  }
  retract(xi_, q_);
  if (error_norm) {
    using std::sqrt;
    S sum(0);
    for (Eigen::Index k = 0; k < xi_.size(); ++k) {
      const S sx = atol + rtol * std::abs(xi_[k]);
      const S sv = atol + rtol * std::max(std::abs(v_[k]), std::abs(v0_[k]));
      sum += (xi_err_[k] / sx) * (xi_err_[k] / sx) + (v_err_[k] / sv) * (v_err_[k] / sv);
    }
    *error_norm = xi_.size() ? sqrt(sum / S(2 * xi_.size())) : S(0);
  }
  return Status{};
}

// Dormand-Prince sub-steps across one step dt, step size kept between calls.
template <class S>
Status SimulatorTpl<S>::adaptive_step() {
  using std::pow;
  S a[49], b[7], e[7], c[7];
  for (int k = 0; k < 49; ++k) a[k] = S(tableau::dp_a[k]);
  for (int k = 0; k < 7; ++k) b[k] = S(tableau::dp_b[k]), e[k] = S(tableau::dp_e[k]), c[k] = S(tableau::dp_c[k]);
  const S end = time_ + dt_;
  int attempts = 0;
  while (time_ < end - S(1e-12) * dt_) {
    if (++attempts > 100000) return Status{StatusCode::step_size_underflow, -1};
    const S h = std::min(adaptive_h_, end - time_);
    q_save_ = q_;
    v_save_ = v_;
    S err(0);
    const Status s = runge_kutta(7, a, b, c, h, e, &err);
    if (!s.ok()) return s;
    const S factor = std::clamp(S(0.9) * pow(std::max(err, S(1e-10)), S(-0.2)), S(0.2), S(5));
    if (err <= S(1)) {
      time_ += h;
      apply_sources(time_);
      if (h == adaptive_h_ || factor < S(1)) adaptive_h_ = h * factor;
    } else {
      q_ = q_save_;
      v_ = v_save_;
      adaptive_h_ = h * factor;
      if (adaptive_h_ < S(1e-14) * dt_) return Status{StatusCode::step_size_underflow, -1};
    }
  }
  time_ = end;
  return Status{};
}

// Driven DOFs follow their drive exactly: positions and velocities are set,
// not left to the integrated accelerations.
template <class S>
void SimulatorTpl<S>::apply_sources(S t) {
  for (int dof = 0; dof < model_.nv; ++dof) {
    const std::size_t d = static_cast<std::size_t>(dof);
    const int coordinate = coordinate_of_[d];
    if (drive_[d] == Drive::held) {
      v_[dof] = S(0);
      if (coordinate >= 0) q_[coordinate] = held_position_[dof];
    } else if (drive_[d] == Drive::sourced) {
      const MotionSample<S> s = sample_source(sources_[static_cast<std::size_t>(source_of_[d])], t);
      v_[dof] = s.velocity;
      q_[coordinate] = source_offset_[dof] + s.position;
    }
  }
}

template <class S>
Status SimulatorTpl<S>::step() {
  Status s = fire_due_events();
  if (!s.ok()) return s;
  switch (integrator_) {
    case Integrator::semi_implicit_euler:
      q0_ = q_;
      s = evaluate(time_, q_, v_, k_v_[0]);
      if (!s.ok()) return s;
      forces_ = data_.tau;
      v_ += dt_ * k_v_[0];
      xi_.setZero();
      chart_rates(q0_, xi_, v_, k_xi_[0]);
      xi_ = dt_ * k_xi_[0];
      retract(xi_, q_);
      time_ += dt_;
      break;
    case Integrator::rk4: {
      S a[16], b[4], c[4];
      for (int k = 0; k < 16; ++k) a[k] = S(tableau::rk4_a[k]);
      for (int k = 0; k < 4; ++k) b[k] = S(tableau::rk4_b[k]), c[k] = S(tableau::rk4_c[k]);
      s = runge_kutta(4, a, b, c, dt_, nullptr, nullptr);
      if (!s.ok()) return s;
      time_ += dt_;
      break;
    }
    case Integrator::dopri5:
      s = adaptive_step();
      if (!s.ok()) return s;
      break;
  }
  apply_sources(time_);
  ++steps_;
  for (Eigen::Index k = 0; k < v_.size(); ++k)
    if (!std::isfinite(static_cast<double>(v_[k]))) return Status{StatusCode::non_finite_result, static_cast<int>(k)};
  return Status{};
}

}  // namespace soadyn
