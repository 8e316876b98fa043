// A simulator driven the way embedding hosts drive one (the C API, the FMU): one input u per DOF
// (torque of a regular DOF, acceleration of a DOF that follows its input, as in hybrid_dynamics) and two
// switches per DOF (locked, prescribed) that take effect at the next apply_inputs. Inputs change between
// steps only, like the signals of a co-simulation master: a prescribed DOF moves at the constant
// acceleration u over the steps between two apply_inputs (SimulatorTpl::set_driven_acceleration).
//
// Everything is allocated by the constructor; the calls after it allocate nothing and never throw
// (failures are Status values; describe() builds the message, allocating then only).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "soadyn/sim/simulator.hpp"

namespace soadyn::embed {

// Whether a DOF can be locked (not modal) or follow its input (a scalar coordinate, not modal).
bool lockable_dof(const Model& model, int dof);
bool sourceable_dof(const Model& model, int dof);

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
  // The first DOF whose input is not finite, or -1 (the C API names it before stepping).
  int non_finite_input() const;
  bool lockable(int dof) const { return dof >= 0 && dof < nv() && lockable_[static_cast<std::size_t>(dof)]; }
  bool sourceable(int dof) const { return dof >= 0 && dof < nv() && sourceable_[static_cast<std::size_t>(dof)]; }

  // Mode switches first (locked wins over prescribed; a DOF neither is regular), then the inputs: torques
  // of the regular DOFs, accelerations of the DOFs that follow their inputs (rebased here).
  Status apply_inputs();
  // apply_inputs, then `steps` steps; stops at the first failure.
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
  VecX<double> qdd_, tau_;
  // Scratch of save_state and load_state: a state is read whole before anything changes.
  mutable SimulatorSnapshot<double> snapshot_;
  std::vector<double> loaded_u_;
  std::vector<std::uint8_t> loaded_locked_, loaded_prescribed_;
};

Integrator integrator_from_name(const std::string& name);  // throws std::invalid_argument naming it

}  // namespace soadyn::embed
