// The settings of a soadyn FMU, written at export into resources/soadyn_fmu.txt, one per line:
// "soadyn-fmu 1", "token <instantiation token>", "step <s>", "substeps <n>", "integrator <rk4|euler|dopri5>",
// "q0 <nq numbers>", "v0 <nv numbers>", "frames <names>" (the frames with outputs), "wrenches <names>" (the
// frames with wrench inputs), "inputs <dof>=<kind> ..." (the DOFs whose input u, when they follow it, is a
// velocity or a position: embed::InputKind; the others' is an acceleration). The FMU's internal step is
// step / substeps; a DoStep of h runs h / (step / substeps) steps (h must be a whole number of them).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "soadyn/embed/plant.hpp"

namespace soadyn::fmu {

struct Settings {
  std::string token;   // the instantiation token (FMI 2: guid) of the modelDescription.xml
  double step = 1e-3;  // the export's communication step, s
  int substeps = 1;
  std::string integrator = "rk4";
  std::vector<double> q0, v0;
  std::vector<std::string> frames;    // the named frames with outputs
  std::vector<std::string> wrenches;  // the named frames with wrench inputs
  std::vector<std::pair<std::string, std::string>> inputs;  // (DOF name, input kind name) other than acceleration
};

// Reads resources/soadyn_fmu.txt; throws std::invalid_argument naming the file and line at fault.
Settings read_settings(const std::string& path, int nq, int nv);
std::string settings_text(const Settings& settings);

// One item "<dof>=<kind>" of the inputs line, as (DOF name, kind name); throws std::invalid_argument naming
// an item of another form or an unknown kind.
std::pair<std::string, std::string> input_item(const std::string& item);

// Each DOF's input kind (acceleration unless `settings.inputs` names it); throws std::invalid_argument naming
// an unknown DOF or kind, or a DOF that cannot follow its input.
std::vector<embed::InputKind> input_kinds(const Model& model, const Settings& settings);

// The integrators an FMU offers, as its `integrator` parameter numbers them (1, 2, 3).
inline constexpr const char* kIntegrators[3] = {"rk4", "euler", "dopri5"};
int integrator_number(const std::string& name);  // 1 to 3; throws std::invalid_argument naming it

}  // namespace soadyn::fmu
