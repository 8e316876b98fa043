// One instance of a soadyn FMU, independent of the FMI version: its model and settings read from the FMU's
// resources, a Plant driven by the variables of variables.hpp, and the FMI calls' behaviour (the fmi2 and
// fmi3 entry points translate their arguments and status codes only).
//
// resources/model.json: the model file; resources/soadyn_fmu.txt: the settings written at export
// (settings.hpp). The integrator and the substeps are fixed parameters (set before the initialization
// ends; their start values are the settings'); the model's parameters are tunable but for the placements
// (a placement moves bodies and would open the loops): set in step mode, a change applies from the next
// DoStep on, the state kept.
//
// Real time: do_step, get and set allocate nothing and never throw (qdd, tau and the energies are
// evaluated when first read after a step); errors are logged with the item named
// (the message is built then) and put the instance in its error state, where only reads, reset and
// freeing are accepted (FMI's rule after an error).
#pragma once
#include <functional>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "soadyn/algorithms/frames.hpp"
#include "soadyn/embed/plant.hpp"
#include "soadyn/fmu/settings.hpp"
#include "soadyn/fmu/variables.hpp"

namespace soadyn::fmu {

class Instance {
 public:
  // error: true for an error, false for information; category as FMI's ("logError", "logInfo").
  using Log = std::function<void(bool error, const char* category, const std::string& message)>;

  // Throws std::invalid_argument naming the resource at fault.
  Instance(const std::string& resources, Log log);

  const std::vector<Variable>& variables() const { return variables_; }
  const Settings& settings() const { return settings_; }

  bool enter_initialization(double start_time);
  bool exit_initialization();
  bool reset();
  bool do_step(double current_time, double step);

  bool set_float64(unsigned vr, double value);
  bool get_float64(unsigned vr, double& value);
  bool set_boolean(unsigned vr, bool value);
  bool get_boolean(unsigned vr, bool& value);
  // The Int32 (substeps) and Enumeration (integrator) parameters; `type` is the type the call serves
  // (FMI 3: fmi3Get/SetInt32 an Int32, fmi3Get/SetInt64 an Enumeration; FMI 2's Integer calls both: nullopt).
  bool set_integer(unsigned vr, long long value, std::optional<ValueType> type);
  bool get_integer(unsigned vr, long long& value, std::optional<ValueType> type);

  std::size_t state_size() const {
    return plant_->state_size() + sizeof(double) + 1 + tunable_values_.size() * sizeof(double);
  }
  void save_state(unsigned char* out);
  bool load_state(const unsigned char* in, std::size_t size);

  bool failed() const { return failed_; }

 private:
  bool fail(const std::string& message);
  bool update_outputs();
  const Variable* variable(unsigned vr, const char* call);
  bool start();  // the start state at start_time_, the inputs applied, the outputs computed
  void make_plant();  // a Plant of model_ with the settings' step, substeps, integrator, input kinds and wrenches
  bool set_parameter(const Variable& v, double value);
  // The tunable parameters' values (the FMU state holds them) into tunable_values_, and back.
  void save_tunable();
  bool load_tunable(const double* values);

  std::string resources_;
  Log log_;
  Model model_;
  Settings settings_;
  std::vector<Variable> variables_;
  std::unique_ptr<embed::Plant> plant_;
  std::unique_ptr<ParameterTable<double>> parameters_;
  std::vector<double> parameter_scratch_;
  std::vector<int> tunable_entries_;       // the ParameterTable entries of the tunable parameters
  std::vector<double> tunable_values_, tunable_loaded_;  // their values (now, and from a saved state)
  bool parameters_changed_ = false;  // the Plant is rebuilt from model_ when the initialization ends
  double start_time_ = 0.0, kinetic_ = 0.0, potential_ = 0.0;
  bool failed_ = false, initialized_ = false;
  // qdd, tau and the energies are evaluated when first read after a step, not by every DoStep: a master
  // that reads q and v only pays for the steps.
  bool outputs_current_ = false;
  std::vector<FrameLocation<double>> frames_;  // the frames with outputs, located once
  std::vector<double> frame_values_;           // 16 per frame (kFrameOutputs), with the other outputs
  std::vector<double> loop_values_;            // 6 per loop: the loop wrenches of the outputs' evaluation
};

}  // namespace soadyn::fmu
