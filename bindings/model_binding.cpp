// Joint and Model classes. Argument sugar (placements, names, masks) lives in
// python/soadyn/model.py; this file only exposes the C++ objects.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>
#include <tuple>
#include <utility>
#include <variant>

#include "soadyn/model/model_file.hpp"
#include "arrays.hpp"
#include "model_handle.hpp"
#include "soadyn/model/modal_rule.hpp"
#include "soadyn/flex/flexible_body.hpp"
#include "soadyn_scenes/scenes.hpp"

namespace soadyn_py {

using soadyn::Vec3;
using JointModel = soadyn::JointModel<double>;

// A joint type with an optional name (default: the body's name).
struct JointSpec {
  JointModel joint;
  std::string name;
};

namespace {

// A per-body flag vector (std::uint8_t) as a Python list of bools.
std::vector<bool> as_bools(const std::vector<std::uint8_t>& flags) { return {flags.begin(), flags.end()}; }

// Joint.<type>(parameters..., name=""): one static factory per alternative
// of JointModel, its arguments named by the joint type's parameter_names.
template <class J, class... P, std::size_t... I>
void def_joint_factory(py::class_<JointSpec>& cls, std::tuple<P...>*, std::index_sequence<I...>) {
  cls.def_static(
      J::name, [](const P&... parameters, const std::string& name) { return JointSpec{JointModel(J{parameters...}), name}; },
      py::arg(J::parameter_names[I])..., py::arg("name") = "", J::description);
}

template <class... J>
void def_joint_factories(py::class_<JointSpec>& cls, std::variant<J...>*) {
  (def_joint_factory<J>(cls, static_cast<typename J::Parameters*>(nullptr),
                        std::make_index_sequence<std::tuple_size_v<typename J::Parameters>>{}),
   ...);
}

py::array_t<bool> prescribed_mask(const soadyn::Model& m) {
  py::array_t<bool> mask(m.nv);
  for (int k = 0; k < m.nv; ++k) mask.mutable_at(k) = m.prescribed[static_cast<std::size_t>(k)] != 0;
  return mask;
}

// Checked before any flag changes, so a refused request changes nothing.
// (Python checks the range first; checked again under the model's lock, since
// another thread may have replaced the model in between.)
void refuse_modal(const soadyn::Model& m, int dof, bool flag) {
  if (dof < 0 || dof >= m.nv)
    throw py::value_error("DOF index " + std::to_string(dof) + " is out of range (nv = " + std::to_string(m.nv) + ")");
  if (flag) soadyn::require_regular_modal_dof(m, dof);  // std::invalid_argument: ValueError
}

py::array_t<bool> modal_mask(const soadyn::Model& m) {
  py::array_t<bool> mask(m.nv);
  for (int k = 0; k < m.nv; ++k) mask.mutable_at(k) = m.is_modal(k);
  return mask;
}

// Replaces the handle's model by a built-in scene; a scene refusing its
// arguments (std::invalid_argument) is a ValueError.
template <class Build>
void load_scene(ModelHandle& h, Build build) {
  soadyn::Model scene;
  try {
    scene = build();
  } catch (const soadyn::LoopError&) {
    throw;  // soadyn.LoopError, naming the loop
  } catch (const soadyn::ModelFileError&) {
    throw;  // soadyn.ModelFileError, naming the file and the item
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  const auto lock = h.lock_for_change();
  h.replace_model(std::move(scene));
}

// `set(dof, value)` (Model::set_armature, set_effort_limit) for each of
// `dofs`, all or nothing: tried on a copy first.
void set_for_dofs(ModelHandle& h, const std::vector<int>& dofs, double value,
                  void (soadyn::Model::*set)(int, double)) {
  const auto lock = h.lock_for_change();
  soadyn::Model trial = h.model;
  for (int d : dofs) (trial.*set)(d, value);
  for (int d : dofs) (h.model.*set)(d, value);
}

}  // namespace

void bind_model(py::module_& mod) {
  py::class_<JointSpec> joint(
      mod, "Joint",
      "A joint type; build one with the static constructors and give it to Model.add_body.\n\n"
      "Axes are 3-vectors in the joint frame, normalised when the body is added; a zero or non-finite axis is\n"
      "refused by Model.add_body with a ValueError naming the joint. Coordinates: rad for rotations, m for\n"
      "translations (a helical joint's pitch in m per rad). DOF names are the joint's name, or '<name>:<part>'\n"
      "for joints of several DOFs (':1', ':2' of a universal joint, ':angle', ':offset' of a cylindrical one).");
  def_joint_factories(joint, static_cast<JointModel*>(nullptr));
  joint
      .def_property_readonly("type", [](const JointSpec& j) { return std::string(soadyn::joint_type_name(j.joint)); },
                             "The joint type's name ('revolute', 'free', ...).")
      .def_property_readonly("nq", [](const JointSpec& j) { return soadyn::joint_nq(j.joint); }, "Its number of coordinates.")
      .def_property_readonly("nv", [](const JointSpec& j) { return soadyn::joint_nv(j.joint); }, "Its number of DOFs.")
      .def_readonly("name", &JointSpec::name, "Its name ('': the body's name).")
      .def("__repr__", [](const JointSpec& j) {
        return std::string("Joint.") + soadyn::joint_type_name(j.joint) + "(" + (j.name.empty() ? "" : "name='" + j.name + "'") + ")";
      });

  py::class_<ModelHandle>(mod, "_Model")
      .def(py::init<>())
      .def("_add_body",
           [](ModelHandle& h, const std::string& name, const std::string& parent, const JointSpec& joint,
              const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double mass, const Eigen::Vector3d& com,
              const Eigen::Matrix3d& inertia, bool accept_nonphysical_inertia) {
             soadyn::Transform<double> X;
             X.rotation = R;
             X.translation = p;
             const auto lock = h.lock_for_change();
             return h.model.add_body(name, parent, joint.joint, X, mass, com, inertia, joint.name,
                                     accept_nonphysical_inertia ? soadyn::InertiaPolicy::accept_nonphysical
                                                                : soadyn::InertiaPolicy::require_physical);
           },
           py::arg("name"), py::arg("parent"), py::arg("joint"), py::arg("R"), py::arg("p"), py::arg("mass"),
           py::arg("com"), py::arg("inertia"), py::arg("accept_nonphysical_inertia") = false)
      .def("_add_flexible_body",
           [](ModelHandle& h, const std::string& name, const std::string& parent, const JointSpec& joint,
              const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const soadyn::FlexibleBody& body) {
             soadyn::Transform<double> X;
             X.rotation = R;
             X.translation = p;
             const auto lock = h.lock_for_change();
             return h.model.add_flexible_body(name, parent, joint.joint, X, body, joint.name);
           })
      .def("_add_loop",
           [](ModelHandle& h, const std::string& name, const std::string& frame_a, const std::string& frame_b,
              const std::string& kind, const Eigen::Matrix3d& Ra, const Eigen::Vector3d& pa, const Eigen::Matrix3d& Rb,
              const Eigen::Vector3d& pb, double length, std::optional<Eigen::VectorXd> q) {
             soadyn::Transform<double> Xa, Xb;
             Xa.rotation = Ra;
             Xa.translation = pa;
             Xb.rotation = Rb;
             Xb.translation = pb;
             const soadyn::LoopKind k = soadyn::parse_loop_kind(kind, name);
             const auto lock = h.lock_for_change();
             if (q && q->size() != h.model.nq)
               throw py::value_error("loop '" + name + "': q has " + std::to_string(q->size()) + " entries, expected " +
                                     std::to_string(h.model.nq));
             return h.model.add_loop(name, frame_a, frame_b, k, Xa, Xb, length, q ? q->data() : nullptr);
           })
      .def_property_readonly("loop_names", [](const ModelHandle& h) {
             std::vector<std::string> names;
             for (const auto& l : h.model.loops) names.push_back(l.name);
             return names;
           }, "Names of the closed loops, in the order added.")
      .def_property_readonly("nloops", [](const ModelHandle& h) { return h.model.nloops(); }, "Number of closed loops.")
      .def_property_readonly("nloop_equations", [](const ModelHandle& h) { return h.model.nloop_equations; },
                             "Number of loop-closure equations (the rows of loop_jacobian).")
      .def_property_readonly(
          "loop_solver",
          [](const ModelHandle& h) {
            const soadyn::Model& m = h.model;
            return std::string(m.dynamics_path == soadyn::DynamicsPath::rigid_tree_frames && !m.loops_through_mass_matrix()
                                   ? "articulated"
                                   : "mass matrix");
          },
          "How constrained_dynamics solves the loops of this model: 'articulated' (the articulated-body "
          "response to unit multipliers, O(N) in the bodies) or 'mass matrix' (M by CRBA, factored with the "
          "tree's sparsity: rigid trees where that factor is cheap for their number of loop equations, and models with flexible bodies). A call with a body "
          "beyond its tree-frame reach takes the mass matrix in body frames.")
      .def("_set_prescribed_indices",
           [](ModelHandle& h, const std::vector<int>& dofs, bool flag) {
             const auto lock = h.lock_for_change();
             for (int d : dofs) refuse_modal(h.model, d, flag);
             for (int d : dofs) h.model.set_prescribed(d, flag);
           })
      .def("_set_armature",
           [](ModelHandle& h, const std::vector<int>& dofs, double value) {
             set_for_dofs(h, dofs, value, &soadyn::Model::set_armature);
           })
      .def("_set_effort_limit",
           [](ModelHandle& h, const std::vector<int>& dofs, double value) {
             set_for_dofs(h, dofs, value, &soadyn::Model::set_effort_limit);
           })
      .def_property_readonly("effort_limits",
                             [](const ModelHandle& h) {
                               return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(h.model.effort_limit.data(), h.model.nv));
                             },
                             "Float array (nv): each DOF's effort limit (largest actuator force or torque; inf: none,\n"
                             "the default). HIL runs take it as the DOF's command limit.")
      .def_property_readonly("armature",
                             [](const ModelHandle& h) {
                               return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(h.model.armature.data(), h.model.nv));
                             },
                             "Float array (nv): each DOF's armature (rotor inertia on the DOF; zero by default).")
      .def("_require_regular_modal_dofs",
           [](const ModelHandle& h, const std::vector<int>& dofs) {
             for (int d : dofs) refuse_modal(h.model, d, true);
           },
           "Raises ValueError naming the first of `dofs` that is a modal coordinate (always regular).")
      .def("_set_prescribed_mask",
           [](ModelHandle& h, const std::vector<bool>& mask) {
             const auto lock = h.lock_for_change();
             if (mask.size() != static_cast<std::size_t>(h.model.nv))
               throw py::value_error("prescribed mask has " + std::to_string(mask.size()) + " entries, expected " +
                                     std::to_string(h.model.nv));
             for (int d = 0; d < h.model.nv; ++d) refuse_modal(h.model, d, mask[static_cast<std::size_t>(d)]);
             for (int d = 0; d < h.model.nv; ++d) h.model.set_prescribed(d, mask[static_cast<std::size_t>(d)]);
           })
      .def("body_index", [](const ModelHandle& h, const std::string& n) { return h.model.body_index(n); },
           "Index of the named body, or -1.")
      .def("dof_index", [](const ModelHandle& h, const std::string& n) { return h.model.dof_index(n); },
           "Velocity index of the named DOF, or -1.")
      .def("_load_cassini", [](ModelHandle& h) { load_scene(h, [] { return soadyn::cassini_model<double>(); }); })
      .def("_to_json", [](const ModelHandle& h) { return soadyn::model_to_json(h.model); },
           "The model as model-file JSON text (soadyn/model/model_file.hpp).")
      .def("_load_json",
           [](ModelHandle& h, const std::string& text, const std::string& source) {
             load_scene(h, [&] { return soadyn::model_from_json(text, source); });
           },
           py::arg("text"), py::arg("source"), "Replaces this model by the one model-file JSON `text` holds.")
      .def_property(
          "_description", [](const ModelHandle& h) { return h.model.description; },
          [](ModelHandle& h, const std::string& text) {
            const auto lock = h.lock_for_change();
            h.model.description = text;
          },
          "The description (visuals, metadata) as JSON text: kept by model files, unused by the dynamics.")
      .def("_load_pendulum_chain", [](ModelHandle& h, int links, double length, double mass) {
        load_scene(h, [&] { return soadyn::pendulum_chain_model<double>(links, length, mass); });
      })
      .def("_load_four_bar", [](ModelHandle& h, const std::string& closure) {
        load_scene(h, [&] {
          return soadyn::four_bar_model<double>(soadyn::parse_loop_kind(closure, "coupler_rocker"));
        });
      })
      .def("_load_slider_crank", [](ModelHandle& h, const std::string& closure) {
        load_scene(h, [&] {
          return soadyn::slider_crank_model<double>(soadyn::parse_loop_kind(closure, "wrist_pin"));
        });
      })
      .def("_load_delta_robot",
           [](ModelHandle& h) { load_scene(h, [] { return soadyn::delta_robot_model<double>(); }); })
      .def("_copy_from", [](ModelHandle& h, const ModelHandle& other) {
        soadyn::Model copy = other.model;  // read under the GIL: no change can run (model_handle.hpp)
        const auto lock = h.lock_for_change();
        h.replace_model(std::move(copy));
      })
      .def_property_readonly("nq", [](const ModelHandle& h) { return h.model.nq; }, "Number of coordinates (len q).")
      .def_property_readonly("nv", [](const ModelHandle& h) { return h.model.nv; }, "Number of DOFs (len v).")
      .def_property_readonly("nbodies", [](const ModelHandle& h) { return h.model.nbodies(); },
                             "Number of bodies (welded ones merged into their parents are frames).")
      .def_property_readonly("body_names", [](const ModelHandle& h) { return h.model.body_names; },
                             "Body names in tree order (parent before child).")
      .def_property_readonly("joint_names", [](const ModelHandle& h) { return h.model.joint_names; },
                             "Each body's joint name, in body order.")
      .def_property_readonly("joint_types", [](const ModelHandle& h) {
        std::vector<std::string> t;
        for (const auto& j : h.model.joints) t.emplace_back(soadyn::joint_type_name(j));
        return t;
      }, "Each body's joint type ('revolute', 'free', ...), in body order.")
      .def_property_readonly("dof_names", [](const ModelHandle& h) { return h.model.dof_names; },
                             "DOF names in velocity order (entries of v, tau, u).")
      .def_property_readonly("coordinate_names", [](const ModelHandle& h) { return h.model.coordinate_names; },
                             "Coordinate names in q order (a quaternion's four entries named each).")
      .def_property_readonly("frame_names", [](const ModelHandle& h) {
        std::vector<std::string> names;
        for (const auto& f : h.model.frames) names.push_back(f.name);
        return names;
      }, "Names of the frames welded to bodies (fixed-joint links, flexible bodies' attachment nodes).")
      .def_property_readonly("parents", [](const ModelHandle& h) { return h.model.parent; },
                             "Each body's parent body index (-1: the world).")
      .def_property_readonly("q_index", [](const ModelHandle& h) { return h.model.q_index; },
                             "Each body's first coordinate's index in q.")
      .def_property_readonly("v_index", [](const ModelHandle& h) { return h.model.v_index; },
                             "Each body's first DOF's index in v.")
      .def_property_readonly(
          "constant_tree_inertia", [](const ModelHandle& h) { return as_bools(h.model.derived.constant_tree_inertia); },
          "Per body: whether the dynamics read its inertia formed once (constant in its free root's frame: "
          "welded to the root, or turning about an axis of mass symmetry on it).")
      .def_property_readonly(
          "placement_axes",
          [](const ModelHandle& h) {
            std::vector<const char*> shapes;
            for (const soadyn::PlacementAxes<double>& axes : h.model.derived.placement_axes)
              shapes.push_back(axes.kind == soadyn::PlacementAxes<double>::Kind::identity             ? "identity"
                               : axes.kind == soadyn::PlacementAxes<double>::Kind::signed_permutation ? "axis_permutation"
                                                                                                : "general");
            return shapes;
          },
          "Per body: the shape of its placement's rotation as the sweeps apply it: 'identity', "
          "'axis_permutation' (quarter turns: each axis onto a coordinate axis, up to sign) or 'general'. "
          "Entries within machine epsilon of the first two count as them.")
      .def_property_readonly(
          "appendage_in_root_frame", [](const ModelHandle& h) { return as_bools(h.model.derived.appendage_in_root_frame); },
          "Per body: whether it is a flexible appendage welded to its root, whose modal integrals the dynamics "
          "read formed once in the root's frame.")
      .def_property_readonly(
          "constant_leaf_hinge", [](const ModelHandle& h) { return as_bools(h.model.derived.constant_leaf_hinge); },
          "Per body: whether it is a leaf turning about an axis of mass symmetry on a body welded to its root "
          "(a reaction wheel), whose hinge terms D, G and P+ the dynamics read formed once (when its DOF is "
          "regular and has no armature).")
      .def_property_readonly(
          "leaf_terms_presummed",
          [](const ModelHandle& h) {
            std::vector<std::pair<bool, bool>> out;
            for (const std::uint8_t bits : h.model.derived.leaf_plus_presummed) out.emplace_back(bits & 1, bits & 2);
            return out;
          },
          "Per body: (under the prescribed flags, with every DOF regular), whether it is a leaf whose constant "
          "P+ (or, prescribed, its constant P) its parent's articulated inertia starts with, summed once.")
      .def_property_readonly("masses", [](const ModelHandle& h) { return h.model.mass; },
                             "Each body's mass in kg, welded parts included.")
      .def_property_readonly("n_modes", [](const ModelHandle& h) { return h.model.n_modes; },
                             "Modal coordinates per body (0 for a rigid body).")
      .def_property_readonly("modal", [](const ModelHandle& h) { return modal_mask(h.model); },
                             "Bool array (nv): True where the DOF is a modal coordinate (always regular).")
      .def("flexible_body", [](const ModelHandle& h, const std::string& name) {
             const int b = h.model.body_index(name);
             if (b < 0 || !h.model.is_flexible(b)) throw py::value_error("'" + name + "' is not a flexible body");
             return h.model.flexible_body(b);
           }, py::arg("name"), "The FlexibleBody of the named body.")
      .def_property_readonly("prescribed", [](const ModelHandle& h) { return prescribed_mask(h.model); },
                             "Bool array (nv): True where the DOF is prescribed.")
      .def_property(
          "gravity", [](const ModelHandle& h) { return Eigen::Vector3d(h.model.gravity); },
          [](ModelHandle& h, py::handle g) {
            const Array a = checked_vector(g, "gravity", {"x", "y", "z"});
            const auto lock = h.lock_for_change();
            h.model.gravity = Eigen::Map<const Eigen::Vector3d>(a.data());
          },
          "Gravity in the world frame (default (0, 0, -9.81)).");

  py::register_exception<soadyn::NonphysicalInertiaError>(mod, "NonphysicalInertiaError", PyExc_ValueError);
  py::register_exception<soadyn::LoopError>(mod, "LoopError", PyExc_ValueError);
  py::register_exception<soadyn::ModelFileError>(mod, "ModelFileError", PyExc_ValueError);

  // Closed states of the loop scenes (std::invalid_argument: ValueError).
  const auto state = [](const soadyn::SceneState<double>& s) { return py::make_tuple(s.q, s.v); };
  mod.def("_four_bar_state", [state](double angle, double rate) { return state(soadyn::four_bar_state(angle, rate)); },
          py::arg("crank_angle"), py::arg("crank_rate"));
  mod.def("_slider_crank_state",
          [state](double angle, double rate) { return state(soadyn::slider_crank_state(angle, rate)); },
          py::arg("crank_angle"), py::arg("crank_rate"));
  mod.def("_delta_robot_state", [state](const Eigen::Vector3d& position, const Eigen::Vector3d& velocity) {
    return state(soadyn::delta_robot_state<double>(position, velocity));
  }, py::arg("position"), py::arg("velocity"));
}

}  // namespace soadyn_py
