// The C API (soadyn/embed/c_api.h) over embed::Plant. Setup calls catch every C++ exception at the boundary and
// turn it into SOADYN_ERROR with the message in the thread's last error; the calls after soadyn_sim_create
// do not throw (Plant's contract) and allocate only an error's message.
#include "soadyn/embed/c_api.h"

#include <exception>
#include <memory>
#include <new>
#include <string>

#include "soadyn/embed/plant.hpp"
#include "soadyn/model/model_file.hpp"

struct soadyn_model {
  soadyn::Model model;
};

struct soadyn_sim {
  soadyn::embed::Plant plant;
};

namespace {

thread_local std::string last_error;

int fail(const std::string& message) {
  last_error = message;
  return SOADYN_ERROR;
}

int ok() {
  last_error.clear();
  return SOADYN_OK;
}

int result(const soadyn_sim* sim, const soadyn::Status& s) {
  return s.ok() ? ok() : fail(sim->plant.describe(s));
}

bool valid_dof(const soadyn_sim* sim, int dof, const char* call) {
  if (sim == nullptr) {
    fail(std::string(call) + ": the simulator is NULL");
    return false;
  }
  if (dof < 0 || dof >= sim->plant.nv()) {
    fail(std::string(call) + ": DOF index " + std::to_string(dof) + " is out of range (the model has " +
         std::to_string(sim->plant.nv()) + " DOFs)");
    return false;
  }
  return true;
}

bool valid_array(const soadyn_sim* sim, const void* array, int given, int expected, const char* call,
                 const char* what) {
  if (sim == nullptr) return fail(std::string(call) + ": the simulator is NULL") == SOADYN_OK;
  if (array == nullptr) return fail(std::string(call) + ": " + what + " is NULL") == SOADYN_OK;
  if (given != expected)
    return fail(std::string(call) + ": " + what + " has " + std::to_string(given) + " entries, the model needs " +
                std::to_string(expected)) == SOADYN_OK;
  return true;
}

template <class Make>
soadyn_model* make_model(Make&& make) {
  try {
    auto* m = new soadyn_model{make()};
    ok();
    return m;
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown error while reading the model");
  }
  return nullptr;
}

}  // namespace

extern "C" {

int soadyn_c_api_version(void) { return SOADYN_C_API_VERSION; }

const char* soadyn_last_error(void) { return last_error.c_str(); }

soadyn_model* soadyn_model_load(const char* path) {
  if (path == nullptr) return fail("soadyn_model_load: the path is NULL"), nullptr;
  return make_model([&] { return soadyn::load_model(path); });
}

soadyn_model* soadyn_model_from_json(const char* text) {
  if (text == nullptr) return fail("soadyn_model_from_json: the text is NULL"), nullptr;
  return make_model([&] { return soadyn::model_from_json(text, "model JSON"); });
}

void soadyn_model_free(soadyn_model* model) { delete model; }

int soadyn_model_nq(const soadyn_model* model) { return model ? model->model.nq : -1; }
int soadyn_model_nv(const soadyn_model* model) { return model ? model->model.nv : -1; }

const char* soadyn_model_dof_name(const soadyn_model* model, int dof) {
  if (!model || dof < 0 || dof >= model->model.nv) return nullptr;
  return model->model.dof_names[static_cast<std::size_t>(dof)].c_str();
}

const char* soadyn_model_coordinate_name(const soadyn_model* model, int coordinate) {
  if (!model || coordinate < 0 || coordinate >= model->model.nq) return nullptr;
  return model->model.coordinate_names[static_cast<std::size_t>(coordinate)].c_str();
}

int soadyn_model_dof_index(const soadyn_model* model, const char* name) {
  if (!model || !name) return -1;
  return model->model.dof_index(name);
}

int soadyn_model_is_prescribed(const soadyn_model* model, int dof) {
  if (!model || dof < 0 || dof >= model->model.nv) return 0;
  return model->model.is_prescribed(dof) ? 1 : 0;
}

soadyn_sim* soadyn_sim_create(const soadyn_model* model, double dt, const char* integrator) {
  if (model == nullptr) return fail("soadyn_sim_create: the model is NULL"), nullptr;
  try {
    auto* sim = new soadyn_sim{soadyn::embed::Plant(
        model->model, dt, soadyn::embed::integrator_from_name(integrator ? integrator : "rk4"))};
    ok();
    return sim;
  } catch (const std::exception& e) {
    fail(std::string("soadyn_sim_create: ") + e.what());
  } catch (...) {
    fail("soadyn_sim_create: unknown error");
  }
  return nullptr;
}

void soadyn_sim_free(soadyn_sim* sim) { delete sim; }

int soadyn_sim_set_input(soadyn_sim* sim, int dof, double u) {
  if (!valid_dof(sim, dof, "soadyn_sim_set_input")) return SOADYN_ERROR;
  sim->plant.set_u(dof, u);
  return ok();
}

int soadyn_sim_set_input_by_name(soadyn_sim* sim, const char* dof, double u) {
  if (sim == nullptr || dof == nullptr) return fail("soadyn_sim_set_input_by_name: a NULL argument");
  const int index = sim->plant.model().dof_index(dof);
  if (index < 0) return fail(std::string("soadyn_sim_set_input_by_name: no DOF named '") + dof + "'");
  sim->plant.set_u(index, u);
  return ok();
}

int soadyn_sim_lock(soadyn_sim* sim, int dof) {
  if (!valid_dof(sim, dof, "soadyn_sim_lock")) return SOADYN_ERROR;
  if (!sim->plant.lockable(dof)) return fail("soadyn_sim_lock: a modal DOF cannot be locked");
  sim->plant.set_locked(dof, true);
  return result(sim, sim->plant.apply_inputs());
}

int soadyn_sim_release(soadyn_sim* sim, int dof) {
  if (!valid_dof(sim, dof, "soadyn_sim_release")) return SOADYN_ERROR;
  sim->plant.set_locked(dof, false);
  sim->plant.set_prescribed(dof, false);
  return result(sim, sim->plant.apply_inputs());
}

int soadyn_sim_prescribe(soadyn_sim* sim, int dof) {
  if (!valid_dof(sim, dof, "soadyn_sim_prescribe")) return SOADYN_ERROR;
  if (!sim->plant.sourceable(dof))
    return fail("soadyn_sim_prescribe: DOF '" + sim->plant.model().dof_names[static_cast<std::size_t>(dof)] +
                "' has no scalar coordinate (planar, spherical, free or modal): it cannot follow an input");
  sim->plant.set_locked(dof, false);
  sim->plant.set_prescribed(dof, true);
  return result(sim, sim->plant.apply_inputs());
}

int soadyn_sim_set_input_kind(soadyn_sim* sim, int dof, const char* kind) {
  if (!valid_dof(sim, dof, "soadyn_sim_set_input_kind")) return SOADYN_ERROR;
  if (kind == nullptr) return fail("soadyn_sim_set_input_kind: the kind is NULL");
  try {
    sim->plant.set_input_kind(dof, soadyn::embed::input_kind_from_name(kind));
  } catch (const std::exception& e) {
    return fail(std::string("soadyn_sim_set_input_kind: ") + e.what());
  }
  return ok();
}

int soadyn_sim_add_wrench_input(soadyn_sim* sim, const char* frame) {
  if (sim == nullptr || frame == nullptr) return fail("soadyn_sim_add_wrench_input: a NULL argument"), -1;
  try {
    const int index = sim->plant.add_wrench_input(frame);
    ok();
    return index;
  } catch (const std::exception& e) {
    fail(std::string("soadyn_sim_add_wrench_input: ") + e.what());
  }
  return -1;
}

int soadyn_sim_set_wrench(soadyn_sim* sim, int wrench, const double values[6]) {
  if (sim == nullptr || values == nullptr) return fail("soadyn_sim_set_wrench: a NULL argument");
  if (wrench < 0 || wrench >= sim->plant.wrench_inputs())
    return fail("soadyn_sim_set_wrench: wrench input " + std::to_string(wrench) + " does not exist (the simulator has " +
                std::to_string(sim->plant.wrench_inputs()) + ")");
  for (int k = 0; k < 6; ++k) sim->plant.set_wrench(wrench, k, values[k]);
  return ok();
}

int soadyn_sim_step(soadyn_sim* sim, int steps) {
  if (sim == nullptr) return fail("soadyn_sim_step: the simulator is NULL");
  if (steps < 0) return fail("soadyn_sim_step: a negative number of steps");
  const int bad = sim->plant.non_finite_input();
  if (bad >= 0)
    return fail("soadyn_sim_step: the input of DOF '" + sim->plant.model().dof_names[static_cast<std::size_t>(bad)] +
                "' is not finite");
  const int bad_wrench = sim->plant.non_finite_wrench();
  if (bad_wrench >= 0)
    return fail("soadyn_sim_step: wrench input " + std::to_string(bad_wrench) + " is not finite");
  return result(sim, sim->plant.advance(steps));
}

double soadyn_sim_time(const soadyn_sim* sim) { return sim ? sim->plant.simulator().time() : 0.0; }

int soadyn_sim_get_q(const soadyn_sim* sim, double* q, int nq) {
  if (!valid_array(sim, q, nq, sim ? sim->plant.nq() : 0, "soadyn_sim_get_q", "q")) return SOADYN_ERROR;
  const auto& x = sim->plant.simulator().q();
  for (int k = 0; k < nq; ++k) q[k] = x[k];
  return ok();
}

int soadyn_sim_get_v(const soadyn_sim* sim, double* v, int nv) {
  if (!valid_array(sim, v, nv, sim ? sim->plant.nv() : 0, "soadyn_sim_get_v", "v")) return SOADYN_ERROR;
  const auto& x = sim->plant.simulator().v();
  for (int k = 0; k < nv; ++k) v[k] = x[k];
  return ok();
}

int soadyn_sim_get_qdd_tau(soadyn_sim* sim, double* qdd, double* tau, int nv) {
  const int expected = sim ? sim->plant.nv() : 0;
  if (!valid_array(sim, qdd, nv, expected, "soadyn_sim_get_qdd_tau", "qdd") ||
      !valid_array(sim, tau, nv, expected, "soadyn_sim_get_qdd_tau", "tau"))
    return SOADYN_ERROR;
  const soadyn::Status s = sim->plant.evaluate_outputs();
  if (!s.ok()) return result(sim, s);
  for (int k = 0; k < nv; ++k) {
    qdd[k] = sim->plant.qdd()[k];
    tau[k] = sim->plant.tau()[k];
  }
  return ok();
}

int soadyn_sim_set_state(soadyn_sim* sim, const double* q, int nq, const double* v, int nv, double t) {
  if (!valid_array(sim, q, nq, sim ? sim->plant.nq() : 0, "soadyn_sim_set_state", "q") ||
      !valid_array(sim, v, nv, sim->plant.nv(), "soadyn_sim_set_state", "v"))
    return SOADYN_ERROR;
  try {
    sim->plant.simulator().set_state(Eigen::Map<const Eigen::VectorXd>(q, nq), Eigen::Map<const Eigen::VectorXd>(v, nv),
                                     t);
  } catch (const std::exception& e) {
    return fail(std::string("soadyn_sim_set_state: ") + e.what());
  }
  return ok();
}

size_t soadyn_sim_state_size(const soadyn_sim* sim) { return sim ? sim->plant.state_size() : 0; }

int soadyn_sim_save_state(const soadyn_sim* sim, void* buffer, size_t size) {
  if (sim == nullptr || buffer == nullptr) return fail("soadyn_sim_save_state: a NULL argument");
  if (size < sim->plant.state_size())
    return fail("soadyn_sim_save_state: the buffer holds " + std::to_string(size) + " bytes, the state needs " +
                std::to_string(sim->plant.state_size()));
  sim->plant.save_state(static_cast<unsigned char*>(buffer));
  return ok();
}

int soadyn_sim_load_state(soadyn_sim* sim, const void* buffer, size_t size) {
  if (sim == nullptr || buffer == nullptr) return fail("soadyn_sim_load_state: a NULL argument");
  const char* why = "";
  if (!sim->plant.load_state(static_cast<const unsigned char*>(buffer), size, &why))
    return fail(std::string("soadyn_sim_load_state: ") + why);
  return ok();
}

}  // extern "C"
