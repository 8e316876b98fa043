#include "soadyn/fmu/instance.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "soadyn/algorithms/energy.hpp"
#include "soadyn/model/model_file.hpp"

namespace soadyn::fmu {

Instance::Instance(const std::string& resources, Log log) : resources_(resources), log_(std::move(log)) {
  model_ = load_model(resources_ + "/model.json");
  settings_ = read_settings(resources_ + "/soadyn_fmu.txt", model_.nq, model_.nv);
  variables_ = fmu::variables(model_, settings_);
  for (const std::string& name : settings_.frames) frames_.push_back(locate_frame<double>(model_, name));
  frame_values_.assign(16 * frames_.size(), 0.0);
  loop_values_.assign(6 * static_cast<std::size_t>(model_.nloops()), 0.0);
  parameters_ = std::make_unique<ParameterTable<double>>(model_);
  parameter_scratch_.assign(16, 0.0);
  for (const Variable& v : variables_)  // each tunable entry once (its elements are consecutive variables)
    if (v.quantity == Quantity::parameter && v.tunable && (tunable_entries_.empty() || tunable_entries_.back() != v.index))
      tunable_entries_.push_back(v.index);
  std::size_t tunable_size = 0;
  for (int k : tunable_entries_) tunable_size += static_cast<std::size_t>(parameters_->entry(k).size());
  tunable_values_.assign(tunable_size, 0.0);
  tunable_loaded_.assign(tunable_size, 0.0);
  make_plant();
}

void Instance::make_plant() {
  auto plant = std::make_unique<embed::Plant>(model_, settings_.step / settings_.substeps,
                                              embed::integrator_from_name(settings_.integrator));
  const std::vector<embed::InputKind> kinds = input_kinds(model_, settings_);
  for (int dof = 0; dof < model_.nv; ++dof)
    if (kinds[static_cast<std::size_t>(dof)] != embed::InputKind::acceleration)
      plant->set_input_kind(dof, kinds[static_cast<std::size_t>(dof)]);
  for (const std::string& frame : settings_.wrenches) plant->add_wrench_input(frame);
  if (plant_) {  // a rebuild keeps the inputs set so far
    for (int dof = 0; dof < model_.nv; ++dof) {
      plant->set_u(dof, plant_->u(dof));
      plant->set_locked(dof, plant_->locked(dof));
      plant->set_prescribed(dof, plant_->prescribed(dof));
    }
    for (int k = 0; k < plant->wrench_inputs(); ++k)
      for (int c = 0; c < 6; ++c) plant->set_wrench(k, c, plant_->wrench(k, c));
  }
  plant_ = std::move(plant);
}

bool Instance::fail(const std::string& message) {
  failed_ = true;
  if (log_) log_(true, "logError", message);
  return false;
}

const Variable* Instance::variable(unsigned vr, const char* call) {
  if (vr >= variables_.size()) {
    fail(std::string(call) + ": no variable has value reference " + std::to_string(vr) + " (0 to " +
         std::to_string(variables_.size() - 1) + ")");
    return nullptr;
  }
  return &variables_[vr];
}

bool Instance::start() {
  const int nq = model_.nq, nv = model_.nv;
  Eigen::VectorXd q = plant_->simulator().q(), v = Eigen::VectorXd::Zero(nv);
  if (!settings_.q0.empty()) q = Eigen::Map<const Eigen::VectorXd>(settings_.q0.data(), nq);
  if (!settings_.v0.empty()) v = Eigen::Map<const Eigen::VectorXd>(settings_.v0.data(), nv);
  try {
    plant_->simulator().set_state(q, v, start_time_);
  } catch (const std::exception& e) {
    return fail(std::string("the start state: ") + e.what());
  }
  const Status s = plant_->apply_inputs();
  if (!s.ok()) return fail(plant_->describe(s));
  return update_outputs();
}

bool Instance::enter_initialization(double start_time) {
  if (!std::isfinite(start_time)) return fail("the start time is not finite");
  start_time_ = start_time;
  return start();
}

bool Instance::exit_initialization() {
  if (failed_) return fail("exit initialization after an error");
  if (parameters_changed_) {  // setup, not a step: the new model's Plant is made here, with the inputs set so far
    try {
      make_plant();
    } catch (const std::exception& e) {
      return fail(std::string("ExitInitializationMode: ") + e.what());
    }
    parameters_changed_ = false;
  }
  initialized_ = true;
  return start();  // the inputs set during initialization, from the start state
}

bool Instance::reset() {
  failed_ = false;
  initialized_ = false;
  parameters_changed_ = false;
  try {  // the parameters' start values: the model and settings as exported (setup: it allocates)
    model_ = load_model(resources_ + "/model.json");
    settings_ = read_settings(resources_ + "/soadyn_fmu.txt", model_.nq, model_.nv);
    parameters_ = std::make_unique<ParameterTable<double>>(model_);
    plant_.reset();
    make_plant();
  } catch (const std::exception& e) {
    return fail(std::string("Reset: ") + e.what());
  }
  start_time_ = 0.0;
  return start();
}

bool Instance::update_outputs() {
  const Status s = plant_->evaluate_outputs();
  if (!s.ok()) return fail(plant_->describe(s));
  Simulator& sim = plant_->simulator();
  for (int loop = 0; loop < sim.model().nloops(); ++loop)  // before the energies and frames reuse the data
    for (int row = 0; row < 6; ++row)
      loop_values_[static_cast<std::size_t>(6 * loop + row)] = sim.data().loops.wrench[static_cast<std::size_t>(loop)][row];
  kinetic_ = kinetic_energy<double>(sim.model(), sim.data(), sim.q(), sim.v());
  potential_ = potential_energy<double>(sim.model(), sim.data(), sim.q());
  if (!std::isfinite(kinetic_) || !std::isfinite(potential_)) return fail("the energy is not finite");
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const Transform<double> pose = frame_pose<double>(sim.model(), sim.data(), sim.q(), frames_[k]);
    const Vec6<double> velocity =
        frame_velocity<double>(sim.model(), sim.data(), sim.q(), sim.v(), frames_[k], Reference::local);
    const Vec6<double> acceleration = frame_acceleration<double>(sim.model(), sim.data(), sim.q(), sim.v(),
                                                                 plant_->qdd(), frames_[k], Reference::local, true);
    const Eigen::Quaterniond orientation(pose.rotation);
    double* out = frame_values_.data() + 16 * k;
    for (int i = 0; i < 3; ++i) {
      out[i] = pose.translation[i];
      out[7 + i] = velocity[i];
      out[10 + i] = velocity[3 + i];
      out[13 + i] = acceleration[3 + i];
    }
    out[3] = orientation.x(), out[4] = orientation.y(), out[5] = orientation.z(), out[6] = orientation.w();
    for (int i = 0; i < 16; ++i)
      if (!std::isfinite(out[i])) return fail("the outputs of frame '" + settings_.frames[k] + "' are not finite");
  }
  outputs_current_ = true;
  return true;
}

bool Instance::do_step(double current_time, double step) {
  if (failed_) return fail("DoStep after an error: reset or free the instance");
  if (!initialized_) return fail("DoStep before the initialization ended");
  const Simulator& sim = plant_->simulator();
  const double dt = sim.dt();
  if (!(step > 0) || !std::isfinite(step)) return fail("DoStep: the step size must be a finite number > 0");
  if (std::abs(current_time - sim.time()) > 1e-9 * std::max(1.0, std::abs(sim.time())) + 1e-6 * dt)
    return fail("DoStep: the communication point " + std::to_string(current_time) + " s is not the FMU's time " +
                std::to_string(sim.time()) + " s");
  const double exact = step / dt;
  const double steps = std::round(exact);
  if (steps < 1 || std::abs(exact - steps) > 1e-6 || steps > std::numeric_limits<int>::max())
    return fail("DoStep: the step size " + std::to_string(step) + " s is not a whole number of the FMU's internal step " +
                std::to_string(dt) + " s (its step / substeps)");
  outputs_current_ = false;
  const Status s = plant_->advance(static_cast<int>(steps));
  if (!s.ok()) return fail("DoStep: " + plant_->describe(s));
  return true;
}

bool Instance::set_float64(unsigned vr, double value) {
  const Variable* v = variable(vr, "SetFloat64");
  if (!v) return false;
  if (v->quantity == Quantity::parameter) return set_parameter(*v, value);
  if (v->quantity != Quantity::input && v->quantity != Quantity::wrench)
    return fail("SetFloat64: '" + v->name + "' is not a Float64 input or parameter");
  if (!std::isfinite(value)) return fail("SetFloat64: the value of '" + v->name + "' is not finite");
  if (v->quantity == Quantity::wrench) plant_->set_wrench(v->index, v->row, value);
  else plant_->set_u(v->index, value);
  return true;
}

// Before the initialization ends: the model changes and the Plant is rebuilt when it ends. After, a tunable
// parameter changes in the model and in the simulator's copy at once (allocation-free: ParameterTable::set),
// from the next DoStep on.
bool Instance::set_parameter(const Variable& v, double value) {
  if (initialized_ && !v.tunable)
    return fail("SetFloat64: the parameter '" + v.name + "' is fixed: set it before the initialization ends");
  if (!std::isfinite(value)) return fail("SetFloat64: the value of '" + v.name + "' is not finite");
  try {
    set_parameter_element(*parameters_, model_, v, value, parameter_scratch_);
  } catch (const std::exception& e) {
    return fail(std::string("SetFloat64: ") + e.what());
  }
  if (!initialized_) {
    parameters_changed_ = true;
    return true;
  }
  parameters_->get(model_, v.index, parameter_scratch_.data());  // the value just accepted, mirror included
  plant_->simulator().change_parameters([&](Model& m) { parameters_->set(m, v.index, parameter_scratch_.data()); });
  outputs_current_ = false;
  return true;
}

bool Instance::get_float64(unsigned vr, double& value) {
  const Variable* v = variable(vr, "GetFloat64");
  if (!v) return false;
  const Simulator& sim = plant_->simulator();
  const bool evaluated = v->quantity == Quantity::acceleration || v->quantity == Quantity::force ||
                         v->quantity == Quantity::kinetic_energy || v->quantity == Quantity::potential_energy ||
                         v->quantity == Quantity::frame || v->quantity == Quantity::loop_wrench;
  if (evaluated && !outputs_current_ && !update_outputs()) return false;
  switch (v->quantity) {
    case Quantity::time: value = sim.time(); return true;
    case Quantity::input: value = plant_->u(v->index); return true;
    case Quantity::wrench: value = plant_->wrench(v->index, v->row); return true;
    case Quantity::position: value = sim.q()[v->index]; return true;
    case Quantity::velocity: value = sim.v()[v->index]; return true;
    case Quantity::acceleration: value = plant_->qdd()[v->index]; return true;
    case Quantity::force: value = plant_->tau()[v->index]; return true;
    case Quantity::kinetic_energy: value = kinetic_; return true;
    case Quantity::potential_energy: value = potential_; return true;
    case Quantity::frame: value = frame_values_[static_cast<std::size_t>(16 * v->index + v->row)]; return true;
    case Quantity::loop_wrench: value = loop_values_[static_cast<std::size_t>(6 * v->index + v->row)]; return true;
    case Quantity::parameter: value = parameter_element(*parameters_, model_, *v, parameter_scratch_); return true;
    default: return fail("GetFloat64: '" + v->name + "' is a Boolean");
  }
}

bool Instance::set_integer(unsigned vr, long long value, std::optional<ValueType> type) {
  const Variable* v = variable(vr, "SetInteger");
  if (!v) return false;
  if ((v->quantity != Quantity::integrator && v->quantity != Quantity::substeps) || (type && *type != v->type))
    return fail("SetInteger: '" + v->name + "' is not a parameter of this type (integrator: Enumeration, substeps: Int32)");
  if (initialized_) return fail("SetInteger: the parameter '" + v->name + "' is fixed: set it before the initialization ends");
  if (v->quantity == Quantity::integrator) {
    if (value < 1 || value > 3) return fail("SetInteger: integrator must be 1 (rk4), 2 (euler) or 3 (dopri5), got " +
                                            std::to_string(value));
    settings_.integrator = kIntegrators[value - 1];
  } else {
    if (value < 1 || value > 1000000) return fail("SetInteger: substeps must be 1 to 1000000, got " + std::to_string(value));
    settings_.substeps = static_cast<int>(value);
  }
  parameters_changed_ = true;
  return true;
}

bool Instance::get_integer(unsigned vr, long long& value, std::optional<ValueType> type) {
  const Variable* v = variable(vr, "GetInteger");
  if (!v) return false;
  if ((v->quantity != Quantity::integrator && v->quantity != Quantity::substeps) || (type && *type != v->type))
    return fail("GetInteger: '" + v->name + "' is not a variable of this type (integrator: Enumeration, substeps: Int32)");
  value = v->quantity == Quantity::integrator ? integrator_number(settings_.integrator) : settings_.substeps;
  return true;
}

bool Instance::set_boolean(unsigned vr, bool value) {
  const Variable* v = variable(vr, "SetBoolean");
  if (!v) return false;
  if (v->quantity == Quantity::locked) plant_->set_locked(v->index, value);
  else if (v->quantity == Quantity::prescribed) plant_->set_prescribed(v->index, value);
  else return fail("SetBoolean: '" + v->name + "' is not a Boolean input");
  return true;
}

bool Instance::get_boolean(unsigned vr, bool& value) {
  const Variable* v = variable(vr, "GetBoolean");
  if (!v) return false;
  if (v->quantity == Quantity::locked) value = plant_->locked(v->index);
  else if (v->quantity == Quantity::prescribed) value = plant_->prescribed(v->index);
  else return fail("GetBoolean: '" + v->name + "' is not a Boolean");
  return true;
}

void Instance::save_tunable() {
  double* at = tunable_values_.data();
  for (int k : tunable_entries_) {
    parameters_->get(model_, k, at);
    at += parameters_->entry(k).size();
  }
}

// All or nothing: values a ParameterTable refuses (a corrupted state) leave the model as it was. Before,
// save_tunable() put the present values into tunable_values_.
bool Instance::load_tunable(const double* values) {
  const auto set_all = [this](Model& m, const double* from, std::size_t entries) {
    for (std::size_t j = 0; j < entries; ++j) {
      parameters_->set(m, tunable_entries_[j], from);
      from += parameters_->entry(tunable_entries_[j]).size();
    }
  };
  std::size_t applied = 0;
  try {
    const double* at = values;
    for (int k : tunable_entries_) {
      parameters_->set(model_, k, at);
      at += parameters_->entry(k).size();
      ++applied;
    }
  } catch (const std::exception& e) {
    set_all(model_, tunable_values_.data(), applied);  // the values it had: valid
    return fail(std::string("SetFMUState: the state's parameters are refused: ") + e.what());
  }
  plant_->simulator().change_parameters([&](Model& m) { set_all(m, values, tunable_entries_.size()); });
  return true;
}

void Instance::save_state(unsigned char* out) {
  plant_->save_state(out);
  std::size_t at = plant_->state_size();
  std::memcpy(out + at, &start_time_, sizeof(double));
  out[at + sizeof(double)] = initialized_ ? 1 : 0;
  save_tunable();
  if (!tunable_values_.empty())
    std::memcpy(out + at + sizeof(double) + 1, tunable_values_.data(), tunable_values_.size() * sizeof(double));
}

bool Instance::load_state(const unsigned char* in, std::size_t size) {
  if (size != state_size()) return fail("SetFMUState: the state has the wrong size for this FMU");
  const std::size_t at = plant_->state_size() + sizeof(double) + 1;
  for (std::size_t k = 0; k < tunable_loaded_.size(); ++k) {  // the parameters: checked, then set all or nothing
    std::memcpy(&tunable_loaded_[k], in + at + k * sizeof(double), sizeof(double));
    if (!std::isfinite(tunable_loaded_[k])) return fail("SetFMUState: the state holds a parameter that is not finite");
  }
  save_tunable();
  if (!load_tunable(tunable_loaded_.data())) return false;
  const char* why = "";
  if (!plant_->load_state(in, plant_->state_size(), &why)) {
    load_tunable(tunable_values_.data());  // the values before: valid
    return fail(std::string("SetFMUState: ") + why);
  }
  std::memcpy(&start_time_, in + plant_->state_size(), sizeof(double));
  initialized_ = in[plant_->state_size() + sizeof(double)] != 0;
  failed_ = false;
  outputs_current_ = false;
  return true;
}

}  // namespace soadyn::fmu
