// What soadyn.export_fmu asks the FMU binary at export: the modelDescription.xml and the settings file of an
// FMU of a model, made by the code that serves them at run time (variables.hpp, model_description.hpp,
// instance.hpp), so an FMU's description and its binary always agree. Called through ctypes; results and
// errors are kept per thread until the next call.
#include <exception>
#include <sstream>
#include <string>

#include "soadyn/embed/plant.hpp"
#include "soadyn/fmu/model_description.hpp"
#include "soadyn/embed/c_api.h"
#include "soadyn/algorithms/frames.hpp"
#include "soadyn/model/model_file.hpp"

namespace {
thread_local std::string description_xml, settings, error;
}

extern "C" {

SOADYN_C_EXPORT int soadyn_fmu_describe(const char* model_json, int fmi_version, double step, int substeps,
                                        const char* integrator, const double* q0, const double* v0,
                                        const char* frames, const char* wrenches, const char* inputs,
                                        const char* model_name, const char* model_identifier, const char* token,
                                        const char* description, const char* generation_tool,
                                        const char* generation_time) {
  try {
    const soadyn::Model model = soadyn::model_from_json(model_json, "the exported model");
    soadyn::fmu::Settings s;
    s.token = token;
    s.step = step;
    s.substeps = substeps;
    s.integrator = integrator;
    s.q0.assign(q0, q0 + model.nq);
    s.v0.assign(v0, v0 + model.nv);
    std::istringstream names(frames);
    for (std::string name; names >> name;) {
      soadyn::locate_frame<double>(model, name);  // an unknown frame or one on a flexible body: named
      s.frames.push_back(name);
    }
    std::istringstream wrench_names(wrenches);
    for (std::string name; wrench_names >> name;) s.wrenches.push_back(name);
    std::istringstream input_items(inputs);  // <dof>=<kind> ...
    for (std::string item; input_items >> item;) s.inputs.push_back(soadyn::fmu::input_item(item));
    soadyn::fmu::input_kinds(model, s);  // an unknown DOF, or one that cannot follow its input: named
    if (!(step > 0) || substeps < 1) throw std::invalid_argument("the step must be > 0 and substeps >= 1");
    // The start state is checked by the code that will use it: a Plant at it.
    soadyn::embed::Plant plant(model, step / substeps, soadyn::embed::integrator_from_name(integrator));
    for (const std::string& name : s.wrenches) plant.add_wrench_input(name);  // an unknown frame: named
    plant.simulator().set_state(Eigen::Map<const Eigen::VectorXd>(q0, model.nq),
                                Eigen::Map<const Eigen::VectorXd>(v0, model.nv), 0.0);
    const soadyn::fmu::Identity id{model_name, model_identifier, token, description, generation_tool, generation_time};
    description_xml = soadyn::fmu::model_description(model, s, id, fmi_version);
    settings = soadyn::fmu::settings_text(s);
    error.clear();
    return SOADYN_OK;
  } catch (const std::exception& e) {
    error = e.what();
  }
  return SOADYN_ERROR;
}

SOADYN_C_EXPORT const char* soadyn_fmu_description_xml(void) { return description_xml.c_str(); }
SOADYN_C_EXPORT const char* soadyn_fmu_settings_text(void) { return settings.c_str(); }
SOADYN_C_EXPORT const char* soadyn_fmu_error(void) { return error.c_str(); }

}  // extern "C"
