#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/constraints/constrained_dynamics.hpp"
#include "soadyn/constraints/constrained_impulse.hpp"
#include "soadyn/constraints/loop_closure.hpp"
#include "soadyn/algorithms/energy.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/sim/chart.hpp"
#include "soadyn/model/modal_rule.hpp"
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
    : model_(model), data_(model_), dt_(dt), adaptive_h_(dt), integrator_(integrator), guard_(model.nv) {
  if (!(dt > S(0)) || !std::isfinite(scalar_value(dt))) throw std::invalid_argument("dt must be positive");
  if (event_capacity < 0) throw std::invalid_argument("event capacity must be >= 0");
  const int nv = model_.nv, nq = model_.nq;
  q_.resize(nq);
  neutral_configuration<S>(model_, q_);
  for (VecX<S>* x : {&v_, &inputs_, &forces_, &u_, &source_offset_, &held_position_, &xi_, &vs_, &xi_err_, &v_err_,
                     &v0_, &v_save_, &step_v_, &step_forces_, &sampled_position_, &sampled_velocity_, &free_dofs_,
                     &kept_forces_})
    x->setZero(nv);
  for (VecX<S>* x : {&q0_, &qs_, &q_save_, &step_q_}) x->setZero(nq);
  external_wrenches_.setZero(6 * model_.nbodies());
  input_motion_.assign(static_cast<std::size_t>(nv), InputMotion<S>{});
  k_xi_.assign(7, VecX<S>::Zero(nv));
  k_v_.assign(7, VecX<S>::Zero(nv));
  drive_.assign(static_cast<std::size_t>(nv), Drive::regular);
  source_of_.assign(static_cast<std::size_t>(nv), -1);
  coordinate_of_.assign(static_cast<std::size_t>(nv), -1);
  dof_of_coordinate_.assign(static_cast<std::size_t>(nq), -1);
  for (int b = 0; b < model_.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const bool scalar = joint_has_scalar_coordinates(model_.joints[bi]);
    if (!scalar) curved_chart_bodies_.push_back(b);
    for (int k = 0; k < model_.nq_body[bi]; ++k)  // a curved joint's coordinates: its DOFs in order, then its first
      dof_of_coordinate_[static_cast<std::size_t>(model_.q_index[bi] + k)] =
          model_.v_index[bi] + std::min(k, std::max(model_.nv_body[bi] - 1, 0));
    for (int k = 0; k < model_.nv_body[bi]; ++k) {
      const std::size_t dof = static_cast<std::size_t>(model_.v_index[bi] + k);
      coordinate_of_[dof] = scalar ? model_.q_index[bi] + k : -1;
    }
    for (int k = 0; k < model_.n_modes[bi]; ++k) {  // modal coordinates: q' = v
      const std::size_t dof = static_cast<std::size_t>(model_.modal_v_index(b) + k);
      coordinate_of_[dof] = model_.modal_q_index(b) + k;
      dof_of_coordinate_[static_cast<std::size_t>(model_.modal_q_index(b) + k)] = static_cast<int>(dof);
    }
  }
  for (int dof = 0; dof < nv; ++dof) {  // runs of DOFs whose coordinates follow one another in the same order
    const int coordinate = coordinate_of_[static_cast<std::size_t>(dof)];
    if (coordinate < 0) continue;
    if (!flat_chart_runs_.empty()) {
      FlatChartRun& run = flat_chart_runs_.back();
      if (run.dof + run.length == dof && run.coordinate + run.length == coordinate) {
        ++run.length;
        continue;
      }
    }
    flat_chart_runs_.push_back(FlatChartRun{dof, coordinate, 1});
  }
  for (int dof = 0; dof < nv; ++dof)
    if (model_.is_prescribed(dof)) drive_[static_cast<std::size_t>(dof)] = Drive::held;
  input_source_.assign(static_cast<std::size_t>(nv), -1);
  for (int dof = 0; dof < nv; ++dof) {  // the input sources (drive_by_input), made once
    if (coordinate_of_[static_cast<std::size_t>(dof)] < 0 || model_.is_modal(dof)) continue;
    input_source_[static_cast<std::size_t>(dof)] = static_cast<int>(sources_.size());
    sources_.push_back({ConstantAcceleration<S>{}});
  }
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
  require_regular_modal_dof(model_, dof);
}

template <class S>
S SimulatorTpl<S>::quaternion_tolerance() {
  return std::max(S(1e-6), S(64) * std::numeric_limits<S>::epsilon());
}

namespace detail {
template <class S>
bool finite(S x) {
  return std::isfinite(scalar_value(x));
}
template <class S>
bool finite(const MotionSample<S>& m) {
  return finite(m.position) && finite(m.velocity) && finite(m.acceleration);
}
}  // namespace detail

template <class S>
MotionSample<S> SimulatorTpl<S>::SampledSource::at(S t) {
  // A source is a function of time: the cache only saves its evaluation.
  // Packets evaluate it again (their lanes' times may differ in some lanes
  // only: the comparison would split them).
  if constexpr (!is_packet_scalar_v<S>)
    if (sampled && t == time) return sample;
  const MotionSample<S> s = sample_source(source, t);
  sampled = detail::finite(s);
  sample = s;
  time = t;
  return s;
}

template <class S>
void SimulatorTpl<S>::set_state(const ConstVecRef<S>& q, const ConstVecRef<S>& v, S time) {
  if (q.size() != model_.nq || v.size() != model_.nv)
    throw std::invalid_argument("state has the wrong size: q needs " + std::to_string(model_.nq) + " entries and v " +
                                std::to_string(model_.nv));
  if (!detail::finite(time)) throw std::invalid_argument("state time is not finite");
  for (Eigen::Index k = 0; k < q.size(); ++k)
    if (!detail::finite(q[k]))
      throw std::invalid_argument("q['" + model_.coordinate_names[static_cast<std::size_t>(k)] + "'] is not finite");
  for (Eigen::Index k = 0; k < v.size(); ++k)
    if (!detail::finite(v[k]))
      throw std::invalid_argument("v['" + model_.dof_names[static_cast<std::size_t>(k)] + "'] is not finite");
  S norm(0);
  const int body = first_non_unit_quaternion<S>(model_, q, quaternion_tolerance(), &norm);
  if (body >= 0)
    throw std::invalid_argument("the quaternion of joint '" + model_.joint_names[static_cast<std::size_t>(body)] +
                                "' has norm " + std::to_string(scalar_value(norm)) +
                                ", not 1 (tolerance " + std::to_string(scalar_value(quaternion_tolerance())) +
                                ")");
  for (int dof = 0; dof < model_.nv; ++dof) {  // every source at the new time, before anything changes
    const std::size_t d = static_cast<std::size_t>(dof);
    if (drive_[d] != Drive::sourced) continue;
    if (driven_by_input(dof)) {  // an input source starts again from the given state (rebased below)
      sampled_position_[dof] = q[coordinate_of_[d]];
      sampled_velocity_[dof] = v[dof];
      continue;
    }
    const MotionSample<S> s = sources_[static_cast<std::size_t>(source_of_[d])].at(time);
    if (!detail::finite(s)) {
      const Status status{StatusCode::non_finite_source, dof};
      throw SimulationError(status, "set_state: " + describe(status));
    }
    sampled_position_[dof] = s.position;
    sampled_velocity_[dof] = s.velocity;
  }
  q_ = q;
  v_ = v;
  time_ = time;
  adaptive_h_ = dt_;
  for (int dof = 0; dof < model_.nv; ++dof) {  // held DOFs hold where they are put, at rest
    const std::size_t d = static_cast<std::size_t>(dof);
    if (drive_[d] == Drive::held) {
      v_[dof] = S(0);
      if (coordinate_of_[d] >= 0) held_position_[dof] = q_[coordinate_of_[d]];
    } else if (drive_[d] == Drive::sourced) {
      source_offset_[dof] = q_[coordinate_of_[d]] - sampled_position_[dof];
      v_[dof] = sampled_velocity_[dof];
      if (driven_by_input(dof))
        rebase_input_source(dof, input_motion_[d].a, input_motion_[d].jerk);
    }
  }
  restart_divergence_guard();
}

// No finiteness check here: the HIL loop calls this in real time (it must
// not throw); a non-finite input stops the next step with a Status naming the DOF.
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
  sources_.push_back({std::move(source)});
  const Status s = switch_mode(dof, Drive::sourced, static_cast<int>(sources_.size()) - 1, true);
  if (!s.ok()) {
    sources_.pop_back();  // switch_mode changed nothing
    throw SimulationError(s, "prescribe: " + describe(s));
  }
}

template <class S>
void SimulatorTpl<S>::check_event_room() const {
  if (events_.size() >= event_capacity_)
    throw std::length_error("the event queue is full: " + std::to_string(events_.size()) +
                            " events are pending, the capacity set at construction (event_capacity)");
}

namespace detail {
// The heap's order: `a` fires after `b`.
template <class S>
bool fires_after(const Event<S>& a, const Event<S>& b) {
  return a.time > b.time || (a.time == b.time && a.sequence > b.sequence);
}
}  // namespace detail

template <class S>
std::int64_t SimulatorTpl<S>::schedule(S time, EventKind kind, int dof) {
  check_drivable(dof);
  if (kind == EventKind::prescribe) throw std::invalid_argument("use schedule_prescribe for prescribe events");
  if (!detail::finite(time)) throw std::invalid_argument("event time is not finite");
  check_event_room();
  Event<S> e;
  e.time = time;
  e.kind = kind;
  e.dof = dof;
  e.sequence = events_scheduled_++;
  events_.push_back(e);  // within the reserved capacity: no allocation
  std::push_heap(events_.begin(), events_.end(), detail::fires_after<S>);
  return e.sequence;
}

template <class S>
std::int64_t SimulatorTpl<S>::schedule_prescribe(S time, int dof, MotionSource<S> source) {
  check_sourceable(dof);
  if (!detail::finite(time)) throw std::invalid_argument("event time is not finite");
  check_event_room();
  sources_.push_back({std::move(source)});
  Event<S> e;
  e.time = time;
  e.kind = EventKind::prescribe;
  e.dof = dof;
  e.source = static_cast<int>(sources_.size()) - 1;
  e.sequence = events_scheduled_++;
  events_.push_back(e);
  std::push_heap(events_.begin(), events_.end(), detail::fires_after<S>);
  return e.sequence;
}

// The input source's sampled form: ConstantAcceleration without a jerk (bit for bit what prescribe() of
// one gives), else the cubic Polynomial {q0, v0, a / 2, jerk / 6}.
template <class S>
MotionSource<S> input_source_motion(const InputMotion<S>& m) {
  if (m.jerk == S(0)) return ConstantAcceleration<S>{m.t0, m.q0, m.v0, m.a};
  Polynomial<S> cubic;
  cubic.t0 = m.t0;
  cubic.c[0] = m.q0;
  cubic.c[1] = m.v0;
  cubic.c[2] = m.a / S(2);
  cubic.c[3] = m.jerk / S(6);
  cubic.degree = 3;
  return cubic;
}

template <class S>
void SimulatorTpl<S>::rebase_input_source(int dof, S acceleration, S jerk) {
  const std::size_t d = static_cast<std::size_t>(dof);
  input_motion_[d] = InputMotion<S>{time_, q_[coordinate_of_[d]], v_[dof], acceleration, jerk};
  SampledSource& slot = sources_[static_cast<std::size_t>(input_source_[d])];
  slot.source = input_source_motion(input_motion_[d]);
  slot.sampled = false;
}

template <class S>
bool SimulatorTpl<S>::driven_by_input(int dof) const {
  if (dof < 0 || dof >= model_.nv) return false;
  const std::size_t d = static_cast<std::size_t>(dof);
  return input_source_[d] >= 0 && drive_[d] == Drive::sourced && source_of_[d] == input_source_[d];
}

template <class S>
Status SimulatorTpl<S>::drive_by_input(int dof, S acceleration, S jerk) {
  if (dof < 0 || dof >= model_.nv || input_source_[static_cast<std::size_t>(dof)] < 0)
    return Status{StatusCode::invalid_dof, dof};
  if (!detail::finite(acceleration) || !detail::finite(jerk)) return Status{StatusCode::non_finite_source, dof};
  const std::size_t d = static_cast<std::size_t>(dof);
  const InputMotion<S> previous = input_motion_[d];
  rebase_input_source(dof, acceleration, jerk);
  const Status s = switch_mode(dof, Drive::sourced, input_source_[d], true);
  if (!s.ok()) {  // all or nothing
    input_motion_[d] = previous;
    SampledSource& slot = sources_[static_cast<std::size_t>(input_source_[d])];
    slot.source = input_source_motion(previous);
    slot.sampled = false;
  }
  return s;
}

// As prescribe(dof, ConstantAcceleration{time_, q, v, a}) does through switch_mode: the new source's
// position and velocity now are the DOF's, so its offset is zero and there is no impulse.
template <class S>
Status SimulatorTpl<S>::set_driven_acceleration(int dof, S acceleration, S jerk) {
  if (!driven_by_input(dof)) return Status{StatusCode::invalid_dof, dof};
  if (!detail::finite(acceleration) || !detail::finite(jerk)) return Status{StatusCode::non_finite_source, dof};
  rebase_input_source(dof, acceleration, jerk);
  source_offset_[dof] = S(0);
  restart_divergence_guard();
  return Status{};
}

template <class S>
void SimulatorTpl<S>::set_external_wrench(int body, const Vec6<S>& wrench) {
  if (body < 0 || body >= model_.nbodies())
    throw std::invalid_argument("body index " + std::to_string(body) + " is out of range");
  external_wrenches_.template segment<6>(6 * body) = wrench;
  has_external_wrench_ = !external_wrenches_.isZero(S(0));
}

template <class S>
void SimulatorTpl<S>::clear_external_wrenches() {
  external_wrenches_.setZero();
  has_external_wrench_ = false;
}

template <class S>
Status SimulatorTpl<S>::evaluate_now(VecX<S>& qdd, VecX<S>& tau) {
  const Status s = evaluate(time_, q_, v_, qdd);
  if (s.ok()) tau = data_.tau;
  return s;
}

template <class S>
SimulatorSnapshot<S> SimulatorTpl<S>::make_snapshot() const {
  SimulatorSnapshot<S> snapshot;
  snapshot.q.resize(model_.nq);
  for (VecX<S>* x : {&snapshot.v, &snapshot.inputs, &snapshot.forces, &snapshot.source_offset, &snapshot.held_position})
    x->resize(model_.nv);
  snapshot.external_wrenches.resize(external_wrenches_.size());
  snapshot.drive.resize(static_cast<std::size_t>(model_.nv));
  snapshot.source_of.resize(static_cast<std::size_t>(model_.nv));
  snapshot.input_motion.resize(static_cast<std::size_t>(model_.nv));
  save(snapshot);
  return snapshot;
}

template <class S>
void SimulatorTpl<S>::save(SimulatorSnapshot<S>& snapshot) const {
  snapshot.time = time_;
  snapshot.energy_lost = energy_lost_;
  snapshot.adaptive_h = adaptive_h_;
  snapshot.steps = steps_;
  snapshot.q = q_;
  snapshot.v = v_;
  snapshot.inputs = inputs_;
  snapshot.forces = forces_;
  snapshot.source_offset = source_offset_;
  snapshot.held_position = held_position_;
  snapshot.external_wrenches = external_wrenches_;
  for (std::size_t d = 0; d < drive_.size(); ++d) {
    snapshot.drive[d] = static_cast<std::uint8_t>(drive_[d]);
    snapshot.source_of[d] = source_of_[d];
    snapshot.input_motion[d] = input_motion_[d];
  }
}

template <class S>
Status SimulatorTpl<S>::restore(const SimulatorSnapshot<S>& snapshot) {
  const std::size_t nv = static_cast<std::size_t>(model_.nv);
  if (snapshot.q.size() != model_.nq || snapshot.v.size() != model_.nv || snapshot.drive.size() != nv ||
      snapshot.source_of.size() != nv || snapshot.input_motion.size() != nv ||
      snapshot.external_wrenches.size() != external_wrenches_.size())
    return Status{StatusCode::invalid_dof, -1};
  for (std::size_t d = 0; d < nv; ++d)  // a source index this simulator does not have: another simulator's
    if (snapshot.source_of[d] >= static_cast<int>(sources_.size())) return Status{StatusCode::invalid_dof, static_cast<int>(d)};
  time_ = snapshot.time;
  energy_lost_ = snapshot.energy_lost;
  adaptive_h_ = snapshot.adaptive_h;
  steps_ = snapshot.steps;
  q_ = snapshot.q;
  v_ = snapshot.v;
  inputs_ = snapshot.inputs;
  forces_ = snapshot.forces;
  source_offset_ = snapshot.source_offset;
  held_position_ = snapshot.held_position;
  external_wrenches_ = snapshot.external_wrenches;
  has_external_wrench_ = !external_wrenches_.isZero(S(0));
  for (std::size_t d = 0; d < nv; ++d) {
    drive_[d] = static_cast<Drive>(snapshot.drive[d]);
    source_of_[d] = snapshot.source_of[d];
    model_.set_prescribed(static_cast<int>(d), drive_[d] != Drive::regular);
    if (input_source_[d] < 0) continue;
    input_motion_[d] = snapshot.input_motion[d];
    SampledSource& slot = sources_[static_cast<std::size_t>(input_source_[d])];
    slot.source = input_source_motion(input_motion_[d]);
    slot.sampled = false;
  }
  for (SampledSource& source : sources_) source.sampled = false;
  restart_divergence_guard();
  return Status{};
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
// DOFs keep theirs, and the regular DOFs receive no impulse. All or nothing:
// on failure the DOF's mode and every velocity are as before.
template <class S>
Status SimulatorTpl<S>::switch_mode(int dof, Drive drive, int source, bool impulse) {
  const std::size_t d = static_cast<std::size_t>(dof);
  const int coordinate = coordinate_of_[d];
  S target_velocity(0), anchor(0);  // anchor: the source's offset or the held position
  if (drive == Drive::sourced) {
    const MotionSample<S> s = sources_[static_cast<std::size_t>(source)].at(time_);
    if (!detail::finite(s)) return Status{StatusCode::non_finite_source, dof};
    target_velocity = s.velocity;
    if (coordinate >= 0) anchor = q_[coordinate] - s.position;
  } else if (drive == Drive::held && coordinate >= 0) {
    anchor = q_[coordinate];
  }
  const Drive previous_drive = drive_[d];
  const int previous_source = source_of_[d];
  drive_[d] = drive;
  source_of_[d] = source;
  model_.set_prescribed(dof, drive != Drive::regular);
  if (drive != Drive::regular && impulse && target_velocity != v_[dof]) {
    // Only a lock's energy change is recorded (see below): skip the sweep otherwise.
    const S energy_before = drive == Drive::held ? kinetic_energy<S>(model_, data_, q_, v_) : S(0);
    u_.setZero();
    u_[dof] = target_velocity - v_[dof];
    const Status s = constrained_impulse<S>(model_, data_, q_, v_, u_);
    if (!s.ok()) {
      drive_[d] = previous_drive;
      source_of_[d] = previous_source;
      model_.set_prescribed(dof, previous_drive != Drive::regular);
      return s;
    }
    v_ += data_.qdd;
    v_[dof] = target_velocity;  // exact, not up to round-off
    // A lock is a plastic impact and only loses energy; a source's velocity
    // jump is work done by the drive, not counted as lost.
    if (drive == Drive::held) energy_lost_ += energy_before - kinetic_energy<S>(model_, data_, q_, v_);
  }
  if (drive == Drive::sourced && coordinate >= 0) source_offset_[dof] = anchor;
  if (drive == Drive::held && coordinate >= 0) held_position_[dof] = anchor;
  restart_divergence_guard();  // a switch's impulse changes the energy at once
  return Status{};
}

template <class S>
Status SimulatorTpl<S>::fire(const Event<S>& e) {
  if (e.kind == EventKind::lock) return lock(e.dof);
  if (e.kind == EventKind::release) return release(e.dof);
  return switch_mode(e.dof, Drive::sourced, e.source, true);
}

// O(1) when nothing is due (one look at the heap's top); O(log n) per event fired.
template <class S>
Status SimulatorTpl<S>::fire_due_events() {
  const S due = time_ + S(1e-9) * dt_;
  while (!events_.empty() && events_.front().time <= due) {
    const Status s = fire(events_.front());
    if (!s.ok()) return s;  // not applied: it stays pending
    std::pop_heap(events_.begin(), events_.end(), detail::fires_after<S>);
    events_.pop_back();
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
    S acceleration(0);
    if (drive_[d] == Drive::sourced) {
      acceleration = sources_[static_cast<std::size_t>(source_of_[d])].at(t).acceleration;
      if (!detail::finite(acceleration)) return Status{StatusCode::non_finite_source, static_cast<int>(d)};
    }
    u_[static_cast<Eigen::Index>(d)] = acceleration;
  }
  // hybrid_dynamics when there are no loops
  const Status s = constrained_dynamics<S>(model_, data_, q, v, u_, has_external_wrench_ ? external_wrenches_.data() : nullptr);
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
  for (const FlatChartRun& run : flat_chart_runs_)  // flat charts: q = q0 + xi
    q.segment(run.coordinate, run.length) = q0_.segment(run.coordinate, run.length) + xi.segment(run.dof, run.length);
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
    // xi = h sum_j a_sj k_xi_j, v = v0 + h sum_j a_sj k_v_j: the first term
    // assigns, so each stage passes over the vectors once per nonzero weight.
    bool first = true;
    for (int j = 0; j < s; ++j) {
      const S w = h * a[s * stages + j];
      if (w == S(0)) continue;
      if (first) {
        xi_ = w * k_xi_[static_cast<std::size_t>(j)];
        vs_ = v0_ + w * k_v_[static_cast<std::size_t>(j)];
        first = false;
      } else {
        xi_ += w * k_xi_[static_cast<std::size_t>(j)];
        vs_ += w * k_v_[static_cast<std::size_t>(j)];
      }
    }
    if (first) {
      xi_.setZero();
      vs_ = v0_;
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
  // The same sums with the weights b (and b - b_error), the first stage's assigning.
  xi_ = (h * b[0]) * k_xi_[0];
  v_ = v0_ + (h * b[0]) * k_v_[0];
  if (b_error) {
    xi_err_ = (h * (b[0] - b_error[0])) * k_xi_[0];
    v_err_ = (h * (b[0] - b_error[0])) * k_v_[0];
  }
  for (int s = 1; s < stages; ++s) {
    const std::size_t k = static_cast<std::size_t>(s);
    if (b[s] != S(0)) {
      xi_ += (h * b[s]) * k_xi_[k];
      v_ += (h * b[s]) * k_v_[k];
    }
    if (b_error && b[s] != b_error[s]) {
      xi_err_ += (h * (b[s] - b_error[s])) * k_xi_[k];
      v_err_ += (h * (b[s] - b_error[s])) * k_v_[k];
    }
  }
  retract(xi_, q_);
  if (error_norm) {
    using std::abs;
    using std::max;
    using std::sqrt;
    S sum(0);
    for (Eigen::Index k = 0; k < xi_.size(); ++k) {
      const S sx = atol + rtol * abs(xi_[k]);
      const S sv = atol + rtol * max(abs(v_[k]), abs(v0_[k]));
      sum += (xi_err_[k] / sx) * (xi_err_[k] / sx) + (v_err_[k] / sv) * (v_err_[k] / sv);
    }
    *error_norm = xi_.size() ? sqrt(sum / S(static_cast<double>(2 * xi_.size()))) : S(0);
  }
  return Status{};
}

namespace detail {

// A Dormand-Prince sub-step attempt of size h judged by its error norm: it
// is accepted when the norm is at most 1; the size kept for the next
// attempt is h times a factor 0.9 err^(-1/5) clamped to [0.2, 5] (0.2 for a
// norm that is not finite), except that an accepted attempt shortened to
// end the step on time keeps the size it had unless the factor shrinks it.
template <class T>
struct SubstepControl {
  bool accept;
  T next_h;
};

template <class T>
SubstepControl<T> control_substep(T err, T h, T adaptive_h) {
  using std::pow;
  const T factor =
      detail::finite(err) ? std::clamp(T(0.9) * pow(std::max(err, T(1e-10)), T(-0.2)), T(0.2), T(5)) : T(0.2);
  if (err <= T(1)) return {true, h == adaptive_h || factor < T(1) ? h * factor : adaptive_h};
  return {false, h * factor};
}

}  // namespace detail

// Dormand-Prince sub-steps across one step dt, step size kept between calls.
template <class S>
Status SimulatorTpl<S>::adaptive_step() {
  S a[49], b[7], e[7], c[7];
  for (int k = 0; k < 49; ++k) a[k] = S(tableau::dp_a[k]);
  for (int k = 0; k < 7; ++k) b[k] = S(tableau::dp_b[k]), e[k] = S(tableau::dp_e[k]), c[k] = S(tableau::dp_c[k]);
  const S end = time_ + dt_;
  last_substeps_ = 0;
  if constexpr (is_packet_scalar_v<S>) {
    // Each lane takes the sub-steps of its run alone: its own sizes,
    // acceptances and times, judged in double. Each attempt is made in all
    // four lanes at once; a lane that has reached the end of the step sits
    // it out (an attempt of the smallest size in play, whose state and
    // forces it discards), and a lane that rejects its attempt goes back to
    // its state before it, as the run alone does.
    constexpr int lanes = S::lanes;
    int attempts[lanes] = {};
    for (;;) {
      bool active[lanes], any = false;
      S h;
      double smallest = std::numeric_limits<double>::infinity();
      for (int l = 0; l < lanes; ++l) {
        active[l] = time_[l] < end[l] - 1e-12 * dt_[l];
        if (!active[l]) continue;
        if (attempts[l] >= max_substeps) return Status{StatusCode::substep_limit, -1};
        last_substeps_ = std::max(last_substeps_, ++attempts[l]);
        h[l] = std::min(adaptive_h_[l], end[l] - time_[l]);
        smallest = std::min(smallest, h[l]);
        any = true;
      }
      if (!any) break;
      for (int l = 0; l < lanes; ++l)
        if (!active[l]) h[l] = smallest;
      q_save_ = q_;
      v_save_ = v_;
      kept_forces_ = forces_;
      S err(0);
      const Status s = runge_kutta(7, a, b, c, h, e, &err);
      if (!s.ok()) return s;
      bool accept[lanes], any_accepted = false;
      for (int l = 0; l < lanes; ++l) {
        accept[l] = false;
        if (!active[l]) continue;
        const detail::SubstepControl<double> control = detail::control_substep(err[l], h[l], adaptive_h_[l]);
        accept[l] = control.accept;
        adaptive_h_[l] = control.next_h;
        if (control.accept) {
          time_[l] += h[l];
          any_accepted = true;
        } else if (adaptive_h_[l] < 1e-14 * dt_[l]) {
          return Status{StatusCode::step_size_underflow, -1};
        }
      }
      if (any_accepted) {
        const Status sourced = apply_sources(time_);
        if (!sourced.ok()) return sourced;
      }
      for (int l = 0; l < lanes; ++l) {
        if (!active[l])  // sat the attempt out: its forces are its last sub-step's
          for (Eigen::Index k = 0; k < forces_.size(); ++k) forces_[k][l] = kept_forces_[k][l];
        if (accept[l]) continue;
        for (Eigen::Index k = 0; k < q_.size(); ++k) q_[k][l] = q_save_[k][l];
        for (Eigen::Index k = 0; k < v_.size(); ++k) v_[k][l] = v_save_[k][l];
      }
    }
  } else {
    while (time_ < end - S(1e-12) * dt_) {
      if (last_substeps_ >= max_substeps) return Status{StatusCode::substep_limit, -1};
      ++last_substeps_;
      const S h = std::min(adaptive_h_, end - time_);
      q_save_ = q_;
      v_save_ = v_;
      S err(0);
      const Status s = runge_kutta(7, a, b, c, h, e, &err);
      if (!s.ok()) return s;
      const detail::SubstepControl<S> control = detail::control_substep(err, h, adaptive_h_);
      adaptive_h_ = control.next_h;
      if (control.accept) {
        time_ += h;
        const Status sourced = apply_sources(time_);
        if (!sourced.ok()) return sourced;
      } else {
        q_ = q_save_;
        v_ = v_save_;
        if (adaptive_h_ < S(1e-14) * dt_) return Status{StatusCode::step_size_underflow, -1};
      }
    }
  }
  time_ = end;
  return Status{};
}

// Driven DOFs follow their drive exactly: positions and velocities are set,
// not left to the integrated accelerations.
template <class S>
Status SimulatorTpl<S>::apply_sources(S t) {
  for (int k = 0; k < model_.n_prescribed; ++k) {  // the held and sourced DOFs, in ascending order
    const int dof = model_.prescribed_dofs[static_cast<std::size_t>(k)];
    const std::size_t d = static_cast<std::size_t>(dof);
    const int coordinate = coordinate_of_[d];
    if (drive_[d] == Drive::held) {
      v_[dof] = S(0);
      if (coordinate >= 0) q_[coordinate] = held_position_[dof];
    } else if (drive_[d] == Drive::sourced) {
      const MotionSample<S> s = sources_[static_cast<std::size_t>(source_of_[d])].at(t);
      if (!detail::finite(s.position) || !detail::finite(s.velocity)) return Status{StatusCode::non_finite_source, dof};
      v_[dof] = s.velocity;
      q_[coordinate] = source_offset_[dof] + s.position;
    }
  }
  return Status{};
}

template <class S>
Status SimulatorTpl<S>::check_state_finite() const {
  // A finite sum proves every entry finite; a sum that is not (a non-finite
  // entry, or finite entries whose sum overflows) looks for the entry.
  if (detail::finite(S(q_.sum() + v_.sum()))) return Status{};
  for (Eigen::Index k = 0; k < v_.size(); ++k)
    if (!detail::finite(v_[k])) return Status{StatusCode::non_finite_result, static_cast<int>(k)};
  for (Eigen::Index k = 0; k < q_.size(); ++k)
    if (!detail::finite(q_[k]))
      return Status{StatusCode::non_finite_result, dof_of_coordinate_[static_cast<std::size_t>(k)]};
  return Status{};
}

// The integration of one step from the state after the due events.
template <class S>
Status SimulatorTpl<S>::advance() {
  Status s;
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
  s = apply_sources(time_);
  if (!s.ok()) return s;
  s = check_state_finite();
  if (!s.ok()) return s;
  return close_loops();
}

// Projection onto the closure manifold after a step (see simulator.hpp).
template <class S>
Status SimulatorTpl<S>::close_loops() {
  if (model_.nloops() == 0) return Status{};
  for (int dof = 0; dof < model_.nv; ++dof) free_dofs_[dof] = model_.is_prescribed(dof) ? S(0) : S(1);
  loop_residual<S>(model_, data_, q_, v_.data());
  drift_position_ = data_.loops.residual.template lpNorm<Eigen::Infinity>();
  drift_velocity_ = data_.loops.velocity_residual.template lpNorm<Eigen::Infinity>();
  Status s = assemble_loops<S>(model_, data_, q_, free_dofs_, loop_tolerance, loop_max_iterations);
  if (!s.ok()) return s;
  s = project_loop_velocity<S>(model_, data_, q_, v_, free_dofs_);
  if (!s.ok()) return s;
  max_drift_position_ = std::max(max_drift_position_, drift_position_);
  max_drift_velocity_ = std::max(max_drift_velocity_, drift_velocity_);
  return check_state_finite();
}

template <class S>
void SimulatorTpl<S>::mechanical_energy(S& energy, S& magnitude) {
  S kinetic, potential;
  soadyn::mechanical_energy<S>(model_, data_, q_, v_, kinetic, potential);
  using std::abs;
  energy = kinetic + potential;
  magnitude = kinetic + abs(potential);
}

template <class S>
void SimulatorTpl<S>::restart_divergence_guard() {
  if (!guard_.enabled()) return;
  S energy, magnitude;
  mechanical_energy(energy, magnitude);
  guard_.restart(energy, magnitude);
}

template <class S>
void SimulatorTpl<S>::set_divergence_guard(bool on) {
  guard_.set_enabled(on);
  restart_divergence_guard();
}

// The divergence guard's verdict on the step just taken (from step_v_ to v_).
template <class S>
Status SimulatorTpl<S>::judge_step() {
  if (!guard_.enabled()) return Status{};
  S energy, magnitude;
  mechanical_energy(energy, magnitude);
  int dof = -1;
  if (guard_.judge(step_v_, v_, forces_, dt_, energy, magnitude, dof, !has_external_wrench_)) return Status{};
  return Status{StatusCode::diverging, dof};
}

template <class S>
Status SimulatorTpl<S>::step() {
  Status s = fire_due_events();
  if (!s.ok()) return s;
  step_q_ = q_;
  step_v_ = v_;
  step_forces_ = forces_;
  const S step_time = time_, step_h = adaptive_h_;
  s = advance();
  if (s.ok()) s = judge_step();
  if (!s.ok()) {
    q_ = step_q_;
    v_ = step_v_;
    forces_ = step_forces_;
    time_ = step_time;
    adaptive_h_ = step_h;
    return s;
  }
  ++steps_;
  return Status{};
}

template <class S>
std::string SimulatorTpl<S>::describe(const Status& s) const {
  std::string text = status_message(s.code);
  const bool loop_status = s.code == StatusCode::loop_not_closed || s.code == StatusCode::inconsistent_loop_equations;
  if (loop_status && s.index >= 0 && s.index < model_.nloops()) {
    text += " (loop '" + model_.loops[static_cast<std::size_t>(s.index)].name + "'";
    if (s.code == StatusCode::loop_not_closed)
      text += ", tolerance " + std::to_string(scalar_value(loop_tolerance)) + " in " +
              std::to_string(loop_max_iterations) + " Gauss-Newton steps";
    text += ")";
  }
  else if (s.index >= 0 && s.index < model_.nv) text += " (DOF '" + model_.dof_names[static_cast<std::size_t>(s.index)] + "')";
  if (s.code == StatusCode::diverging)
    text += ": the state's energy grew beyond what the applied forces can supply, or a velocity passed its "
            "limit: the integration is unstable at this step size (take a smaller dt or lower the command limits)";
  if (s.code == StatusCode::substep_limit)
    text += " (dopri5: " + std::to_string(max_substeps) + " sub-step attempts in one step, max_substeps)";
  return text + " at t = " + std::to_string(scalar_value(time_));
}

}  // namespace soadyn
