// Fixed-step simulation with prescribed-motion sources and run-time mode
// switching (the seed's application: turntables at a rate, gimbals under
// velocity control, actuator lock-up faults).
//
// Memory policy: everything is allocated by the constructor, by prescribe()
// (which stores the source) and by schedule() (which stores the event, up to
// the capacity given at construction). step() and the events it fires
// allocate nothing, take no lock, do no I/O and never throw; failures come
// back as a Status and stop the run.
#pragma once
#include <cstdint>
#include <string>
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/sim/motion_source.hpp"

namespace soadyn {

enum class Integrator {
  semi_implicit_euler,  // velocity first, then position with the new velocity (symplectic)
  rk4,                  // classical Runge-Kutta, 4th order, on the joint manifolds
  dopri5,               // Dormand-Prince 5(4) with error control; sub-steps inside each step
};

enum class EventKind { lock, release, prescribe };

template <class S>
struct Event {
  S time = S(0);
  EventKind kind = EventKind::lock;
  int dof = -1;
  int source = -1;  // index into the simulator's stored sources (prescribe)
  bool fired = false;
};

template <class S>
class SimulatorTpl {
 public:
  // Takes a copy of the model: the simulator owns the prescribed flags. DOFs
  // the model marks prescribed start locked (zero velocity, held position)
  // until given a source. `event_capacity` bounds schedule().
  SimulatorTpl(const ModelTpl<S>& model, S dt, Integrator integrator = Integrator::rk4, int event_capacity = 64);

  // Setup (not real-time): state, inputs, sources, events. Throw std::invalid_argument naming the DOF.
  void set_state(const ConstVecRef<S>& q, const ConstVecRef<S>& v, S time = S(0));
  void set_input(int dof, S torque);  // torque of a regular DOF (kept until changed)
  // Prescribes the DOF's motion from now on. The source's position is taken
  // relative to the DOF's position now (positions stay continuous); a
  // velocity jump to the source's is applied as an impulse, as for lock().
  void prescribe(int dof, MotionSource<S> source);
  // Schedules an event at `time` (fires at the first step starting at or
  // after it); returns its index. lock: prescribe zero motion, applying the
  // generalized impulse that stops the hinge (momentum conserved, energy can
  // only drop); release: back to regular, q and v continuous.
  int schedule(S time, EventKind kind, int dof);
  int schedule_prescribe(S time, int dof, MotionSource<S> source);

  // Real-time: immediate events and the step.
  Status lock(int dof);
  Status release(int dof);
  Status step();

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
  Integrator integrator() const { return integrator_; }
  // Kinetic energy removed by lock impulses so far (>= 0).
  S energy_lost() const { return energy_lost_; }
  std::int64_t steps_taken() const { return steps_; }
  // Accuracy of the adaptive integrator (relative and absolute per component).
  S rtol = S(1e-10), atol = S(1e-12);

 private:
  enum class Drive : std::uint8_t { regular, held, sourced };
  Status evaluate(S t, const VecX<S>& q, const VecX<S>& v, VecX<S>& qdd);
  void chart_rates(const VecX<S>& q, const VecX<S>& xi, const VecX<S>& v, VecX<S>& rate) const;
  void retract(const VecX<S>& xi, VecX<S>& q) const;
  Status runge_kutta(int stages, const S* a, const S* b, const S* c, S h, const S* b_error, S* error_norm);
  Status adaptive_step();
  void apply_sources(S t);
  Status switch_mode(int dof, Drive drive, int source, bool impulse);
  Status fire_due_events();
  void check_dof(int dof) const;
  void check_drivable(int dof) const;  // check_dof, and not a modal DOF
  void check_sourceable(int dof) const;  // check_drivable, and a scalar coordinate (coordinate_of_ >= 0)

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
  // Bodies whose joint's chart is not q = q0 + xi with dxi/dt = v (planar,
  // spherical, free): the only ones retract and chart_rates visit.
  std::vector<int> curved_chart_bodies_;
  std::vector<MotionSource<S>> sources_;
  std::vector<Event<S>> events_;
  std::size_t event_capacity_;
  // Runge-Kutta scratch: stage rates of xi and v, base configuration.
  VecX<S> q0_, v0_, xi_, vs_, qs_, xi_err_, v_err_, q_save_, v_save_;
  std::vector<VecX<S>> k_xi_, k_v_;
};

using Simulator = SimulatorTpl<double>;
using SimulatorF = SimulatorTpl<float>;
extern template class SimulatorTpl<double>;
extern template class SimulatorTpl<float>;

}  // namespace soadyn
