// Static equilibrium (python/soadyn/statics.py): the Newton solve
// (soadyn/analysis/static_equilibrium.hpp) and the loop part of its matrix,
// d(C(q)' nu)/dq (soadyn/analysis/loop_force_stiffness.hpp).
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/analysis/loop_force_stiffness.hpp"
#include "interrupts.hpp"

#include <limits>
#include "soadyn/analysis/static_equilibrium.hpp"

namespace soadyn_py {


void bind_statics(py::module_& mod) {
  mod.def("_loop_equation_names", [](const ModelHandle& h) { return loop_equation_names(h.model); }, py::arg("model"),
          "'loop[i]' for each loop-closure equation, in the rows' order.");
  mod.def("_static_equilibrium",
      [](ModelHandle& h, py::handle q0, const std::vector<bool>& free, py::handle tol_arg, py::handle max_iterations_arg) {
        const std::uint64_t version = h.model.version;
        const double tol = checked_real(tol_arg, "tol");
        const int max_iterations = static_cast<int>(
            checked_integer(max_iterations_arg, "max_iterations", 1, std::numeric_limits<int>::max()));
        const Array qa = as_float_array(q0, "q0");
        require_vector_shape(qa, "static_equilibrium: q0", h.model.nq, "nq");
        soadyn::StaticEquilibrium eq(h.model);
        std::string failure;
        PythonInterrupt interrupt;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          try {
            soadyn::static_equilibrium<double>(m, d, eq, Eigen::Map<const Eigen::VectorXd>(qa.data(), m.nq), free, tol,
                                               max_iterations, interrupt.get());
          } catch (const soadyn::StaticEquilibriumError& e) {
            failure = e.what();
          }
        });
        interrupt.raise_if_interrupted();
        if (!failure.empty()) throw DynamicsError(failure);
        auto vec = [](const Eigen::VectorXd& x) {
          auto out = fresh_array(x.size());
          Eigen::Map<Eigen::VectorXd>(out.mutable_data(), x.size()) = x;
          return out;
        };
        return py::make_tuple(vec(eq.q), vec(eq.multipliers), vec(eq.generalized_force), vec(eq.stiffness_eigenvalues),
                              eq.iterations, eq.residual_norm, eq.stable);
      },
      py::arg("model"), py::arg("q0"), py::arg("free"), py::arg("tol"), py::arg("max_iterations"),
      "(q, nu, G - C' nu, stiffness eigenvalues, iterations, residual norm, stable) of the static equilibrium\n"
      "nearest q0 with the DOFs whose `free` entry is False held (soadyn.static_equilibrium wraps it).");

  mod.def("loop_force_stiffness",
      [](ModelHandle& h, py::handle q, py::handle nu) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        const Array nua = checked_vector(nu, "nu", loop_equation_names(h.model));
        auto out = fresh_array(h.model.nv, h.model.nv);
        Eigen::MatrixXd stiffness(h.model.nv, h.model.nv);
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          using Map = Eigen::Map<const Eigen::VectorXd>;
          status = soadyn::loop_force_stiffness<double>(m, d, Map(qa.data(), m.nq), Map(nua.data(), m.nloop_equations),
                                                        stiffness);
        });
        raise_on(status, h.model, "loop_force_stiffness");
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            out.mutable_data(), h.model.nv, h.model.nv) = stiffness;
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("nu"),
      "d(C(q)' nu)/dq at fixed multipliers nu (nv, nv), tangent-space columns (column k: d/de at\n"
      "integrate(q, e e_k)): the stiffness of the cut-joint reactions C' nu, analytic. nu: (nloop_equations,)\n"
      "loop-force multipliers (N, N m), as constrained_dynamics solves them; another shape raises ValueError."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);
}

}  // namespace soadyn_py
