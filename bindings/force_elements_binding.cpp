// Force elements (model/force_element.hpp): adding them to a model,
// listing them, their potential energy and dissipated power.
#include <optional>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/algorithms/force_elements.hpp"

namespace soadyn_py {

namespace {
using Map = Eigen::Map<const Eigen::VectorXd>;

py::dict joint_spring_dict(const soadyn::Model& m, const soadyn::JointSpringTpl<double>& s) {
  py::dict d;
  d["name"] = s.name;
  d["kind"] = "joint_spring";
  d["dof"] = m.dof_names[static_cast<std::size_t>(s.dof)];
  d["stiffness"] = s.stiffness;
  d["damping"] = s.damping;
  d["rest"] = s.rest;
  return d;
}

py::dict point_spring_dict(const soadyn::Model& m, const soadyn::PointSpringTpl<double>& s) {
  const auto body = [&](int b) { return b < 0 ? std::string("world") : m.body_names[static_cast<std::size_t>(b)]; };
  py::dict d;
  d["name"] = s.name;
  d["kind"] = "point_spring";
  d["body_a"] = body(s.body_a);
  d["body_b"] = body(s.body_b);
  d["point_a"] = Eigen::Vector3d(s.point_a);
  d["point_b"] = Eigen::Vector3d(s.point_b);
  d["stiffness"] = s.stiffness;
  d["damping"] = s.damping;
  d["rest_length"] = s.rest_length;
  if (!s.force_law.empty()) d["force_law"] = py::make_tuple(s.force_law.length, s.force_law.force);
  return d;
}
}  // namespace

void bind_force_elements(py::module_& mod) {
  mod.def("_add_joint_spring",
      [](ModelHandle& h, const std::string& name, int dof, double stiffness, double damping, double rest) {
        const auto lock = h.lock_for_change();
        return h.model.add_joint_spring(name, dof, stiffness, damping, rest);
      });
  mod.def("_add_point_spring",
      [](ModelHandle& h, const std::string& name, const std::string& frame_a, const std::string& frame_b,
         const Eigen::Vector3d& point_a, const Eigen::Vector3d& point_b, double stiffness, double damping,
         std::optional<double> rest_length, const std::vector<double>& lengths, const std::vector<double>& forces) {
        const auto lock = h.lock_for_change();
        return h.model.add_point_spring(name, frame_a, frame_b, point_a, point_b, stiffness, damping,
                                        rest_length ? &*rest_length : nullptr, lengths, forces);
      });
  mod.def("force_elements",
      [](const ModelHandle& h) {
        py::list out;
        for (const auto& s : h.model.force_elements.joint_springs) out.append(joint_spring_dict(h.model, s));
        for (const auto& s : h.model.force_elements.point_springs) out.append(point_spring_dict(h.model, s));
        return out;
      },
      py::arg("model"),
      "The model's force elements as a list of dicts (joint springs first, then point springs): name, kind, the\n"
      "DOF or the two frames and points, stiffness (N/m or N m/rad), damping (N s/m or N m s/rad), rest value.");
  mod.def("force_element_potential",
      [](ModelHandle& h, py::handle q) {
        return at_configuration(h, q, [](const soadyn::Model& m, soadyn::Data& d, const Map& qm) {
          const double e = soadyn::force_element_potential<double>(m, d, qm);
          if (!std::isfinite(e)) raise_non_finite_force_element("force_element_potential", m, d, qm, nullptr);
          return e;
        });
      },
      py::arg("model"), py::arg("q"),
      "Potential energy of the springs alone, in J (also included in potential_energy)." SOADYN_DOC_STATE
      SOADYN_DOC_RAISES);
  mod.def("dissipated_power",
      [](ModelHandle& h, py::handle q, py::handle v) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
        double p = 0;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          p = soadyn::force_element_dissipation<double>(m, d, Map(qa.data(), m.nq), Map(va.data(), m.nv));
          if (!std::isfinite(p)) raise_non_finite_force_element("dissipated_power", m, d, Map(qa.data(), m.nq), va.data());
        });
        return p;
      },
      py::arg("model"), py::arg("q"), py::arg("v"),
      "Power the dampers dissipate at (q, v), >= 0: the rate at which kinetic plus potential energy falls when "
      "no actuator or external force acts; in W." SOADYN_DOC_STATE SOADYN_DOC_RAISES);
}

}  // namespace soadyn_py
