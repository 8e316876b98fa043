// Loop assembly and projection (soadyn/constraints/loop_assembly.hpp): thin
// calls behind soadyn.assemble, soadyn.project_velocity and
// soadyn.independent_coordinates (python/soadyn/loops.py turns `hold` into
// the mask of DOFs allowed to move).
#include <pybind11/stl.h>

#include <limits>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "interrupts.hpp"
#include "model_handle.hpp"
#include "soadyn/soadyn.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;

Eigen::VectorXd free_mask(const ModelHandle& h, const std::vector<bool>& free) {
  if (free.size() != static_cast<std::size_t>(h.model.nv))
    throw py::value_error("free mask has " + std::to_string(free.size()) + " entries, expected nv = " +
                          std::to_string(h.model.nv));
  Eigen::VectorXd mask(h.model.nv);
  for (int k = 0; k < h.model.nv; ++k) mask[k] = free[static_cast<std::size_t>(k)] ? 1.0 : 0.0;
  return mask;
}

}  // namespace

void bind_loop_kinematics(py::module_& mod) {
  mod.def("_assemble",
      [](ModelHandle& h, py::handle q, const std::vector<bool>& free, py::handle tolerance_arg,
         py::handle max_iterations_arg) {
        const std::uint64_t version = h.model.version;
        const double tolerance = checked_real(tolerance_arg, "tolerance");
        const int max_iterations = static_cast<int>(
            checked_integer(max_iterations_arg, "max_iterations", 1, std::numeric_limits<int>::max()));
        const Array qa = q_arg(h, q);
        const Eigen::VectorXd mask = free_mask(h, free);
        if (!(tolerance > 0) || !std::isfinite(tolerance)) throw py::value_error("tolerance must be positive and finite");
        if (max_iterations < 1) throw py::value_error("max_iterations must be >= 1");
        auto out = fresh_array(h.model.nq);
        Eigen::Map<Eigen::VectorXd> q_out(out.mutable_data(), h.model.nq);
        soadyn::Status status;
        PythonInterrupt interrupt;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          q_out = Map(qa.data(), m.nq);
          status = soadyn::assemble_loops<double>(m, d, q_out, mask, tolerance, max_iterations, nullptr, interrupt.get());
        });
        interrupt.raise_if_interrupted();
        raise_on(status, h.model, "assemble");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("free"), py::arg("tolerance"), py::arg("max_iterations"));

  mod.def("_project_velocity",
      [](ModelHandle& h, py::handle q, py::handle v, const std::vector<bool>& free) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        const Array va = v_arg(h, v, "v");
        const Eigen::VectorXd mask = free_mask(h, free);
        auto out = fresh_array(h.model.nv);
        Eigen::Map<Eigen::VectorXd> v_out(out.mutable_data(), h.model.nv);
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          v_out = Map(va.data(), m.nv);
          status = soadyn::project_loop_velocity<double>(m, d, Map(qa.data(), m.nq), v_out, mask);
        });
        raise_on(status, h.model, "project_velocity");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("free"));

  mod.def("independent_coordinates",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        std::vector<std::string> names;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          for (const int k : soadyn::independent_coordinates<double>(m, d, Map(qa.data(), m.nq)))
            names.push_back(m.dof_names[static_cast<std::size_t>(k)]);
        });
        return names;
      },
      py::arg("model"), py::arg("q"),
      "Names of the independent DOFs at q by coordinate partitioning: the DOFs whose columns of the loop\n"
      "constraint Jacobian C(q) carry the largest pivots of a fully pivoted LU factorisation are dependent,\n"
      "the others (nv - rank C of them, in DOF order) independent." SOADYN_DOC_STATE SOADYN_DOC_RAISES);
}

}  // namespace soadyn_py
