#include "soadyn/fmu/model_description.hpp"

#include <set>
#include <vector>
#include <sstream>
#include <stdexcept>

namespace soadyn::fmu {

namespace {

std::string escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

// The SI base units of each unit the variables use (FMI's BaseUnit exponents).
const char* base_unit(const std::string& unit) {
  if (unit == "s") return "s=\"1\"";
  if (unit == "m") return "m=\"1\"";
  if (unit == "rad") return "rad=\"1\"";
  if (unit == "m/s") return "m=\"1\" s=\"-1\"";
  if (unit == "rad/s") return "rad=\"1\" s=\"-1\"";
  if (unit == "m/s2") return "m=\"1\" s=\"-2\"";
  if (unit == "rad/s2") return "rad=\"1\" s=\"-2\"";
  if (unit == "N") return "kg=\"1\" m=\"1\" s=\"-2\"";
  if (unit == "N.m" || unit == "J") return "kg=\"1\" m=\"2\" s=\"-2\"";
  if (unit == "kg") return "kg=\"1\"";
  if (unit == "kg.m2") return "kg=\"1\" m=\"2\"";
  throw std::logic_error("no base unit for '" + unit + "'");
}

bool is_parameter(const Variable& v) {
  return v.quantity == Quantity::parameter || v.quantity == Quantity::integrator || v.quantity == Quantity::substeps;
}

bool is_output(const Variable& v) {
  return v.quantity != Quantity::time && v.quantity != Quantity::input && v.quantity != Quantity::locked &&
         v.quantity != Quantity::prescribed && v.quantity != Quantity::wrench && !is_parameter(v);
}

const char* causality(const Variable& v) {
  if (v.quantity == Quantity::time) return "independent";
  if (is_parameter(v)) return "parameter";
  return is_output(v) ? "output" : "input";
}

const char* variability(const Variable& v) {
  if (is_parameter(v)) return v.tunable ? "tunable" : "fixed";
  return v.type == ValueType::float64 ? "continuous" : "discrete";
}

// The start attribute of an input or parameter ("" for the others, whose values are computed).
std::string start(const Model& model, const Settings& settings, const Variable& v) {
  if (v.type == ValueType::boolean) return std::string(" start=\"") + (v.start_true ? "true" : "false") + "\"";
  if (v.quantity == Quantity::input || v.quantity == Quantity::wrench) return " start=\"0\"";
  if (v.quantity == Quantity::integrator) return " start=\"" + std::to_string(integrator_number(settings.integrator)) + "\"";
  if (v.quantity == Quantity::substeps) return " start=\"" + std::to_string(settings.substeps) + "\"";
  if (v.quantity != Quantity::parameter) return "";
  const ParameterTable<double> table(model);
  std::vector<double> scratch(16);
  return " start=\"" + number(parameter_element(table, model, v, scratch)) + "\"";
}

std::string attributes(const Variable& v, std::size_t vr) {
  std::string a = "name=\"" + escaped(v.name) + "\" valueReference=\"" + std::to_string(vr) + "\" causality=\"" +
                  causality(v) + "\" variability=\"" + variability(v) + "\"";
  if (!v.description.empty()) a += " description=\"" + escaped(v.description) + "\"";
  return a;
}

std::string unit_definitions(const std::vector<Variable>& variables) {
  std::set<std::string> units;
  for (const Variable& v : variables)
    if (!v.unit.empty()) units.insert(v.unit);
  std::string out = "  <UnitDefinitions>\n";
  for (const std::string& u : units)
    out += "    <Unit name=\"" + u + "\"><BaseUnit " + base_unit(u) + "/></Unit>\n";
  return out + "  </UnitDefinitions>\n";
}

constexpr const char* kIntegratorType = "soadyn.Integrator";

// The integrator parameter's items, as FMI 3 (EnumerationType) and FMI 2 (SimpleType) declare them.
std::string integrator_items(const char* indent) {
  std::string out;
  for (int k = 0; k < 3; ++k)
    out += std::string(indent) + "<Item name=\"" + kIntegrators[k] + "\" value=\"" + std::to_string(k + 1) + "\"/>\n";
  return out;
}

// FMI 3's element of a variable's type.
const char* fmi3_element(const Variable& v) {
  switch (v.type) {
    case ValueType::boolean: return "Boolean";
    case ValueType::int32: return "Int32";
    case ValueType::enumeration: return "Enumeration";
    default: return "Float64";
  }
}

std::string fmi3(const Model& model, const Settings& settings, const Identity& id) {
  const std::vector<Variable> vars = variables(model, settings);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"" << escaped(id.model_name) << "\" instantiationToken=\""
    << escaped(id.token) << "\" description=\"" << escaped(id.description) << "\" generationTool=\""
    << escaped(id.generation_tool) << "\" generationDateAndTime=\"" << escaped(id.generation_time)
    << "\" variableNamingConvention=\"flat\">\n"
    << "  <CoSimulation modelIdentifier=\"" << escaped(id.model_identifier)
    << "\" canHandleVariableCommunicationStepSize=\"true\" canGetAndSetFMUState=\"true\" "
       "canSerializeFMUState=\"true\" fixedInternalStepSize=\""
    << number(settings.step / settings.substeps) << "\" hasEventMode=\"false\"/>\n"
    << unit_definitions(vars) << "  <TypeDefinitions>\n    <EnumerationType name=\"" << kIntegratorType << "\">\n"
    << integrator_items("      ") << "    </EnumerationType>\n  </TypeDefinitions>\n"
    << "  <DefaultExperiment startTime=\"0\" stepSize=\"" << number(settings.step) << "\"/>\n  <ModelVariables>\n";
  for (std::size_t vr = 0; vr < vars.size(); ++vr) {
    const Variable& v = vars[vr];
    x << "    <" << fmi3_element(v) << " " << attributes(v, vr);
    if (v.type == ValueType::enumeration) x << " declaredType=\"" << kIntegratorType << "\"";
    if (!v.unit.empty()) x << " unit=\"" << v.unit << "\"";
    x << start(model, settings, v) << "/>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n";
  for (std::size_t vr = 0; vr < vars.size(); ++vr)
    if (is_output(vars[vr])) x << "    <Output valueReference=\"" << vr << "\"/>\n";
  for (std::size_t vr = 0; vr < vars.size(); ++vr)
    if (is_output(vars[vr])) x << "    <InitialUnknown valueReference=\"" << vr << "\"/>\n";
  x << "  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

std::string fmi2(const Model& model, const Settings& settings, const Identity& id) {
  const std::vector<Variable> vars = variables(model, settings);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"" << escaped(id.model_name) << "\" guid=\""
    << escaped(id.token) << "\" description=\"" << escaped(id.description) << "\" generationTool=\""
    << escaped(id.generation_tool) << "\" generationDateAndTime=\"" << escaped(id.generation_time)
    << "\" variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">\n"
    << "  <CoSimulation modelIdentifier=\"" << escaped(id.model_identifier)
    << "\" canHandleVariableCommunicationStepSize=\"true\" canGetAndSetFMUstate=\"true\" "
       "canSerializeFMUstate=\"true\"/>\n"
    << unit_definitions(vars) << "  <TypeDefinitions>\n    <SimpleType name=\"" << kIntegratorType
    << "\">\n      <Enumeration>\n" << integrator_items("        ")
    << "      </Enumeration>\n    </SimpleType>\n  </TypeDefinitions>\n"
    << "  <DefaultExperiment startTime=\"0\" stepSize=\"" << number(settings.step) << "\"/>\n  <ModelVariables>\n";
  // FMI 2.0 needs no independent variable, and readers disagree on its start: time is left out, and
  // value reference 0 unused. ModelStructure's indices count the variables written, from 1.
  std::vector<std::size_t> position(vars.size(), 0);
  std::size_t written = 0;
  for (std::size_t vr = 0; vr < vars.size(); ++vr) {
    const Variable& v = vars[vr];
    if (v.quantity == Quantity::time) continue;
    position[vr] = ++written;
    x << "    <ScalarVariable " << attributes(v, vr) << ">";
    if (v.type == ValueType::boolean) {
      x << "<Boolean" << start(model, settings, v) << "/>";
    } else if (v.type == ValueType::int32) {
      x << "<Integer" << start(model, settings, v) << "/>";
    } else if (v.type == ValueType::enumeration) {
      x << "<Enumeration declaredType=\"" << kIntegratorType << "\"" << start(model, settings, v) << "/>";
    } else {
      x << "<Real";
      if (!v.unit.empty()) x << " unit=\"" << v.unit << "\"";
      x << start(model, settings, v) << "/>";
    }
    x << "</ScalarVariable>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
  for (std::size_t vr = 0; vr < vars.size(); ++vr)
    if (is_output(vars[vr])) x << "      <Unknown index=\"" << position[vr] << "\"/>\n";
  x << "    </Outputs>\n    <InitialUnknowns>\n";
  for (std::size_t vr = 0; vr < vars.size(); ++vr)
    if (is_output(vars[vr])) x << "      <Unknown index=\"" << position[vr] << "\"/>\n";
  x << "    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

}  // namespace

std::string model_description(const Model& model, const Settings& settings, const Identity& identity,
                              int fmi_version) {
  if (fmi_version == 3) return fmi3(model, settings, identity);
  if (fmi_version == 2) return fmi2(model, settings, identity);
  throw std::invalid_argument("FMI version must be 2 or 3, got " + std::to_string(fmi_version));
}

}  // namespace soadyn::fmu
