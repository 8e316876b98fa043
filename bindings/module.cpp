#include <pybind11/pybind11.h>

namespace soadyn_py {
void bind_model(pybind11::module_& mod);
void bind_algorithms(pybind11::module_& mod);
void bind_loop_kinematics(pybind11::module_& mod);
void bind_frames(pybind11::module_& mod);
void bind_equation_terms(pybind11::module_& mod);
void bind_derivatives(pybind11::module_& mod);
void bind_statics(pybind11::module_& mod);
void add_fast_paths(pybind11::module_& mod);
void bind_simulator(pybind11::module_& mod);
void bind_hil(pybind11::module_& mod);
void bind_flexible_body(pybind11::module_& mod);
void bind_force_elements(pybind11::module_& mod);
void bind_parameters(pybind11::module_& mod);
void bind_batch(pybind11::module_& mod);
}  // namespace soadyn_py

PYBIND11_MODULE(_soadyn, mod) {
  mod.doc() = "soadyn C++ core";
  soadyn_py::bind_flexible_body(mod);  // before the Model, whose signatures name it
  soadyn_py::bind_model(mod);
  soadyn_py::bind_algorithms(mod);
  soadyn_py::bind_loop_kinematics(mod);
  soadyn_py::bind_frames(mod);
  soadyn_py::bind_equation_terms(mod);
  soadyn_py::bind_derivatives(mod);
  soadyn_py::bind_statics(mod);
  soadyn_py::add_fast_paths(mod);
  soadyn_py::bind_simulator(mod);
  soadyn_py::bind_hil(mod);
  soadyn_py::bind_force_elements(mod);
  soadyn_py::bind_parameters(mod);
  soadyn_py::bind_batch(mod);
}
