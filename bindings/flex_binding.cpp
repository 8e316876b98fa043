// FlexibleBody: a modal flexible body (soadyn/flex/flexible_body.hpp) and
// the cantilever beam builder. The binding checks array shapes and names
// the argument at fault; the C++ validation names the node, mode or matrix.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "errors.hpp"
#include "soadyn/flex/cantilever_beam.hpp"

namespace soadyn_py {

namespace {

using soadyn::FlexibleBody;
using Shape = std::vector<py::ssize_t>;

std::string shape_text(const Shape& shape, const char* any) {
  std::string s = "(";
  for (std::size_t k = 0; k < shape.size(); ++k)
    s += (k ? ", " : "") + (shape[k] < 0 ? std::string(any) : std::to_string(shape[k]));
  return s + (shape.size() == 1 ? ",)" : ")");
}

// Real array of the given shape (-1: any extent, called `free_extent` in
// messages) as C-contiguous float64. Finiteness is left to
// FlexibleBodyDescription::validate, which names the node or mode.
Array shaped_array(py::handle obj, const char* arg, const Shape& expected, const char* free_extent = "N") {
  Array a = as_float_array(obj, arg);
  Shape actual(a.shape(), a.shape() + a.ndim());
  bool ok = actual.size() == expected.size();
  for (std::size_t k = 0; ok && k < expected.size(); ++k) ok = expected[k] < 0 || actual[k] == expected[k];
  if (!ok)
    throw py::value_error(std::string(arg) + " has shape " + shape_text(actual, "") + ", expected " +
                          shape_text(expected, free_extent));
  return a;
}

soadyn::FlexibleBodyDescription<double> description_from_arrays(py::handle positions, py::handle masses,
                                                                py::handle rotary_inertias, py::handle mode_shapes,
                                                                py::handle stiffness, py::handle damping,
                                                                const std::map<std::string, int>& attachments) {
  const Array r = shaped_array(positions, "positions", {-1, 3});
  const py::ssize_t N = r.shape(0);
  const Array m = shaped_array(masses, "masses", {N});
  const Array J = shaped_array(rotary_inertias, "rotary_inertias", {N, 3, 3});
  const Array phi = shaped_array(mode_shapes, "mode_shapes", {N, 6, -1}, "n_modes");
  const py::ssize_t n = phi.shape(2);
  const Array K = shaped_array(stiffness, "stiffness", {n, n});
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  soadyn::FlexibleBodyDescription<double> d;
  for (py::ssize_t j = 0; j < N; ++j) {
    soadyn::FlexibleNode<double> node;
    node.position = Eigen::Map<const Eigen::Vector3d>(r.data(j, 0));
    node.mass = *m.data(j);
    node.rotary_inertia = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(J.data(j, 0, 0));
    node.mode_shape = Eigen::Map<const RowMajor>(phi.data(j, 0, 0), 6, n);
    d.nodes.push_back(node);
  }
  d.stiffness = Eigen::Map<const RowMajor>(K.data(), n, n);
  if (damping.is_none()) {
    d.damping = Eigen::MatrixXd::Zero(n, n);
  } else {
    const Array C = shaped_array(damping, "damping", {n, n});
    d.damping = Eigen::Map<const RowMajor>(C.data(), n, n);
  }
  d.attachments = attachments;
  return d;
}

Eigen::VectorXd eta_arg(const FlexibleBody& body, py::handle eta) {
  std::vector<std::string> names;
  for (int k = 0; k < body.n_modes(); ++k) names.push_back("mode " + std::to_string(k));
  const Array a = checked_vector(eta, "eta", names);
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
}

// Node `node` of `body`: an int in [0, n_nodes), IndexError naming it otherwise.
int node_index(const FlexibleBody& body, py::handle node) {
  const long long j = checked_integer(node, "j", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
  if (j < 0 || j >= body.n_nodes())
    throw py::index_error("node " + std::to_string(j) + " is out of range: the body has " +
                          std::to_string(body.n_nodes()) + " nodes");
  return static_cast<int>(j);
}

// `result` of the call `what` at modal coordinates `eta`, or DynamicsError
// naming the largest modal coordinate when an entry is not finite.
template <class Result>
Result finite_at(Result result, const char* what, const Eigen::VectorXd& eta) {
  if (result.allFinite()) return result;
  Eigen::Index mode = 0;
  if (eta.size() > 0) eta.cwiseAbs().maxCoeff(&mode);
  char value[32] = "";
  if (eta.size() > 0) std::snprintf(value, sizeof value, "%.6g", eta[mode]);
  throw DynamicsError(std::string("FlexibleBody.") + what + ": the result is not finite at these modal coordinates" +
                      (eta.size() > 0 ? " (mode " + std::to_string(mode) + " = " + value +
                                            " is too large for floating point)"
                                      : std::string()));
}

// (N, ...) arrays of per-node data.
py::array_t<double> node_positions(const FlexibleBody& b) {
  py::array_t<double> out({py::ssize_t(b.n_nodes()), py::ssize_t(3)});
  for (int j = 0; j < b.n_nodes(); ++j)
    for (int c = 0; c < 3; ++c) out.mutable_at(j, c) = b.node(j).position[c];
  return out;
}
py::array_t<double> node_masses(const FlexibleBody& b) {
  py::array_t<double> out(b.n_nodes());
  for (int j = 0; j < b.n_nodes(); ++j) out.mutable_at(j) = b.node(j).mass;
  return out;
}
py::array_t<double> node_rotary_inertias(const FlexibleBody& b) {
  py::array_t<double> out({py::ssize_t(b.n_nodes()), py::ssize_t(3), py::ssize_t(3)});
  for (int j = 0; j < b.n_nodes(); ++j)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.mutable_at(j, r, c) = b.node(j).rotary_inertia(r, c);
  return out;
}
py::array_t<double> node_mode_shapes(const FlexibleBody& b) {
  const int n = b.n_modes();
  py::array_t<double> out({py::ssize_t(b.n_nodes()), py::ssize_t(6), py::ssize_t(n)});
  for (int j = 0; j < b.n_nodes(); ++j)
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < n; ++k) out.mutable_at(j, r, k) = b.node(j).mode_shape(r, k);
  return out;
}

Eigen::Matrix4d homogeneous(const soadyn::Transform<double>& X) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = X.rotation;
  T.topRightCorner<3, 1>() = X.translation;
  return T;
}

}  // namespace

void bind_flexible_body(py::module_& mod) {
  py::class_<FlexibleBody>(mod, "FlexibleBody",
      "Modal flexible body: a rigid reference frame at the inboard hinge plus n_modes linear modes\n"
      "of a lumped model (nodes with point masses, rotary inertias and 6 x n_modes mode shapes,\n"
      "rows [rotation; translation]). Immutable; its modal integrals are computed once.")
      .def(py::init([](py::handle positions, py::handle masses, py::handle rotary_inertias, py::handle mode_shapes,
                       py::handle stiffness, py::handle damping, std::map<std::string, int> attachments) {
             return FlexibleBody(description_from_arrays(positions, masses, rotary_inertias, mode_shapes, stiffness,
                                                         damping, attachments));
           }),
           py::arg("positions"), py::arg("masses"), py::arg("rotary_inertias"), py::arg("mode_shapes"),
           py::arg("stiffness"), py::arg("damping") = py::none(),
           py::arg("attachments") = std::map<std::string, int>{},
           "positions (N, 3) undeformed node positions in the body frame; masses (N,); rotary_inertias\n"
           "(N, 3, 3) about each node; mode_shapes (N, 6, n_modes); stiffness and damping (n_modes,\n"
           "n_modes), symmetric positive semidefinite (damping None: zero); attachments {name: node}.\n"
           "Units: m, kg, kg m^2; mode shapes per unit modal coordinate (rad and m); stiffness in the modal\n"
           "coordinates' units (N m / rad^2 for a unit-rad mode), damping likewise per s. A wrong shape, a non-finite\n"
           "or negative mass, an asymmetric or indefinite matrix or an attachment to a missing node raises\n"
           "ValueError naming the node or the matrix.")
      .def_static("cantilever_beam",
                  [](py::handle length, py::handle EI, py::handle mass_per_length, py::handle n_modes,
                     py::handle n_nodes) {
                    const int largest = std::numeric_limits<int>::max();
                    return soadyn::cantilever_beam<double>(
                        checked_real(length, "length"), checked_real(EI, "EI"),
                        checked_real(mass_per_length, "mass_per_length"),
                        static_cast<int>(checked_integer(n_modes, "n_modes", 0, largest)),
                        static_cast<int>(checked_integer(n_nodes, "n_nodes", 0, largest)));
                  },
                  py::arg("length"), py::arg("EI"),
                  py::arg("mass_per_length"), py::arg("n_modes"), py::arg("n_nodes") = 60,
                  "Uniform Euler-Bernoulli cantilever along x, clamped at the body origin: n_nodes lumped\n"
                  "segments plus a massless 'tip' node; n_modes clamped-free bending modes per plane in the\n"
                  "x-y and x-z planes, interleaved (2 * n_modes modes in all).")
      .def_property_readonly("n_modes", &FlexibleBody::n_modes, "Number of modes (modal DOFs).")
      .def_property_readonly("n_nodes", &FlexibleBody::n_nodes, "Number of nodes N.")
      .def_property_readonly("nodes", &node_positions, "(N, 3) undeformed node positions, body frame.")
      .def_property_readonly("masses", &node_masses, "(N,) node masses, kg.")
      .def_property_readonly("rotary_inertias", &node_rotary_inertias, "(N, 3, 3) node rotary inertias, kg m^2.")
      .def_property_readonly("mode_shapes", &node_mode_shapes, "(N, 6, n_modes): rows [rotation; translation].")
      .def_property_readonly("stiffness", &FlexibleBody::stiffness, "(n_modes, n_modes) modal stiffness K.")
      .def_property_readonly("damping", &FlexibleBody::damping, "(n_modes, n_modes) modal damping D.")
      .def_property_readonly("modal_mass", &FlexibleBody::modal_mass,
                             "(n_modes, n_modes) modal mass: sum over nodes of the mode shapes' mass-weighted products.")
      .def_property_readonly("attachments", &FlexibleBody::attachments, "{name: node index} of the attachment nodes.")
      .def("augmented_mass_matrix",
           [](const FlexibleBody& b, py::handle eta) {
             const Eigen::VectorXd e = eta_arg(b, eta);
             return finite_at(b.augmented_mass_matrix(e), "augmented_mass_matrix", e);
           },
           py::arg("eta"),
           "M(eta), (6 + n_modes) square: T = 1/2 [V; eta_dot]' M [V; eta_dot], V = [omega; v_origin] body frame.")
      .def("strain_energy",
           [](const FlexibleBody& b, py::handle eta) {
             const Eigen::VectorXd e = eta_arg(b, eta);
             return finite_at(Eigen::Matrix<double, 1, 1>::Constant(b.strain_energy(e)), "strain_energy", e)[0];
           },
           py::arg("eta"), "1/2 eta' K eta.")
      .def("node_pose",
           [](const FlexibleBody& b, py::handle node, py::handle eta) {
             const int j = node_index(b, node);
             const Eigen::VectorXd e = eta_arg(b, eta);
             return finite_at(homogeneous(b.node_pose(j, e)), "node_pose", e);
           },
           py::arg("j"), py::arg("eta"), "4x4 pose of node j in the body frame at eta.")
      .def("node_load",
           [](const FlexibleBody& b, py::handle node, py::handle eta, const Eigen::Matrix<double, 6, 1>& wrench) {
             const int j = node_index(b, node);
             if (!wrench.allFinite()) throw py::value_error("wrench is not finite");
             Eigen::Matrix<double, 6, 1> body;
             Eigen::VectorXd modal(b.n_modes());
             const Eigen::VectorXd e = eta_arg(b, eta);
             b.node_load(j, e, wrench, body, modal);
             return py::make_tuple(finite_at(body, "node_load", e), finite_at(modal, "node_load", e));
           },
           py::arg("j"), py::arg("eta"), py::arg("wrench"),
           "Generalized force of `wrench` = [torque; force] applied at node j (node frame) at eta: returns\n"
           "(body_wrench, modal_forces): the wrench about the body origin in the body frame (add it to\n"
           "f_ext[body]) and the modal forces (add them to the modal DOFs' entries of tau / u).")
      .def("natural_frequencies_clamped", &FlexibleBody::clamped_natural_frequencies,
           "Natural frequencies (rad/s, ascending) of the body clamped at its reference frame.")
      .def("__repr__", [](const FlexibleBody& b) {
        return "FlexibleBody(n_nodes=" + std::to_string(b.n_nodes()) + ", n_modes=" + std::to_string(b.n_modes()) + ")";
      });
}

}  // namespace soadyn_py
