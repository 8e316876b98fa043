// Named parameters (parameters.hpp) and their sensitivities
// (analysis/parameter_sensitivity.hpp): convert values between numpy's
// row-major shapes and the table's column-major storage, call the C++ code.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arrays.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/analysis/equilibrium_sensitivity.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/model/parameters.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;

// Shape of a parameter's value in Python: () for 1 x 1, (rows,) for a column, else (rows, cols).
std::vector<py::ssize_t> value_shape(const soadyn::ParameterEntry<double>& e) {
  if (e.rows == 1 && e.cols == 1) return {};
  if (e.cols == 1) return {e.rows};
  return {e.rows, e.cols};
}

std::string shape_text(const std::vector<py::ssize_t>& shape) {
  std::string s = "(";
  for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

py::object get_value(const soadyn::ParameterEntry<double>& e, const soadyn::Model& m) {
  Eigen::MatrixXd value(e.rows, e.cols);
  e.get(m, e.index, value.data());
  if (e.rows == 1 && e.cols == 1) return py::float_(value(0, 0));
  py::array_t<double> out(value_shape(e));
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(), e.rows,
                                                                                      e.cols) = value;
  return std::move(out);
}

// `value` in the table's column-major layout, its shape checked.
Eigen::MatrixXd checked_value(const soadyn::ParameterEntry<double>& e, py::handle value) {
  const Array a = as_float_array(value, e.name.c_str());
  const std::vector<py::ssize_t> shape = value_shape(e);
  std::vector<py::ssize_t> got(a.shape(), a.shape() + a.ndim());
  if (got != shape)
    throw soadyn::ParameterError("parameter '" + e.name + "': expected shape " + shape_text(shape) + ", got " +
                                 shape_text(got));
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(a.data(), e.rows,
                                                                                                  e.cols);
}

// The shape of one derivative's trailing (parameter) axes (parameter_sensitivity.hpp).
std::vector<py::ssize_t> direction_shape(const soadyn::ParameterEntry<double>& e) {
  if (soadyn::parameter_directions(e) != e.size()) return {soadyn::parameter_directions(e)};  // placement
  return value_shape(e);
}

// A (lead..., directions...) array from the columns of `d` (lead rows x directions).
py::array_t<double> derivative_array(const Eigen::MatrixXd& d, std::vector<py::ssize_t> lead,
                                     const soadyn::ParameterEntry<double>& e) {
  const std::vector<py::ssize_t> trailing = direction_shape(e);
  lead.insert(lead.end(), trailing.begin(), trailing.end());
  py::array_t<double> out(lead);
  double* o = out.mutable_data();
  const Eigen::Index n = d.cols();
  const bool matrix = trailing.size() == 2;  // C order of (a, b) is column a + 3 b of the column-major storage
  for (Eigen::Index r = 0; r < d.rows(); ++r)
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index column = matrix ? (j / trailing[1]) + trailing[0] * (j % trailing[1]) : j;
      o[r * n + j] = d(r, column);
    }
  return out;
}

// An equilibrium's (q, nu), free mask and parameter names, checked against the model.
struct EquilibriumArgs {
  EquilibriumArgs(ModelHandle& h, py::handle q_in, py::handle nu_in, const std::vector<bool>& free_mask,
                  const std::vector<std::string>& params)
      : model_version(h.model.version), free(free_mask), table(h.model) {
    const soadyn::Model& m = h.model;
    for (int k = 0; k < m.nloop_equations; ++k) equation_names.push_back("loop equation " + std::to_string(k));
    q = checked_vector(q_in, "q", m.coordinate_names);
    nu = checked_vector(nu_in, "multipliers", equation_names);
    if (free.size() != static_cast<std::size_t>(m.nv))
      throw py::value_error("free mask has " + std::to_string(free.size()) + " entries, expected nv = " +
                            std::to_string(m.nv));
    for (const auto& name : params) entries.push_back(table.require(m, name));
  }
  // The sensitivities' workspace at this equilibrium of `m` (the locked model).
  soadyn::EquilibriumSensitivity at(const soadyn::Model& m) const {
    return soadyn::EquilibriumSensitivity(m, Map(q.data(), m.nq), Map(nu.data(), m.nloop_equations), free);
  }
  std::uint64_t model_version;
  std::vector<bool> free;
  std::vector<std::string> equation_names;
  Array q, nu;
  soadyn::ParameterTable<double> table;
  std::vector<int> entries;
};

}  // namespace

void bind_parameters(py::module_& mod) {
  py::register_exception<soadyn::ParameterError>(mod, "ParameterError", PyExc_ValueError);

  mod.def("_parameter_names",
      [](const ModelHandle& h) {
        const soadyn::ParameterTable<double> table(h.model);
        std::vector<std::string> names;
        for (const auto& e : table.entries()) names.push_back(e.name);
        return names;
      },
      py::arg("model"));

  mod.def("_get_parameter",
      [](const ModelHandle& h, const std::string& name) {
        const soadyn::ParameterTable<double> table(h.model);
        return get_value(table.entry(table.require(h.model, name)), h.model);
      },
      py::arg("model"), py::arg("name"));

  mod.def("_set_parameter",
      [](ModelHandle& h, const std::string& name, py::handle value) {
        const soadyn::ParameterTable<double> table(h.model);
        const int k = table.require(h.model, name);
        const Eigen::MatrixXd v = checked_value(table.entry(k), value);
        const auto lock = h.lock_for_change();
        table.set(h.model, k, v.data());
      },
      py::arg("model"), py::arg("name"), py::arg("value"));

  mod.def("_parameter_sensitivity",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, const std::vector<std::string>& params,
         bool spanning_tree) {
        const StateArgs a(h, q, v, u, "u", py::none());
        const soadyn::ParameterTable<double> table(h.model);
        std::vector<int> entries;
        for (const auto& name : params) entries.push_back(table.require(h.model, name));
        soadyn::ParameterSensitivity sensitivity(h.model);
        const Eigen::Index nv = h.model.nv, nw = 6 * h.model.nloops();
        std::vector<Eigen::MatrixXd> dqdd, dtau, dwrench;
        for (int k : entries) {
          const int n = soadyn::parameter_directions(table.entry(k));
          dqdd.emplace_back(nv, n);
          dtau.emplace_back(nv, n);
          dwrench.emplace_back(nw, n);
        }
        soadyn::Status status;
        run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data&) {
          for (std::size_t p = 0; p < entries.size() && status.ok(); ++p)
            status = sensitivity.compute(m, table, entries[p], Map(a.q.data(), m.nq), Map(a.v.data(), m.nv),
                                         Map(a.x.data(), m.nv), dqdd[p], dtau[p], dwrench[p], spanning_tree);
        });
        raise_on(status, h.model, "parameter_sensitivity");
        std::vector<std::string> wrench_rows;  // six per loop
        for (const auto& loop : h.model.loops) wrench_rows.insert(wrench_rows.end(), 6, loop.name);
        py::dict out;
        for (std::size_t p = 0; p < entries.size(); ++p) {
          const auto& e = table.entry(entries[p]);
          const std::string quantity = "derivative with respect to '" + e.name + "'";
          refuse_non_finite_rows("parameter_sensitivity", "acceleration " + quantity, dqdd[p], h.model.dof_names);
          refuse_non_finite_rows("parameter_sensitivity", "generalized force " + quantity, dtau[p], h.model.dof_names);
          refuse_non_finite_rows("parameter_sensitivity", "loop wrench " + quantity, dwrench[p], wrench_rows);
          py::array_t<double> q_part = derivative_array(dqdd[p], {nv}, e), t_part = derivative_array(dtau[p], {nv}, e);
          if (h.model.nloops() > 0 && !spanning_tree)
            out[py::str(e.name)] =
                py::make_tuple(q_part, t_part, derivative_array(dwrench[p], {h.model.nloops(), 6}, e));
          else
            out[py::str(e.name)] = py::make_tuple(q_part, t_part);
        }
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("params"),
      py::arg("spanning_tree") = false);

  mod.def("_equilibrium_sensitivities",
      [](ModelHandle& h, py::handle q, py::handle nu, const std::vector<bool>& free,
         const std::vector<std::string>& params) {
        const EquilibriumArgs a(h, q, nu, free, params);
        py::dict out;
        soadyn::Status status;
        run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data&) {
          soadyn::EquilibriumSensitivity sensitivity = a.at(m);
          const Eigen::Index nheld = static_cast<Eigen::Index>(sensitivity.held().size());
          for (int k : a.entries) {
            const auto& e = a.table.entry(k);
            const int n = soadyn::parameter_directions(e);
            Eigen::MatrixXd dq(m.nv, n), dnu(m.nloop_equations, n), dheld(nheld, n);
            status = sensitivity.direct(m, a.table, k, dq, dnu, dheld);
            if (!status.ok()) return;
            refuse_non_finite_rows("equilibrium_sensitivities", "derivative with respect to '" + e.name + "'", dq,
                                   m.dof_names);
            out[py::str(e.name)] = py::make_tuple(derivative_array(dq, {m.nv}, e),
                                                  derivative_array(dnu, {m.nloop_equations}, e),
                                                  derivative_array(dheld, {nheld}, e));
          }
        });
        raise_on(status, h.model, "equilibrium_sensitivities");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("multipliers"), py::arg("free"), py::arg("params"),
      "{name: (dq/dp, dnu/dp, dH/dp of the held DOFs)} at a static equilibrium, direct method.");
  mod.def("_objective_gradient",
      [](ModelHandle& h, py::handle q, py::handle nu, const std::vector<bool>& free,
         const std::vector<std::string>& params, py::handle dphi_dq, py::handle dphi_dnu) {
        const EquilibriumArgs a(h, q, nu, free, params);
        const Array gq = checked_vector(dphi_dq, "dphi_dq", h.model.dof_names);
        const Array gnu = dphi_dnu.is_none() ? Array(0) : checked_vector(dphi_dnu, "dphi_dnu", a.equation_names);
        py::dict out;
        soadyn::Status status;
        run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data&) {
          soadyn::EquilibriumSensitivity sensitivity = a.at(m);
          sensitivity.set_objective(Map(gq.data(), m.nv), Map(gnu.data(), gnu.size()));
          for (int k : a.entries) {
            const auto& e = a.table.entry(k);
            Eigen::VectorXd gradient(soadyn::parameter_directions(e));
            status = sensitivity.objective_gradient(m, a.table, k, gradient);
            if (!status.ok()) return;
            refuse_non_finite_rows("objective_gradient", "gradient", gradient.transpose(), {e.name});
            out[py::str(e.name)] = derivative_array(gradient.transpose(), {}, e);
          }
        });
        raise_on(status, h.model, "objective_gradient");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("multipliers"), py::arg("free"), py::arg("params"), py::arg("dphi_dq"),
      py::arg("dphi_dnu") = py::none(), "{name: dphi/dp} of a scalar objective at a static equilibrium, adjoint method.");
}

}  // namespace soadyn_py
