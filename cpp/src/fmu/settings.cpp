#include "soadyn/fmu/settings.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

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
    } else if (key == "wrenches") {
      for (std::string name; line >> name;) s.wrenches.push_back(name);
    } else if (key == "inputs") {
      try {
        for (std::string item; line >> item;) s.inputs.push_back(input_item(item));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + ": " + e.what());
      }
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
  out << "\nwrenches";
  for (const std::string& name : s.wrenches) out << ' ' << name;
  out << "\ninputs";
  for (const auto& [dof, kind] : s.inputs) out << ' ' << dof << '=' << kind;
  out << '\n';
  return out.str();
}

std::pair<std::string, std::string> input_item(const std::string& item) {
  const std::size_t eq = item.find('=');
  if (eq == std::string::npos || eq == 0) throw std::invalid_argument("input kind '" + item + "' is not <dof>=<kind>");
  std::pair<std::string, std::string> out{item.substr(0, eq), item.substr(eq + 1)};
  embed::input_kind_from_name(out.second);
  return out;
}

std::vector<embed::InputKind> input_kinds(const Model& model, const Settings& settings) {
  std::vector<embed::InputKind> kinds(static_cast<std::size_t>(model.nv), embed::InputKind::acceleration);
  for (const auto& [name, kind] : settings.inputs) {
    const int dof = model.dof_index(name);
    if (dof < 0) throw std::invalid_argument("input kind of '" + name + "': the model has no DOF of that name");
    if (!embed::sourceable_dof(model, dof))
      throw std::invalid_argument("input kind of '" + name + "': the DOF cannot follow its input (a modal DOF, or a "
                                  "joint without scalar coordinates)");
    kinds[static_cast<std::size_t>(dof)] = embed::input_kind_from_name(kind);
  }
  return kinds;
}

int integrator_number(const std::string& name) {
  for (int k = 0; k < 3; ++k)
    if (name == kIntegrators[k]) return k + 1;
  throw std::invalid_argument("unknown integrator '" + name + "' (rk4, euler or dopri5)");
}

}  // namespace soadyn::fmu
