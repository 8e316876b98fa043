// modelDescription.xml of a soadyn FMU (FMI 3.0 or 2.0 co-simulation), written from the same variable
// table the binary serves (variables.hpp), by the binary itself at export (soadyn_fmu_model_description).
#pragma once
#include <string>

#include "soadyn/fmu/instance.hpp"

namespace soadyn::fmu {

struct Identity {
  std::string model_name, model_identifier, token, description, generation_tool, generation_time;
};

// fmi_version: 2 or 3; throws std::invalid_argument for another.
std::string model_description(const Model& model, const Settings& settings, const Identity& identity,
                              int fmi_version);

}  // namespace soadyn::fmu
