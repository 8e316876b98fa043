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

namespace {

constexpr const char* kSettingsHeader = "soadyn-fmu 1";

std::vector<double> numbers(std::istringstream& line, std::size_t count, const std::string& where) {
  std::vector<double> out(count);
  for (double& x : out)
    if (!(line >> x) || !std::isfinite(x)) throw std::invalid_argument(where + ": expected " + std::to_string(count) +
                                                                     " finite numbers");
  std::string extra;
  if (line >> extra) throw std::invalid_argument(where + ": more than " + std::to_string(count) + " numbers");
  return out;
}

}  // namespace

Settings read_settings(const std::string& path, int nq, int nv) {
  std::ifstream file(path);
  if (!file) throw std::invalid_argument("cannot read the FMU's settings '" + path + "' (a missing resource?)");
  Settings s;
  std::string text;
  int number = 0;
  bool header = false;
  while (std::getline(file, text)) {
    ++number;
    const std::string where = path + ", line " + std::to_string(number);
    if (!header) {
      if (text != kSettingsHeader) throw std::invalid_argument(where + ": expected '" + kSettingsHeader + "'");
      header = true;
      continue;
    }
    std::istringstream line(text);
    std::string key;
    if (!(line >> key)) continue;
    if (key == "token") {
      if (!(line >> s.token)) throw std::invalid_argument(where + ": the token is missing");
    } else if (key == "step") {
      s.step = numbers(line, 1, where)[0];
      if (!(s.step > 0)) throw std::invalid_argument(where + ": the step must be > 0");
    } else if (key == "substeps") {
      const double n = numbers(line, 1, where)[0];
      if (!(n >= 1 && n <= 1e6 && n == std::floor(n))) throw std::invalid_argument(where + ": substeps must be 1 to 1e6");
      s.substeps = static_cast<int>(n);
    } else if (key == "integrator") {
      if (!(line >> s.integrator)) throw std::invalid_argument(where + ": the integrator's name is missing");
      embed::integrator_from_name(s.integrator);
    } else if (key == "q0") {
      s.q0 = numbers(line, static_cast<std::size_t>(nq), where);
    } else if (key == "v0") {
      s.v0 = numbers(line, static_cast<std::size_t>(nv), where);
    } else if (key == "frames") {
      for (std::string name; line >> name;) s.frames.push_back(name);
    } else {
      throw std::invalid_argument(where + ": unknown setting '" + key + "'");
    }
  }
  if (!header) throw std::invalid_argument(path + ": empty (expected '" + kSettingsHeader + "')");
  return s;
}

std::string settings_text(const Settings& s) {
  std::ostringstream out;
  out.precision(17);
  out << kSettingsHeader << "\ntoken " << s.token << "\nstep " << s.step << "\nsubsteps " << s.substeps
      << "\nintegrator " << s.integrator;
  out << "\nq0";
  for (double x : s.q0) out << ' ' << x;
  out << "\nv0";
  for (double x : s.v0) out << ' ' << x;
  out << "\nframes";
  for (const std::string& name : s.frames) out << ' ' << name;
  out << '\n';
  return out.str();
}

Instance::Instance(const std::string& resources, Log log) : resources_(resources), log_(std::move(log)) {
  model_ = load_model(resources_ + "/model.json");
  settings_ = read_settings(resources_ + "/soadyn_fmu.txt", model_.nq, model_.nv);
  variables_ = fmu::variables(model_, settings_.frames);
  for (const std::string& name : settings_.frames) frames_.push_back(locate_frame<double>(model_, name));
  frame_values_.assign(16 * frames_.size(), 0.0);
  loop_values_.assign(6 * static_cast<std::size_t>(model_.nloops()), 0.0);
  parameters_ = std::make_unique<ParameterTable<double>>(model_);
  parameter_scratch_.assign(16, 0.0);
  plant_ = std::make_unique<embed::Plant>(model_, settings_.step / settings_.substeps,
                                          embed::integrator_from_name(settings_.integrator));
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
    auto changed = std::make_unique<embed::Plant>(model_, settings_.step / settings_.substeps,
                                                  embed::integrator_from_name(settings_.integrator));
    for (int dof = 0; dof < model_.nv; ++dof) {
      changed->set_u(dof, plant_->u(dof));
      changed->set_locked(dof, plant_->locked(dof));
      changed->set_prescribed(dof, plant_->prescribed(dof));
    }
    plant_ = std::move(changed);
    parameters_changed_ = false;
  }
  initialized_ = true;
  return start();  // the inputs set during initialization, from the start state
}

bool Instance::reset() {
  failed_ = false;
  initialized_ = false;
  parameters_changed_ = false;
  try {  // the parameters' start values: the model as exported (setup: it allocates)
    model_ = load_model(resources_ + "/model.json");
    parameters_ = std::make_unique<ParameterTable<double>>(model_);
  } catch (const std::exception& e) {
    return fail(std::string("Reset: ") + e.what());
  }
  plant_ = std::make_unique<embed::Plant>(model_, settings_.step / settings_.substeps,
                                          embed::integrator_from_name(settings_.integrator));
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
  if (v->quantity == Quantity::parameter) {
    if (initialized_) return fail("SetFloat64: the parameter '" + v->name + "' is fixed: set it before the "
                                  "initialization ends");
    if (!std::isfinite(value)) return fail("SetFloat64: the value of '" + v->name + "' is not finite");
    try {
      set_parameter_element(*parameters_, model_, *v, value, parameter_scratch_);
    } catch (const std::exception& e) {
      return fail(std::string("SetFloat64: ") + e.what());
    }
    parameters_changed_ = true;
    return true;
  }
  if (v->quantity != Quantity::input) return fail("SetFloat64: '" + v->name + "' is not a Float64 input");
  if (!std::isfinite(value)) return fail("SetFloat64: the value of '" + v->name + "' is not finite");
  plant_->set_u(v->index, value);
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

void Instance::save_state(unsigned char* out) const {
  plant_->save_state(out);
  std::memcpy(out + plant_->state_size(), &start_time_, sizeof(double));
  out[plant_->state_size() + sizeof(double)] = initialized_ ? 1 : 0;
}

bool Instance::load_state(const unsigned char* in, std::size_t size) {
  if (size != state_size()) return fail("SetFMUState: the state has the wrong size for this FMU");
  const char* why = "";
  if (!plant_->load_state(in, plant_->state_size(), &why)) return fail(std::string("SetFMUState: ") + why);
  std::memcpy(&start_time_, in + plant_->state_size(), sizeof(double));
  initialized_ = in[plant_->state_size() + sizeof(double)] != 0;
  failed_ = false;
  outputs_current_ = false;
  return true;
}

}  // namespace soadyn::fmu
