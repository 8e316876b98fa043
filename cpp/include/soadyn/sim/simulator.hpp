// Fixed-step simulation with prescribed-motion sources and run-time mode
// switching (the application of Jain & Rodriguez 1993: turntables at a rate, gimbals under
// velocity control, actuator lock-up faults).
//
// Memory policy: everything is allocated by the constructor, by prescribe()
// (which stores the source) and by schedule() (which stores the event in a
// queue whose capacity is fixed at construction). step() and the events it
// fires allocate nothing, take no lock, do no I/O and never throw; failures
// come back as a Status and leave the state as it was before the step.
//
// Setup calls (set_state, set_input, prescribe, schedule) validate their
// arguments and give the strong guarantee: when they throw, the simulator is
// unchanged. std::invalid_argument names the argument at fault;
// SimulationError carries the Status of a dynamics failure (a singular
// impulse, a motion source returning a non-finite value).
//
// Closed loops: a model with loops steps with constrained_dynamics, and
// after every step the state is projected back onto the closure manifold
// (loop_assembly.hpp): Gauss-Newton on Psi(q) = 0, then C v = 0, both moving
// only the regular DOFs (prescribed ones follow their drives exactly), to
// loop_tolerance. The integrator's drift before the projection is reported
// (last_loop_drift, max_loop_drift). Mode switches in loops use the impulse
// form with the cut impulses (constrained_impulse.hpp). set_state keeps the
// state as given: assemble it first (assemble_loops, project_loop_velocity).
//
// Threads: a simulator is not safe to use from two threads at once; the
// Python binding serialises its calls (bindings/simulator_handle.hpp).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/constraints/loop_assembly.hpp"
#include "soadyn/sim/divergence_guard.hpp"
#include "soadyn/sim/motion_source.hpp"

namespace soadyn {

enum class Integrator {
  // Velocity first, then position with the new velocity. Symplectic only
  // when the mass matrix does not depend on q (docs/guides/simulation.md: its energy drift).
  semi_implicit_euler,
  rk4,                  // classical Runge-Kutta, 4th order, on the joint manifolds
  dopri5,               // Dormand-Prince 5(4) with error control; sub-steps inside each step
};

enum class EventKind { lock, release, prescribe };

template <class S>
struct Event {
  S time = S(0);
  EventKind kind = EventKind::lock;
  int dof = -1;
  int source = -1;             // index into the simulator's stored sources (prescribe)
  std::int64_t sequence = 0;  // scheduling order: events due at the same time fire in it
};

// A dynamics failure met by a setup call (not real-time); what() names the
// DOF at fault (SimulatorTpl::describe).
struct SimulationError : std::runtime_error {
  SimulationError(const Status& s, const std::string& message) : std::runtime_error(message), status(s) {}
  Status status;
};

// The motion of a DOF's input source (SimulatorTpl::drive_by_input) from the time t0, position q0 and
// velocity v0 it started from: q = q0 + v0 s + a s^2 / 2 + jerk s^3 / 6 with s = t - t0.
template <class S>
struct InputMotion {
  S t0 = S(0), q0 = S(0), v0 = S(0), a = S(0), jerk = S(0);
};

// What a step reads and writes, saved and restored whole (a co-simulation master's rollback: the C API's
// and the FMU's saved states): time, state, inputs, external wrenches, each DOF's drive and its input source. Made by
// SimulatorTpl::make_snapshot (allocates); save and restore copy into and out of it without allocating.
// Not part of it: the motion sources given by prescribe() and the pending events (restore keeps the
// simulator's), the divergence guard's reference (restarted from the restored state).
template <class S>
struct SimulatorSnapshot {
  S time = S(0), energy_lost = S(0), adaptive_h = S(0);
  std::int64_t steps = 0;
  VecX<S> q, v, inputs, forces, source_offset, held_position, external_wrenches;
  std::vector<std::uint8_t> drive;
  std::vector<int> source_of;
  std::vector<InputMotion<S>> input_motion;  // each DOF's input source (zero for a DOF without one)
};

template <class S>
class SimulatorTpl {
 public:
  // Takes a copy of the model: the simulator owns the prescribed flags. DOFs
  // the model marks prescribed start locked (zero velocity, held position)
  // until given a source. `event_capacity` bounds schedule().
  SimulatorTpl(const ModelTpl<S>& model, S dt, Integrator integrator = Integrator::rk4, int event_capacity = 64);

  // Setup (not real-time): state, inputs, sources, events. Throw
  // std::invalid_argument naming the item at fault, or SimulationError;
  // either way the simulator is unchanged.
  // set_state: q, v and time finite, every quaternion of unit norm within
  // quaternion_tolerance() (kept as given, not renormalised), every
  // source's sample at `time` finite. A DOF driven by its input source
  // (drive_by_input) keeps the given position and velocity: its source
  // starts again from them with the same acceleration.
  void set_state(const ConstVecRef<S>& q, const ConstVecRef<S>& v, S time = S(0));
  void set_input(int dof, S torque);  // torque of a regular DOF (kept until changed)
  // Prescribes the DOF's motion from now on. The source's position is taken
  // relative to the DOF's position now (positions stay continuous); a
  // velocity jump to the source's is applied as an impulse, as for lock().
  void prescribe(int dof, MotionSource<S> source);
  // Schedules an event at `time` (finite; fires at the first step starting
  // at or after it, at the next step if it is already past); returns its
  // sequence number. lock: prescribe zero motion, applying the generalized
  // impulse that stops the hinge (momentum conserved, energy can only drop);
  // release: back to regular, q and v continuous. Pending events wait in a
  // binary heap ordered by (time, sequence): a step with none due costs one
  // comparison. At most event_capacity() events are pending at once; a
  // schedule() beyond that throws std::length_error.
  std::int64_t schedule(S time, EventKind kind, int dof);
  std::int64_t schedule_prescribe(S time, int dof, MotionSource<S> source);

  // Real-time: immediate events and the step. A failed call changes
  // nothing: lock/release leave the DOF's mode and the velocities as they
  // were; a failed step leaves q, v, time, forces and steps_taken as they
  // were after the events due at its start (each event applies whole or
  // not at all; a failing event stays pending).
  Status lock(int dof);
  Status release(int dof);
  Status step();

  // Real-time inputs of driven DOFs: the C API's and the FMU's input u of a prescribed DOF and their
  // "prescribe" switch. Every DOF with a scalar coordinate (not a modal one) has an input source, made at
  // construction, that moves it from where it is at a constant acceleration, or with a constant jerk:
  // q = q0 + v0 s + a s^2 / 2 + jerk s^3 / 6, s = t - t0, with (t0, q0, v0) the time, position and velocity
  // when the motion was set (InputMotion). drive_by_input makes a DOF follow it from now on (positions and
  // velocities continuous: no impulse); set_driven_acceleration gives the input source of a DOF that
  // follows it a new motion from now on. With jerk = 0 both equal prescribe(dof, ConstantAcceleration{
  // time(), q, v, a}) bit for bit, otherwise prescribe(dof, Polynomial{time(), {q, v, a / 2, jerk / 6}}),
  // without allocating or throwing: invalid_dof for a DOF without an input source (planar, spherical,
  // free joints; modal DOFs) or, for set_driven_acceleration, one that does not follow it;
  // non_finite_source for an acceleration or jerk that is not finite.
  Status drive_by_input(int dof, S acceleration, S jerk = S(0));
  Status set_driven_acceleration(int dof, S acceleration, S jerk = S(0));
  // Whether the DOF follows its input source (after drive_by_input, until a lock, release or prescribe).
  bool driven_by_input(int dof) const;

  // Setup: changes the physical parameters of the simulator's model in place, without a structural change
  // (`change(model)` sets values through a ParameterTable: masses, inertias, gravity, placements ...). The
  // state and the drives stay; the divergence guard restarts from the new energy. What `change` throws
  // passes through (a ParameterTable set changes nothing then). Allocation-free when `change` is.
  template <class Change>
  void change_parameters(Change&& change) {
    change(model_);
    restart_divergence_guard();
  }

  // External wrenches: [torque; force] on a body, in its frame about its origin (f_ext of forward_dynamics),
  // held until changed, like set_input. Real-time (no allocation; throws only std::invalid_argument for a
  // body index out of range, as set_input for a DOF); a wrench that is not finite fails the next step with
  // a non-finite result. The divergence guard's energy budget counts the work of the generalized forces
  // only: while a wrench is applied it checks the velocity limits alone.
  void set_external_wrench(int body, const Vec6<S>& wrench);
  void clear_external_wrenches();
  // (nbodies x 6): each body's external wrench.
  const VecX<S>& external_wrenches() const { return external_wrenches_; }

  // The accelerations and generalized forces at the present time, state and inputs (what the next step's
  // first stage evaluates); qdd and tau must have nv entries. Real-time; changes nothing a step reads.
  Status evaluate_now(VecX<S>& qdd, VecX<S>& tau);

  // Saved states (see SimulatorSnapshot). restore fails (invalid_dof) for a snapshot of another model's
  // size and changes nothing then.
  SimulatorSnapshot<S> make_snapshot() const;
  void save(SimulatorSnapshot<S>& snapshot) const;
  Status restore(const SimulatorSnapshot<S>& snapshot);

  // A Status as a sentence naming the DOF and the time (allocates; not real-time).
  std::string describe(const Status& s) const;
  static S quaternion_tolerance();

  const ModelTpl<S>& model() const { return model_; }
  DataTpl<S>& data() { return data_; }
  const VecX<S>& q() const { return q_; }
  const VecX<S>& v() const { return v_; }
  const VecX<S>& inputs() const { return inputs_; }
  // Generalized forces of the last evaluation at the start of the last step
  // (prescribed DOFs: the torque the drive had to apply).
  const VecX<S>& forces() const { return forces_; }
  S time() const { return time_; }
  S dt() const { return dt_; }
  // The coordinate of a DOF with a scalar coordinate (q = q0 + xi), -1 for the others.
  int coordinate_of(int dof) const { return coordinate_of_[static_cast<std::size_t>(dof)]; }
  Integrator integrator() const { return integrator_; }
  // Kinetic energy removed by lock impulses so far (>= 0).
  S energy_lost() const { return energy_lost_; }
  std::int64_t steps_taken() const { return steps_; }
  std::size_t pending_events() const { return events_.size(); }
  std::size_t event_capacity() const { return event_capacity_; }
  // Sub-step attempts (accepted and rejected) of dopri5's last step.
  int last_substeps() const { return last_substeps_; }
  // Accuracy of the adaptive integrator (relative and absolute per component).
  S rtol = S(1e-10), atol = S(1e-12);
  // dopri5: attempts allowed in one step before it stops with
  // StatusCode::substep_limit (a bound on the step's run time).
  int max_substeps = 1000;
  // Loop closure after each step: largest |Psi_i| allowed, and the Gauss-Newton
  // steps allowed to reach it (StatusCode::loop_not_closed beyond).
  S loop_tolerance = default_closure_tolerance<S>();
  int loop_max_iterations = 10;
  // Largest loop-closure residuals |Psi_i| and |(C v)_i| the integrator left at
  // the end of the last step, before the projection, and their maxima over all steps.
  S last_loop_drift_position() const { return drift_position_; }
  S last_loop_drift_velocity() const { return drift_velocity_; }
  S max_loop_drift_position() const { return max_drift_position_; }
  S max_loop_drift_velocity() const { return max_drift_velocity_; }

  // The divergence guard (sim/divergence_guard.hpp): off by default, on in
  // HIL runs. When on, a step whose state's energy grew beyond what the
  // applied forces can supply, or whose velocity exceeds a DOF's velocity
  // limit, fails with StatusCode::diverging naming the DOF, and the state
  // stays at the last good step. Turning it on (setup, allocates nothing)
  // takes the current state as the energy's reference.
  void set_divergence_guard(bool on);
  bool divergence_guard() const { return guard_.enabled(); }
  // Per-DOF |v| limits the guard enforces (+inf: none, the default); throws
  // std::invalid_argument naming the DOF index at fault.
  void set_velocity_limits(const VecX<S>& limits) { guard_.set_velocity_limits(limits); }
  const VecX<S>& velocity_limits() const { return guard_.velocity_limits(); }

 private:
  enum class Drive : std::uint8_t { regular, held, sourced };
  Status advance();
  Status evaluate(S t, const VecX<S>& q, const VecX<S>& v, VecX<S>& qdd);
  void chart_rates(const VecX<S>& q, const VecX<S>& xi, const VecX<S>& v, VecX<S>& rate) const;
  void retract(const VecX<S>& xi, VecX<S>& q) const;
  Status runge_kutta(int stages, const S* a, const S* b, const S* c, S h, const S* b_error, S* error_norm);
  Status adaptive_step();
  Status apply_sources(S t);
  Status check_state_finite() const;
  Status close_loops();
  // Mechanical energy T + V at the current state, and T + |V| (divergence guard).
  void mechanical_energy(S& energy, S& magnitude);
  void restart_divergence_guard();
  Status judge_step();
  Status switch_mode(int dof, Drive drive, int source, bool impulse);
  Status fire_due_events();
  Status fire(const Event<S>& e);
  void check_event_room() const;
  void check_dof(int dof) const;
  void check_drivable(int dof) const;  // check_dof, and not a modal DOF
  void check_sourceable(int dof) const;  // check_drivable, and a scalar coordinate (coordinate_of_ >= 0)
  void rebase_input_source(int dof, S acceleration, S jerk);

  ModelTpl<S> model_;
  DataTpl<S> data_;
  S dt_, time_ = S(0), energy_lost_ = S(0), adaptive_h_;
  Integrator integrator_;
  std::int64_t steps_ = 0;
  VecX<S> q_, v_, inputs_, forces_, u_;
  // Per DOF: how it is driven, its source (index into sources_) and the
  // position offset that made it continuous when the source took over.
  std::vector<Drive> drive_;
  std::vector<int> source_of_;
  VecX<S> source_offset_, held_position_;
  std::vector<int> coordinate_of_;
  std::vector<int> dof_of_coordinate_;  // the DOF of each coordinate (a quaternion: its joint's first DOF)
  // Bodies whose joint's chart is not q = q0 + xi with dxi/dt = v (planar,
  // spherical, free): the only ones retract and chart_rates visit.
  std::vector<int> curved_chart_bodies_;
  // The other DOFs' coordinates (q = q0 + xi) as runs: DOFs dof..dof+length-1
  // have coordinates coordinate..coordinate+length-1 (retract copies a run at once).
  struct FlatChartRun {
    int dof, coordinate, length;
  };
  std::vector<FlatChartRun> flat_chart_runs_;
  // A source and its last finite sample: a source is a function of time,
  // and an RK4 step samples it twice at t + h/2, and at t + h both in its
  // last stage and in apply_sources (the next step's first stage again). A
  // sample that is not finite is not kept: the next call at that time asks
  // the source again (and a Python source raises again).
  struct SampledSource {
    MotionSource<S> source;
    S time = S(0);
    MotionSample<S> sample;
    bool sampled = false;
    MotionSample<S> at(S t);
  };
  std::vector<SampledSource> sources_;
  std::vector<int> input_source_;  // each DOF's input source (index into sources_), -1 without one
  std::vector<InputMotion<S>> input_motion_;  // the motion of each DOF's input source (its slot in sources_ samples it)
  VecX<S> external_wrenches_;                 // nbodies x 6, body frames
  bool has_external_wrench_ = false;          // some wrench is not zero: evaluate passes them to the dynamics
  std::vector<Event<S>> events_;  // binary heap, earliest (time, sequence) first; capacity reserved
  std::size_t event_capacity_;
  std::int64_t events_scheduled_ = 0;
  int last_substeps_ = 0;
  S drift_position_ = S(0), drift_velocity_ = S(0), max_drift_position_ = S(0), max_drift_velocity_ = S(0);
  VecX<S> free_dofs_;  // 1 for a regular DOF, 0 for a driven one: what the closure projection may move
  // Runge-Kutta scratch: stage rates of xi and v, base configuration.
  VecX<S> q0_, v0_, xi_, vs_, qs_, xi_err_, v_err_, q_save_, v_save_;
  // The state at the start of a step (restored when it fails), and the
  // sources' samples set_state checks before it commits.
  VecX<S> step_q_, step_v_, step_forces_, sampled_position_, sampled_velocity_;
  // Packets: the forces of the lanes that sit out a Dormand-Prince sub-step
  // attempt (adaptive_step), restored after it.
  VecX<S> kept_forces_;
  std::vector<VecX<S>> k_xi_, k_v_;
  DivergenceGuardTpl<S> guard_;
};

using Simulator = SimulatorTpl<double>;
using SimulatorF = SimulatorTpl<float>;
extern template class SimulatorTpl<double>;
extern template class SimulatorTpl<float>;

}  // namespace soadyn
