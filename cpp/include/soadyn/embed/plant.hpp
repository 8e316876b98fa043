// A simulator driven the way embedding hosts drive one (the C API, the FMU): one input u per DOF
// (torque of a regular DOF; for a DOF that follows its input, its acceleration as in hybrid_dynamics, or
// its velocity or position, per DOF: InputKind), two switches per DOF (locked, prescribed) that take effect
// at the next apply_inputs, and wrenches on named frames. Inputs change between steps only, like the
// signals of a co-simulation master, and hold over the steps to the next apply_inputs (the horizon h):
//   acceleration: the DOF moves at the constant acceleration u;
//   velocity: at the constant acceleration (u - v) / h, so that its velocity reaches u at the horizon;
//   position: along the cubic from its position q and velocity v now that reaches q = u with velocity
//             (u - q) / h at the horizon (Hermite interpolation: acceleration 4 ((u - q) / h - v) / h now,
//             jerk 6 (v - (u - q) / h) / h^2; the end velocity does not depend on v, so a position command
//             held or ramped is followed without oscillation);
// positions and velocities stay continuous (SimulatorTpl::set_driven_acceleration: no impulse).
//
// Everything is allocated by the constructor; the calls after it allocate nothing and never throw
// (failures are Status values; describe() builds the message, allocating then only).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "soadyn/algorithms/frames.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn::embed {

// Whether a DOF can be locked (not modal) or follow its input (a scalar coordinate, not modal).
bool lockable_dof(const Model& model, int dof);
bool sourceable_dof(const Model& model, int dof);

// What the input u of a DOF that follows its input gives (see above).
enum class InputKind : std::uint8_t { acceleration, velocity, position };
const char* input_kind_name(InputKind kind);
InputKind input_kind_from_name(const std::string& name);  // throws std::invalid_argument naming it

class Plant {
 public:
  // Throws std::invalid_argument for a dt that is not finite and positive.
  Plant(const Model& model, double dt, Integrator integrator);

  const Model& model() const { return sim_.model(); }
  Simulator& simulator() { return sim_; }
  const Simulator& simulator() const { return sim_; }
  int nq() const { return sim_.model().nq; }
  int nv() const { return sim_.model().nv; }

  // Inputs, kept until changed; applied by apply_inputs. u may be any double: a non-finite u fails the
  // next apply_inputs (a prescribed DOF) or step (a regular DOF) with the DOF named.
  void set_u(int dof, double u) { u_[static_cast<std::size_t>(dof)] = u; }
  double u(int dof) const { return u_[static_cast<std::size_t>(dof)]; }
  void set_locked(int dof, bool on) { locked_[static_cast<std::size_t>(dof)] = on; }
  void set_prescribed(int dof, bool on) { prescribed_[static_cast<std::size_t>(dof)] = on; }
  bool locked(int dof) const { return locked_[static_cast<std::size_t>(dof)] != 0; }
  bool prescribed(int dof) const { return prescribed_[static_cast<std::size_t>(dof)] != 0; }
  // The first DOF whose input is not finite, or -1 (the C API names it before stepping; wrench inputs are
  // not counted: the first not finite is non_finite_wrench()).
  int non_finite_input() const;
  int non_finite_wrench() const;
  bool lockable(int dof) const { return dof >= 0 && dof < nv() && lockable_[static_cast<std::size_t>(dof)]; }
  bool sourceable(int dof) const { return dof >= 0 && dof < nv() && sourceable_[static_cast<std::size_t>(dof)]; }

  // Setup: the kind of a DOF's input when it follows it (acceleration by default); throws
  // std::invalid_argument naming the DOF when it cannot follow its input (sourceable_dof).
  void set_input_kind(int dof, InputKind kind);
  InputKind input_kind(int dof) const { return kinds_[static_cast<std::size_t>(dof)]; }

  // Setup: a wrench input on the frame `name` (locate_frame: a body or a named frame, not on a flexible
  // body; throws std::invalid_argument naming it); returns its index. The wrench is [torque; force] in the
  // frame's own axes about its origin (what a force-torque sensor mounted there reads), zero until set.
  int add_wrench_input(const std::string& name);
  int wrench_inputs() const { return static_cast<int>(wrench_frames_.size()); }
  // Component 0..5 (tx ty tz fx fy fz) of wrench input k; any double (a non-finite one fails the next
  // apply_inputs naming the body).
  void set_wrench(int k, int component, double value) { wrenches_[static_cast<std::size_t>(6 * k + component)] = value; }
  double wrench(int k, int component) const { return wrenches_[static_cast<std::size_t>(6 * k + component)]; }

  // Mode switches first (locked wins over prescribed; a DOF neither is regular), then the inputs: torques
  // of the regular DOFs, the motions of the DOFs that follow their inputs over `horizon` s (rebased here),
  // the frames' wrenches as the bodies' external wrenches.
  Status apply_inputs(double horizon);
  Status apply_inputs() { return apply_inputs(sim_.dt()); }
  // apply_inputs over steps * dt, then `steps` steps; stops at the first failure.
  Status advance(int steps);
  // Accelerations and generalized forces at the present state and inputs, into qdd() and tau().
  Status evaluate_outputs();
  const VecX<double>& qdd() const { return qdd_; }
  const VecX<double>& tau() const { return tau_; }

  // The state as bytes (see soadyn_sim_save_state): fixed size for the model.
  std::size_t state_size() const;
  void save_state(unsigned char* out) const;
  // False (and nothing changed) for bytes that are not a state of this model; `why` says what is wrong.
  bool load_state(const unsigned char* in, std::size_t size, const char** why);

  std::string describe(const Status& s) const { return sim_.describe(s); }

 private:
  Simulator sim_;
  std::vector<double> u_;
  std::vector<std::uint8_t> locked_, prescribed_;
  std::vector<std::uint8_t> lockable_, sourceable_;  // per DOF, found once (lockable_dof, sourceable_dof)
  std::vector<InputKind> kinds_;
  std::vector<FrameLocation<double>> wrench_frames_;
  std::vector<double> wrenches_, loaded_wrenches_;  // 6 per wrench input
  VecX<double> body_wrenches_;                      // their sum per body (nbodies x 6, body frames)
  VecX<double> qdd_, tau_;
  // Scratch of save_state and load_state: a state is read whole before anything changes.
  mutable SimulatorSnapshot<double> snapshot_;
  std::vector<double> loaded_u_;
  std::vector<std::uint8_t> loaded_locked_, loaded_prescribed_;
};

Integrator integrator_from_name(const std::string& name);  // throws std::invalid_argument naming it

}  // namespace soadyn::embed
