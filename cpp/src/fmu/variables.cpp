#include "soadyn/fmu/variables.hpp"

#include <cstring>

#include "soadyn/embed/plant.hpp"

namespace soadyn::fmu {

namespace {

const DofUnits kRotation{"rad", "rad/s", "rad/s2", "N.m"};
const DofUnits kTranslation{"m", "m/s", "m/s2", "N"};
const DofUnits kModal{"", "", "", ""};

// The body whose joint or modal coordinates hold `dof`, and the DOF's place among its joint's DOFs (-1: modal).
int body_of_dof(const Model& m, int dof, int& place) {
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int first = m.v_index[bi];
    if (dof >= first && dof < first + m.nv_body[bi]) {
      place = dof - first;
      return b;
    }
    if (dof >= m.modal_v_index(b) && dof < m.modal_v_index(b) + m.n_modes[bi]) {
      place = -1;
      return b;
    }
  }
  place = -1;
  return -1;
}

// A parameter's unit, from the last part of its name.
std::string parameter_unit(const std::string& name) {
  const std::string kind = name.substr(name.rfind('.') + 1);
  if (kind == "mass") return "kg";
  if (kind == "com") return "m";
  if (kind == "inertia") return "kg.m2";
  if (kind == "placement") return "m";
  if (name == "gravity") return "m/s2";
  return "";
}

// The parameters element by element: scalars whole, vectors by [i], 3 x 3 inertias by their upper
// triangle [r,c], 4 x 4 placements by their translation [i,3]; other shapes by every [r,c].
void append_parameters(const Model& m, std::vector<Variable>& out) {
  const ParameterTable<double> table(m);
  for (int k = 0; k < table.size(); ++k) {
    const ParameterEntry<double>& e = table.entry(k);
    // A placement moves bodies (and would open the loops): fixed. Every other parameter is tunable.
    const bool tunable = e.name.size() < 10 || e.name.compare(e.name.size() - 10, 10, ".placement") != 0;
    const std::string unit = parameter_unit(e.name),
                      description = tunable ? "model parameter (tunable)" : "model parameter (fixed)";
    if (e.size() == 1) {
      Variable v{e.name, Quantity::parameter, k, ValueType::float64, false, unit, description};
      v.tunable = tunable;
      out.push_back(v);
      continue;
    }
    for (int r = 0; r < e.rows; ++r)
      for (int c = 0; c < e.cols; ++c) {
        if (e.rows == 3 && e.cols == 3 && c < r) continue;
        if (e.rows == 4 && e.cols == 4 && (c != 3 || r == 3)) continue;
        Variable v{e.cols == 1 ? e.name + "[" + std::to_string(r) + "]"
                               : e.name + "[" + std::to_string(r) + "," + std::to_string(c) + "]",
                   Quantity::parameter, k, ValueType::float64, false, unit, description};
        v.row = r;
        v.col = c;
        v.tunable = tunable;
        out.push_back(v);
      }
  }
}

}  // namespace

DofUnits dof_units(const Model& m, int dof) {
  int place = -1;
  const int body = body_of_dof(m, dof, place);
  if (body < 0 || place < 0) return kModal;
  const char* type = joint_type_name(m.joints[static_cast<std::size_t>(body)]);
  if (!std::strcmp(type, "prismatic") || !std::strcmp(type, "translation")) return kTranslation;
  if (!std::strcmp(type, "cylindrical")) return place == 0 ? kRotation : kTranslation;
  if (!std::strcmp(type, "planar")) return place < 2 ? kTranslation : kRotation;
  if (!std::strcmp(type, "free")) return place < 3 ? kRotation : kTranslation;  // v: angular, then linear
  return kRotation;  // revolute, helical, universal, spherical
}

std::string coordinate_unit(const Model& m, int coordinate) {
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t bi = static_cast<std::size_t>(b);
    const int first = m.q_index[bi];
    if (coordinate < first || coordinate >= first + m.nq_body[bi]) continue;
    const int place = coordinate - first;
    const char* type = joint_type_name(m.joints[bi]);
    if (!std::strcmp(type, "free")) return place < 3 ? "m" : "";  // position, then the quaternion
    if (!std::strcmp(type, "spherical")) return "";               // the quaternion
    return dof_units(m, m.v_index[bi] + place).position;  // scalar coordinates; planar: x, y, theta
  }
  return "";  // a modal coordinate
}

std::vector<Variable> variables(const Model& m, const Settings& settings) {
  const std::vector<std::string>& frames = settings.frames;
  const std::vector<embed::InputKind> kinds = input_kinds(m, settings);
  std::vector<Variable> out;
  out.push_back({"time", Quantity::time, -1, ValueType::float64, false, "s", "simulation time"});
  for (int dof = 0; dof < m.nv; ++dof) {
    const DofUnits units = dof_units(m, dof);
    const std::string& name = m.dof_names[static_cast<std::size_t>(dof)];
    const embed::InputKind kind = kinds[static_cast<std::size_t>(dof)];
    const std::string& driven_unit = kind == embed::InputKind::position   ? units.position
                                     : kind == embed::InputKind::velocity ? units.velocity
                                                                          : units.acceleration;
    const char* fallback = kind == embed::InputKind::position ? "1" : kind == embed::InputKind::velocity ? "1/s" : "1/s2";
    out.push_back({"u." + name, Quantity::input, dof, ValueType::float64, false, "",
                   "torque or force of DOF " + name + " when regular (" + (units.force.empty() ? "modal force"
                                                                                               : units.force) +
                       "); its " + embed::input_kind_name(kind) + " when prescribed (" +
                       (driven_unit.empty() ? fallback : driven_unit) + ")"});
  }
  for (int dof = 0; dof < m.nv; ++dof)
    if (embed::lockable_dof(m, dof))
      out.push_back({"locked." + m.dof_names[static_cast<std::size_t>(dof)], Quantity::locked, dof, ValueType::boolean, false, "",
                     "true: the DOF is locked (stopped by an impulse, then held)"});
  for (int dof = 0; dof < m.nv; ++dof)
    if (embed::sourceable_dof(m, dof))
      out.push_back({"prescribed." + m.dof_names[static_cast<std::size_t>(dof)], Quantity::prescribed, dof,
                     ValueType::boolean, m.is_prescribed(dof), "",
                     std::string("true: the DOF follows its input u as its ") +
                         embed::input_kind_name(kinds[static_cast<std::size_t>(dof)])});
  static const char* const wrench[6] = {"tx", "ty", "tz", "fx", "fy", "fz"};
  for (std::size_t k = 0; k < settings.wrenches.size(); ++k)
    for (int row = 0; row < 6; ++row) {
      Variable v{"wrench." + settings.wrenches[k] + "." + wrench[row], Quantity::wrench, static_cast<int>(k),
                 ValueType::float64, false, row < 3 ? "N.m" : "N",
                 "external wrench on the frame: [torque; force] in its own axes about its origin, held over each "
                 "communication step"};
      v.row = row;
      out.push_back(v);
    }
  for (int k = 0; k < m.nq; ++k)
    out.push_back({"q." + m.coordinate_names[static_cast<std::size_t>(k)], Quantity::position, k, ValueType::float64, false,
                   coordinate_unit(m, k), "coordinate"});
  const struct {
    const char* prefix;
    Quantity quantity;
    std::string DofUnits::*unit;
    const char* description;
  } per_dof[] = {{"v.", Quantity::velocity, &DofUnits::velocity, "velocity"},
                 {"qdd.", Quantity::acceleration, &DofUnits::acceleration, "acceleration at the communication point"},
                 {"tau.", Quantity::force, &DofUnits::force,
                  "generalized force at the communication point (the drive torque of a prescribed or locked DOF)"}};
  for (const auto& kind : per_dof)
    for (int dof = 0; dof < m.nv; ++dof)
      out.push_back({kind.prefix + m.dof_names[static_cast<std::size_t>(dof)], kind.quantity, dof, ValueType::float64, false,
                     dof_units(m, dof).*kind.unit, kind.description});
  out.push_back({"energy.kinetic", Quantity::kinetic_energy, -1, ValueType::float64, false, "J", "kinetic energy"});
  out.push_back({"energy.potential", Quantity::potential_energy, -1, ValueType::float64, false, "J",
                 "potential energy (gravity, springs, strain)"});
  for (int loop = 0; loop < m.nloops(); ++loop)
    for (int row = 0; row < 6; ++row) {
      Variable v{"loop." + m.loops[static_cast<std::size_t>(loop)].name + "." + wrench[row], Quantity::loop_wrench,
                 loop, ValueType::float64, false, row < 3 ? "N.m" : "N",
                 "the loop's wrench at the communication point: [torque; force] of frame_b's side on frame_a's "
                 "side, world axes, about frame_a's origin (constrained_dynamics)"};
      v.row = row;
      out.push_back(v);
    }
  static const char* const units[16] = {"m", "m", "m", "", "", "", "", "rad/s", "rad/s", "rad/s",
                                        "m/s", "m/s", "m/s", "m/s2", "m/s2", "m/s2"};
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (int row = 0; row < 16; ++row) {
      Variable v{"frame." + frames[k] + "." + kFrameOutputs[row], Quantity::frame, static_cast<int>(k), ValueType::float64, false,
                 units[row], "frame output (the FMU guide lists them)"};
      v.row = row;
      out.push_back(v);
    }
  out.push_back({"integrator", Quantity::integrator, -1, ValueType::enumeration, false, "",
                 "the integrator: 1 rk4, 2 euler (semi-implicit), 3 dopri5 (adaptive)"});
  out.push_back({"substeps", Quantity::substeps, -1, ValueType::int32, false, "",
                 "internal steps per export step (the internal step is the export step / substeps)"});
  append_parameters(m, out);
  return out;
}

double parameter_element(const ParameterTable<double>& table, const Model& model, const Variable& v,
                         std::vector<double>& scratch) {
  const ParameterEntry<double>& entry = table.entry(v.index);
  table.get(model, v.index, scratch.data());
  return scratch[static_cast<std::size_t>(v.col * entry.rows + v.row)];  // column-major
}

void set_parameter_element(const ParameterTable<double>& table, Model& model, const Variable& v, double value,
                           std::vector<double>& scratch) {
  const ParameterEntry<double>& entry = table.entry(v.index);
  table.get(model, v.index, scratch.data());
  scratch[static_cast<std::size_t>(v.col * entry.rows + v.row)] = value;
  if (entry.rows == 3 && entry.cols == 3) scratch[static_cast<std::size_t>(v.row * entry.rows + v.col)] = value;
  table.set(model, v.index, scratch.data());
}

}  // namespace soadyn::fmu
