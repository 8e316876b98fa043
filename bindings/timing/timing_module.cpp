// soadyn._timing, the timing loops of bench/ (a module of its own, built only
// with the tests or the benchmarks): an algorithm called in C++ on a pool of
// states, timed with the protocol of Pinocchio's C++ benchmarks (median of 7
// repetitions of `calls` calls cycling through the states), so C++ timings
// of models loaded in Python (URDF) compare with Pinocchio's C++ timings.
// Models are soadyn._soadyn's: that module is imported first, and its Model
// type is shared with this one through pybind11's registry.
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "model_handle.hpp"
#include "soadyn/soadyn.hpp"
#include "soadyn/sweeps/joint_angles.hpp"

namespace py = pybind11;

namespace soadyn_py {
namespace {

using Vector = Eigen::VectorXd;

double median_microseconds_per_call(const std::function<void(int)>& call, int calls, int repetitions) {
  std::vector<double> per_call;
  for (int rep = 0; rep < repetitions; ++rep) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) call(i);
    per_call.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / calls);
  }
  std::sort(per_call.begin(), per_call.end());
  return per_call[per_call.size() / 2];
}

std::vector<Vector> rows(const Array& a, py::ssize_t width, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != width || a.shape(0) < 1)
    throw py::value_error(std::string(name) + " must have shape (states, " + std::to_string(width) + ")");
  std::vector<Vector> out;
  for (py::ssize_t k = 0; k < a.shape(0); ++k) out.emplace_back(Eigen::Map<const Vector>(a.data(k, 0), width));
  return out;
}

void bind_timing(py::module_& mod) {
  mod.def("time_cpp",
      [](ModelHandle& h, const std::string& algorithm, const Array& q, const Array& v, const Array& u, int calls,
         int repetitions) {
        const soadyn::Model& m = h.model;
        const std::uint64_t version = m.version;
        const std::vector<Vector> qs = rows(q, m.nq, "q"), vs = rows(v, m.nv, "v"), us = rows(u, m.nv, "u");
        if (calls < 1 || repetitions < 1) throw py::value_error("calls and repetitions must be positive");
        const int n = static_cast<int>(qs.size());
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(h.mutex);
        refuse_changed_model(h, version);
        soadyn::Data& d = h.scratch();
        std::optional<soadyn::DynamicsDerivatives> derivatives;
        if (algorithm == "dynamics_derivatives" || algorithm == "inverse_dynamics_derivatives") derivatives.emplace(m);
        std::function<void(int)> call;
        if (algorithm == "hybrid")
          call = [&](int i) { soadyn::hybrid_dynamics<double>(m, d, qs[i % n], vs[i % n], us[i % n]); };
        else if (algorithm == "aba")
          call = [&](int i) { soadyn::forward_dynamics<double>(m, d, qs[i % n], vs[i % n], us[i % n]); };
        else if (algorithm == "rnea")
          call = [&](int i) { soadyn::inverse_dynamics<double>(m, d, qs[i % n], vs[i % n], us[i % n]); };
        else if (algorithm == "crba")
          call = [&](int i) { soadyn::mass_matrix<double>(m, d, qs[i % n]); };
        else if (algorithm == "crba_baseline") {  // the baseline kernel whatever this processor runs (crba.hpp)
          if (m.has_flexible_bodies()) throw std::invalid_argument("crba_baseline takes rigid models only");
          const auto baseline = soadyn::detail::available_mass_matrix_kernels().back().run;
          call = [&, baseline](int i) { baseline(m, d, qs[i % n]); };
        } else if (algorithm == "constrained")
          call = [&](int i) { soadyn::constrained_dynamics<double>(m, d, qs[i % n], vs[i % n], us[i % n]); };
        else if (algorithm == "dynamics_derivatives")
          call = [&](int i) { soadyn::dynamics_derivatives<double>(m, d, *derivatives, qs[i % n], vs[i % n], us[i % n]); };
        else if (algorithm == "inverse_dynamics_derivatives")
          call = [&](int i) {
            soadyn::inverse_dynamics_derivatives<double>(m, d, *derivatives, qs[i % n], vs[i % n], us[i % n]);
          };
        else
          throw std::invalid_argument("unknown algorithm '" + algorithm +
                                      "' (hybrid, aba, rnea, crba, crba_baseline, constrained, dynamics_derivatives, "
                                      "inverse_dynamics_derivatives)");
        return median_microseconds_per_call(call, calls, repetitions);
      },
      py::arg("model"), py::arg("algorithm"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("calls") = 20000,
      py::arg("repetitions") = 7,
      "Median microseconds per C++ call of 'hybrid' (model's flags), 'aba', 'rnea', 'crba', 'crba_baseline'\n"
      "(the mass matrix's baseline kernel, rigid models), 'constrained'\n"
      "(constrained_dynamics), 'dynamics_derivatives' (model's flags) or 'inverse_dynamics_derivatives' over the given\n"
      "states (rows), `calls` calls per repetition. For benchmarks; the GIL is released.");
  mod.def("joint_angle_kernel", &soadyn::joint_angle_kernel,
          "The joint-angle kernel this processor runs (sines and cosines of the joint angles).");
  mod.def("mass_matrix_kernel", &soadyn::mass_matrix_kernel, "The mass-matrix kernel this processor runs.");
}

}  // namespace
}  // namespace soadyn_py

PYBIND11_MODULE(_timing, mod) {
  mod.doc() = "C++ timing loops for soadyn's benchmarks";
  py::module_::import("soadyn._soadyn");
  soadyn_py::bind_timing(mod);
}
