// A guard that stops a simulation whose integration is diverging before any
// value of its state stops being finite (SimulatorTpl::set_divergence_guard;
// on by default in HIL runs).
//
// What breaks a fixed-step integration is not speed: a reaction wheel may
// spin at any rate its dynamics allow, since nothing depends on its angle.
// It is energy that the integrator creates: past its stability limit (a
// step too long for the fastest coupled motion), each step multiplies the
// error, and the state's mechanical energy E = T + V (kinetic, gravity,
// springs, strain) grows far beyond what the forces acting on the hinges
// could have supplied. For the exact dynamics,
//
//   E(t) - E(t0) <= W(t) = sum over steps of dt * sum_i |f_i| max(|v_i|, |v_i'|),
//
// f the generalized forces the step applied (regular DOFs: their inputs;
// prescribed DOFs: the drive's torque), v and v' the velocities at the
// step's ends; dampers, lock impulses and loop projection only remove
// energy. The guard trips when
//
//   E - E(t0) > budget_factor * W + slack * E_scale,
//
// E_scale the largest T + |V| seen up to the step before (rounding and the
// integrator's own energy error of a nominal run are a small fraction of
// it: semi-implicit Euler's oscillates by about dt * omega of it). The
// reference t0 restarts at set_state and after each event (a prescribed
// velocity jump changes E at once, by the drive's impulse).
//
// Per-DOF velocity limits (settable; none by default) add a plain bound
// |v_i| <= limit_i for DOFs whose hardware has one.
//
// What it does not guarantee: a diverging step that goes from finite to
// non-finite in one step (a state already far beyond its limits) stops with
// StatusCode::non_finite_result instead; a divergence fed by forces the
// budget counts (a command at its limit pumping a resonance) is physics, not
// divergence, and is not stopped.
//
// Memory policy: construction and set_velocity_limits allocate; judge()
// allocates nothing and never throws.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

template <class S>
class DivergenceGuardTpl {
 public:
  static constexpr double budget_factor = 2.0;
  static constexpr double slack = 0.5;

  explicit DivergenceGuardTpl(int nv)
      : velocity_limit_(VecX<S>::Constant(nv, std::numeric_limits<S>::infinity())) {}

  bool enabled() const { return enabled_; }
  void set_enabled(bool on) { enabled_ = on; }

  // |v_i| <= limits[i] (+inf: no limit). Throws std::invalid_argument naming
  // the first DOF index whose limit is NaN or not positive, or a wrong size.
  void set_velocity_limits(const VecX<S>& limits) {
    if (limits.size() != velocity_limit_.size())
      throw std::invalid_argument("velocity limits: expected " + std::to_string(velocity_limit_.size()) +
                                  " values, got " + std::to_string(limits.size()));
    for (Eigen::Index i = 0; i < limits.size(); ++i)
      if (!(limits[i] > S(0)))
        throw std::invalid_argument("velocity limit of DOF " + std::to_string(i) + " must be > 0, got " +
                                    std::to_string(scalar_value(limits[i])));
    velocity_limit_ = limits;
  }
  const VecX<S>& velocity_limits() const { return velocity_limit_; }

  // The reference state: its energy and its magnitude T + |V|.
  void restart(S energy, S magnitude) {
    reference_energy_ = energy;
    work_bound_ = S(0);
    scale_ = magnitude;
  }

  // Judges a step of length dt from velocities v to v_next that applied the
  // generalized forces `forces` and ended with energy `energy` (magnitude
  // T + |V|). On success the budget moves on; otherwise it is unchanged and
  // `dof` names the DOF at fault: the first beyond its velocity limit, or the
  // one whose speed grew most in the step. Without check_energy (forces the
  // generalized ones leave out act: external wrenches) only the velocity limits are judged.
  bool judge(const VecX<S>& v, const VecX<S>& v_next, const VecX<S>& forces, S dt, S energy, S magnitude,
             int& dof, bool check_energy = true) {
    using std::abs;
    using std::max;
    dof = -1;
    S power(0);
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      const S speed = max(abs(v[i]), abs(v_next[i]));
      power += abs(forces[i]) * speed;
      if (abs(v_next[i]) > velocity_limit_[i]) {
        dof = static_cast<int>(i);
        return false;
      }
    }
    const S work = work_bound_ + dt * power;
    const S allowed = S(budget_factor) * work + S(slack) * scale_ + std::numeric_limits<S>::min();
    if (check_energy && !(energy - reference_energy_ <= allowed)) {  // a NaN energy fails too
      dof = fastest_growing(v, v_next);
      return false;
    }
    work_bound_ = work;
    scale_ = max(scale_, magnitude);
    return true;
  }

 private:
  // The DOF whose speed grew most from v to v_next (the first of equals), or
  // -1 if none grew by more than -1. Asked only when a step fails, so that a
  // passing step branches on no comparison between DOFs (packets of states
  // then take one path: core/packet.hpp).
  static int fastest_growing(const VecX<S>& v, const VecX<S>& v_next) {
    using std::abs;
    int dof = -1;
    S growth(-1);
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      const S grew = abs(v_next[i]) - abs(v[i]);
      if (grew > growth) {
        growth = grew;
        dof = static_cast<int>(i);
      }
    }
    return dof;
  }

  bool enabled_ = false;
  VecX<S> velocity_limit_;
  S reference_energy_ = S(0), work_bound_ = S(0), scale_ = S(0);
};

}  // namespace soadyn
