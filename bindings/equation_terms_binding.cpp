// The equations of motion term by term (algorithms/equation_terms.hpp):
// check arguments, run the C++ algorithm on the model's Data, copy out.
#include <vector>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/algorithms/equation_terms.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using RowMajorMap = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

// g(q) or J' f_ext: `fn(m, d)` leaves the v-sized result in d.tau.
template <class Fn>
py::array_t<double> generalized_forces(ModelHandle& h, std::uint64_t version, const char* what, Fn&& fn) {
  auto out = fresh_array(h.model.nv);
  double* o = out.mutable_data();
  soadyn::Status status;
  run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
    status = fn(m, d);
    Eigen::Map<Eigen::VectorXd>(o, m.nv) = d.tau;
  });
  raise_on(status, h.model, what);
  return out;
}

// C(q, v), and with `mass_rate` Mdot = C + C' instead.
py::array_t<double> coriolis_or_mass_rate(ModelHandle& h, py::handle q, py::handle v, bool mass_rate,
                                          const char* what) {
  const std::uint64_t version = h.model.version;
  const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
  soadyn::EquationTermsWorkspace<double> workspace(h.model);
  Eigen::MatrixXd coriolis(h.model.nv, h.model.nv), rate(h.model.nv, h.model.nv);
  auto out = fresh_array(h.model.nv, h.model.nv);
  double* o = out.mutable_data();
  soadyn::Status status;
  run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
    const Map qm(qa.data(), m.nq), vm(va.data(), m.nv);
    if (mass_rate) {
      status = soadyn::mass_matrix_derivative<double>(m, d, workspace, qm, vm, coriolis, rate);
      RowMajorMap(o, m.nv, m.nv) = rate;
    } else {
      status = soadyn::coriolis_matrix<double>(m, d, workspace, qm, vm, coriolis);
      RowMajorMap(o, m.nv, m.nv) = coriolis;
    }
  });
  raise_on(status, h.model, what);
  return out;
}

}  // namespace

void bind_equation_terms(py::module_& mod) {
  mod.def("gravity_forces",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        return generalized_forces(h, version, "gravity_forces", [&](const soadyn::Model& m, soadyn::Data& d) {
          return soadyn::gravity_forces<double>(m, d, Map(qa.data(), m.nq));
        });
      },
      py::arg("model"), py::arg("q"),
      "g(q), (nv,): the generalized gravity forces, h(q, 0) (bias_forces at rest). On a model with flexible\n"
      "bodies, gravity only (their elastic forces are not part of it). In N and N m by the DOFs' kinds."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("external_forces_to_generalized",
      [](ModelHandle& h, py::handle q, py::handle f_ext) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        const Array f = checked_matrix(f_ext, "f_ext", 6, h.model.body_names);
        return generalized_forces(h, version, "external_forces_to_generalized",
                                  [&](const soadyn::Model& m, soadyn::Data& d) {
                                    return soadyn::external_forces_to_generalized<double>(m, d, Map(qa.data(), m.nq),
                                                                                          f.data());
                                  });
      },
      py::arg("model"), py::arg("q"), py::arg("f_ext"),
      "J(q)' f_ext, (nv,): the generalized forces of (nbodies, 6) body-frame wrenches [torque; force] about each\n"
      "body origin (the f_ext of forward_dynamics: M qdd + h = tau + J' f_ext); f_ext of another shape raises\n"
      "ValueError naming it." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("coriolis_matrix",
      [](ModelHandle& h, py::handle q, py::handle v) { return coriolis_or_mass_rate(h, q, v, false, "coriolis_matrix"); },
      py::arg("model"), py::arg("q"), py::arg("v"),
      "C(q, v), (nv, nv): C v = h(q, v) - g(q) and dM/dt - 2 C is skew-symmetric (Echeandia & Wensing 2021);\n"
      "C(q, v) = sum_k christoffel_symbols(m, q)[:, :, k] v[k]. Rigid bodies only (ValueError naming a\n"
      "flexible body)." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("mass_matrix_derivative",
      [](ModelHandle& h, py::handle q, py::handle v) {
        return coriolis_or_mass_rate(h, q, v, true, "mass_matrix_derivative");
      },
      py::arg("model"), py::arg("q"), py::arg("v"),
      "dM/dt = C + C', (nv, nv): the rate of the mass matrix along the velocity v. Rigid bodies only (ValueError\n"
      "naming a flexible body)." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("christoffel_symbols",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        soadyn::EquationTermsWorkspace<double> workspace(h.model);
        const Eigen::Index nv = h.model.nv;
        Eigen::MatrixXd gamma(nv, nv * nv);
        py::array_t<double> out(std::vector<py::ssize_t>{nv, nv, nv});
        double* o = out.mutable_data();
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          status = soadyn::christoffel_symbols<double>(m, d, workspace, Map(qa.data(), m.nq), gamma);
          for (Eigen::Index i = 0; i < nv; ++i)  // out[i, j, k] = Gamma(i, j, k), C order
            for (Eigen::Index j = 0; j < nv; ++j)
              for (Eigen::Index k = 0; k < nv; ++k) o[(i * nv + j) * nv + k] = gamma(i, k * nv + j);
        });
        raise_on(status, h.model, "christoffel_symbols");
        return out;
      },
      py::arg("model"), py::arg("q"),
      "Gamma, (nv, nv, nv), with C(q, v)[i, j] = sum_k Gamma[i, j, k] v[k]. For DOFs whose coordinates\n"
      "integrate their velocities, Gamma[i, j, k] = 1/2 (dM[i,j]/dq_k + dM[i,k]/dq_j - dM[j,k]/dq_i) (symmetric in\n"
      "j, k); for spherical, planar and free joints (body-frame velocities) the derivatives are along\n"
      "q (+) eps e_k and Gamma adds the Lie-bracket terms of that moving frame (the analysis guide, \"Equations\n"
      "term by term\"). Rigid bodies only (ValueError naming a flexible body)." SOADYN_DOC_STATE SOADYN_DOC_RAISES);
}

}  // namespace soadyn_py
