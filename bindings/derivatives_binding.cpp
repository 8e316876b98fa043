// Analytic derivatives of the dynamics (analysis/dynamics_derivatives.hpp):
// check arguments, run the C++ algorithm on the model's Data, copy out.
#include <pybind11/complex.h>

#include "arrays.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "simulator_handle.hpp"
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/modes.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/analysis/linearization.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using RowMajorMap = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

// Runs `fn(m, d, workspace, q, v, x)` on checked arguments and returns the
// matrices `pick(m, d, workspace)` names, as fresh (nv, nv) arrays.
template <std::size_t N, class Fn, class Pick>
py::tuple derivative_call(ModelHandle& h, py::handle q, py::handle v, py::handle x, const char* x_name,
                          py::handle f_ext, const char* what, Fn&& fn, Pick&& pick) {
  const StateArgs a(h, q, v, x, x_name, f_ext);
  soadyn::DynamicsDerivatives workspace(h.model);
  std::array<py::array_t<double>, N> out;
  for (auto& o : out) o = fresh_array(h.model.nv, h.model.nv);
  soadyn::Status status;
  run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
    status = fn(m, d, workspace, Map(a.q.data(), m.nq), Map(a.v.data(), m.nv), Map(a.x.data(), m.nv), a.f_ext);
    if (!status.ok()) return;
    const std::array<const Eigen::MatrixXd*, N> results = pick(d, workspace);
    for (std::size_t k = 0; k < N; ++k) {
      refuse_non_finite_rows(what, "derivative row", *results[k], m.dof_names);
      RowMajorMap(out[k].mutable_data(), m.nv, m.nv) = *results[k];
    }
  });
  raise_on(status, h.model, what);
  py::tuple t(N);
  for (std::size_t k = 0; k < N; ++k) t[k] = out[k];
  return t;
}

py::array_t<double> copy_out(const Eigen::MatrixXd& x) {
  auto out = fresh_array(x.rows(), x.cols());
  RowMajorMap(out.mutable_data(), x.rows(), x.cols()) = x;
  return out;
}

py::array_t<double> copy_vector(const Eigen::VectorXd& x) {
  auto out = fresh_array(x.size());
  Eigen::Map<Eigen::VectorXd>(out.mutable_data(), x.size()) = x;
  return out;
}

// The modes `compute()` returns; a linearised system without finite roots
// (std::domain_error of modes.cpp) raises DynamicsError.
template <class Compute>
soadyn::Modes modes_or_dynamics_error(Compute&& compute) {
  try {
    return compute();
  } catch (const std::domain_error& e) {
    throw DynamicsError(e.what());
  }
}

// (dofs, w, zeta, roots, shapes) of soadyn::Modes for the Python Modes class.
py::tuple modes_tuple(const soadyn::Modes& result) {
  py::list dofs;
  for (int k : result.dofs) dofs.append(k);
  py::array_t<std::complex<double>> roots({result.roots.rows(), result.roots.cols()});
  auto r = roots.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < result.roots.rows(); ++i)
    for (Eigen::Index j = 0; j < result.roots.cols(); ++j) r(i, j) = result.roots(i, j);
  return py::make_tuple(dofs, copy_vector(result.angular_frequency), copy_vector(result.damping_ratio), roots,
                        copy_out(result.shapes));
}

}  // namespace

void bind_derivatives(py::module_& mod) {
  mod.def("_tree_inverse_dynamics_derivatives",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle qdd, py::handle f_ext) {
        return derivative_call<3>(
            h, q, v, qdd, "qdd", f_ext, "inverse_dynamics_derivatives",
            [](const soadyn::Model& m, soadyn::Data& d, soadyn::DynamicsDerivatives& w, const Map& qm,
               const Map& vm, const Map& xm, const double* f) {
              return soadyn::inverse_dynamics_derivatives<double>(m, d, w, qm, vm, xm, f);
            },
            [](const soadyn::Data& d, const soadyn::DynamicsDerivatives& w) {
              return std::array<const Eigen::MatrixXd*, 3>{&w.inverse_dq, &w.inverse_dv, &d.mass_matrix};
            });
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("qdd"), py::arg("f_ext") = py::none());

  mod.def("_tree_dynamics_derivatives",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, py::handle f_ext) {
        return derivative_call<6>(
            h, q, v, u, "u", f_ext, "dynamics_derivatives",
            [](const soadyn::Model& m, soadyn::Data& d, soadyn::DynamicsDerivatives& w, const Map& qm,
               const Map& vm, const Map& xm, const double* f) {
              return soadyn::dynamics_derivatives<double>(m, d, w, qm, vm, xm, f);
            },
            [](const soadyn::Data&, const soadyn::DynamicsDerivatives& w) {
              return std::array<const Eigen::MatrixXd*, 6>{&w.dqdd_dq, &w.dqdd_dv, &w.dqdd_du,
                                                           &w.dtau_dq, &w.dtau_dv, &w.dtau_du};
            });
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("f_ext") = py::none());

  mod.def("_dual_dynamics_derivatives",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, py::handle f_ext, bool spanning_tree) {
        const StateArgs a(h, q, v, u, "u", f_ext);
        soadyn::ParameterSensitivity dual(h.model);
        const Eigen::Index nv = h.model.nv;
        std::array<Eigen::MatrixXd, 6> d;
        for (auto& x : d) x.setZero(nv, nv);
        soadyn::Status status;
        run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data&) {
          status = dual.state_derivatives(m, Map(a.q.data(), m.nq), Map(a.v.data(), m.nv), Map(a.x.data(), m.nv),
                                          a.f_ext, d[0], d[1], d[2], d[3], d[4], d[5], spanning_tree);
        });
        raise_on(status, h.model, "dynamics_derivatives");
        py::tuple t(6);
        for (std::size_t k = 0; k < 6; ++k) {
          refuse_non_finite_rows("dynamics_derivatives", "derivative row", d[k], h.model.dof_names);
          t[k] = copy_out(d[k]);
        }
        return t;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("f_ext") = py::none(),
      py::arg("spanning_tree") = false);

  mod.def("_linearize",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, py::object dt, py::handle integrator,
         py::handle f_ext) {
        const StateArgs a(h, q, v, u, "u", f_ext);
        const bool discrete = !dt.is_none();
        const double step = discrete ? checked_real(dt, "dt") : 0.0;
        const soadyn::Integrator chosen = integrator_from(checked_text(integrator, "integrator"));
        soadyn::Linearization workspace(h.model);
        py::array_t<double> A, B;
        soadyn::Status status;
        run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
          const Map qm(a.q.data(), m.nq), vm(a.v.data(), m.nv), um(a.x.data(), m.nv);
          status = discrete ? soadyn::linearize_step<double>(m, d, workspace, qm, vm, um, step, chosen, a.f_ext)
                            : soadyn::linearize<double>(m, d, workspace, qm, vm, um, a.f_ext);
        });
        raise_on(status, h.model, "linearize");
        const std::vector<std::string> rows = state_names(h.model);
        refuse_non_finite_rows("linearize", "row of A", workspace.A, rows);
        refuse_non_finite_rows("linearize", "row of B", workspace.B, rows);
        return py::make_tuple(copy_out(workspace.A), copy_out(workspace.B));
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("dt"), py::arg("integrator"),
      py::arg("f_ext") = py::none());

  mod.def("_modes",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        soadyn::DynamicsDerivatives workspace(h.model);
        soadyn::Modes result;
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          result = modes_or_dynamics_error([&] { return soadyn::modes(m, d, workspace, Map(qa.data(), m.nq), status); });
        });
        raise_on(status, h.model, "modes");
        return modes_tuple(result);
      },
      py::arg("model"), py::arg("q"));
  mod.def("_modes_of",
      [](ModelHandle& h, py::handle M, py::handle K, py::handle D) {
        using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        const soadyn::Model& m = h.model;
        const auto matrix = [&](py::handle obj, const char* arg) -> Eigen::MatrixXd {
          const Array a = checked_matrix(obj, arg, m.nv, m.dof_names);
          return Eigen::Map<const RowMajor>(a.data(), m.nv, m.nv);
        };
        const Eigen::MatrixXd mass = matrix(M, "mass_matrix"), stiffness = matrix(K, "stiffness"),
                              damping = matrix(D, "damping");
        std::vector<int> regular;
        for (int k = 0; k < m.nv; ++k)
          if (!m.is_prescribed(k)) regular.push_back(k);
        return modes_tuple(modes_or_dynamics_error([&] { return soadyn::modes_of(mass, stiffness, damping, regular); }));
      },
      py::arg("model"), py::arg("mass_matrix"), py::arg("stiffness"), py::arg("damping"));
}

}  // namespace soadyn_py
