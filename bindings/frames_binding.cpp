// Frames and Jacobians (soadyn/algorithms/frames.hpp): thin calls behind
// soadyn.frame_pose, frame_velocity, frame_acceleration, frame_jacobian,
// frame_jacobian_time_variation and center_of_mass_jacobian.
#include <pybind11/eigen.h>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/algorithms/frames.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using soadyn::FrameLocation;
using soadyn::Reference;

// A body name, a frame name or a body index.
FrameLocation<double> frame_arg(const ModelHandle& h, py::handle frame) {
  if (py::isinstance<py::str>(frame)) return soadyn::locate_frame(h.model, frame.cast<std::string>());
  if (PyIndex_Check(frame.ptr()) && !py::isinstance<py::bool_>(frame) && !py::isinstance<py::array>(frame)) {
    const auto index = py::cast<py::ssize_t>(py::reinterpret_steal<py::object>(PyNumber_Index(frame.ptr())));
    if (index < 0 || index >= h.model.nbodies())
      throw py::value_error("frame index " + std::to_string(index) + " is not a body index (the model has " +
                            std::to_string(h.model.nbodies()) + " bodies)");
    return soadyn::locate_frame(h.model, static_cast<int>(index));
  }
  throw py::type_error("frame must be a body or frame name (str) or a body index (int)");
}

Reference reference_arg(py::handle reference_object) {
  const std::string reference = checked_text(reference_object, "reference");
  if (reference == "world") return Reference::world;
  if (reference == "local") return Reference::local;
  if (reference == "local_world_aligned") return Reference::local_world_aligned;
  throw py::value_error("unknown reference '" + reference + "' (expected 'world', 'local' or 'local_world_aligned')");
}

// The checked arguments of a frame call, with the model version they were
// checked against: q, v and qdd (None when the call takes none), the frame
// and the reference (frame_pose takes none: any).
struct FrameCall {
  FrameCall(const ModelHandle& h, py::handle q_in, py::handle frame_in, py::handle reference_in,
            py::handle v_in = py::none(), py::handle qdd_in = py::none())
      : version(h.model.version),
        q(q_arg(h, q_in)),
        v(v_in.is_none() ? Array() : v_arg(h, v_in, "v")),
        qdd(qdd_in.is_none() ? Array() : v_arg(h, qdd_in, "qdd")),
        frame(frame_arg(h, frame_in)),
        reference(reference_arg(reference_in)) {}
  std::uint64_t version;
  Array q, v, qdd;
  FrameLocation<double> frame;
  Reference reference;
};

// A column-major rows x nv result as a fresh C-ordered array, its columns
// checked finite (named by DOF).
py::array_t<double> checked_columns(const char* what, const ModelHandle& h, const Eigen::MatrixXd& J) {
  refuse_non_finite(what, "column", J.data(), static_cast<std::size_t>(J.cols()), static_cast<std::size_t>(J.rows()),
                    h.model.dof_names);
  auto out = fresh_array(J.rows(), J.cols());
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(), J.rows(),
                                                                                     J.cols()) = J;
  return out;
}

Eigen::VectorXd checked_vector6(const char* what, const soadyn::Vec6<double>& x) {
  if (!x.allFinite()) throw DynamicsError(std::string(what) + ": the result is not finite");
  return x;
}

// Appended to the docstrings of the calls taking a reference.
#define SOADYN_FRAME_REFERENCES                                                                                  \
    "reference: 'world' (world axes, about the world origin), 'local' (frame axes, about the frame origin) or\n" \
    "'local_world_aligned' (world axes, about the frame origin). frame: a body name, a frame name (welded links\n" \
    "included) or a body index; an unknown frame or reference raises ValueError naming it. Angular parts in\n"    \
    "rad/s (rad/s^2), linear parts in m/s (m/s^2)." SOADYN_DOC_STATE SOADYN_DOC_RAISES

}  // namespace

void bind_frames(py::module_& mod) {
  mod.def("frame_pose",
      [](ModelHandle& h, py::handle q, py::handle frame) {
        const FrameCall c(h, q, frame, py::str("world"));
        Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
        run_locked(h, c.version, [&](const soadyn::Model& m, soadyn::Data& d) {
          const soadyn::Transform<double> X = soadyn::frame_pose<double>(m, d, Map(c.q.data(), m.nq), c.frame);
          T.topLeftCorner<3, 3>() = X.rotation;
          T.topRightCorner<3, 1>() = X.translation;
        });
        if (!T.allFinite()) throw DynamicsError("frame_pose: the pose is not finite");
        return T;
      },
      py::arg("model"), py::arg("q"), py::arg("frame"),
      "4x4 homogeneous pose of the frame in the world at q (rotation, translation in m). frame: a body name, a\n"
      "frame name (welded links included) or a body index; an unknown frame raises ValueError naming it."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("frame_velocity",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle frame, py::handle reference) {
        const FrameCall c(h, q, frame, reference, v);
        soadyn::Vec6<double> V;
        run_locked(h, c.version, [&](const soadyn::Model& m, soadyn::Data& d) {
          V = soadyn::frame_velocity<double>(m, d, Map(c.q.data(), m.nq), Map(c.v.data(), m.nv), c.frame, c.reference);
        });
        return checked_vector6("frame_velocity", V);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("frame"), py::arg("reference") = "local",
      "Spatial velocity [angular; linear] of the frame.\n" SOADYN_FRAME_REFERENCES);

  mod.def("frame_acceleration",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle qdd, py::handle frame, py::handle reference,
         py::handle classical_arg) {
        const bool classical = checked_flag(classical_arg, "classical");
        const FrameCall c(h, q, frame, reference, v, qdd);
        soadyn::Vec6<double> A;
        run_locked(h, c.version, [&](const soadyn::Model& m, soadyn::Data& d) {
          A = soadyn::frame_acceleration<double>(m, d, Map(c.q.data(), m.nq), Map(c.v.data(), m.nv),
                                                 Map(c.qdd.data(), m.nv), c.frame, c.reference, classical);
        });
        return checked_vector6("frame_acceleration", A);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("qdd"), py::arg("frame"), py::arg("reference") = "local",
      py::arg("classical") = false,
      "Spatial acceleration [angular; linear] of the frame, velocity products included, gravity\n"
      "not. classical=True: linear rows w x v + (spatial linear), the classical acceleration.\n" SOADYN_FRAME_REFERENCES);

  mod.def("frame_jacobian",
      [](ModelHandle& h, py::handle q, py::handle frame, py::handle reference) {
        const FrameCall c(h, q, frame, reference);
        Eigen::MatrixXd J(6, h.model.nv);
        run_locked(h, c.version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::frame_jacobian<double>(m, d, Map(c.q.data(), m.nq), c.frame, c.reference, J);
        });
        return checked_columns("frame_jacobian", h, J);
      },
      py::arg("model"), py::arg("q"), py::arg("frame"), py::arg("reference") = "local",
      "Frame Jacobian (6 x nv, rows [angular; linear]): J v is frame_velocity.\n" SOADYN_FRAME_REFERENCES);

  mod.def("frame_jacobian_time_variation",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle frame, py::handle reference) {
        const FrameCall c(h, q, frame, reference, v);
        Eigen::MatrixXd dJ(6, h.model.nv);
        run_locked(h, c.version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::frame_jacobian_time_variation<double>(m, d, Map(c.q.data(), m.nq), Map(c.v.data(), m.nv), c.frame,
                                                        c.reference, dJ);
        });
        return checked_columns("frame_jacobian_time_variation", h, dJ);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("frame"), py::arg("reference") = "local",
      "dJ/dt (6 x nv) of frame_jacobian along v: J qdd + dJ/dt v is frame_acceleration (world,\n"
      "local), or its classical form (local_world_aligned).\n" SOADYN_FRAME_REFERENCES);

  mod.def("center_of_mass_jacobian",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        if (h.model.has_flexible_bodies())
          throw py::value_error("center_of_mass_jacobian: models with flexible bodies are not supported");
        Eigen::MatrixXd J(3, h.model.nv);
        bool ok = false;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::SubtreeMassWorkspace<double> workspace(m);
          ok = soadyn::center_of_mass_jacobian<double>(m, d, Map(qa.data(), m.nq), workspace, J);
        });
        if (!ok) throw py::value_error("center_of_mass_jacobian: the model has no mass");
        return checked_columns("center_of_mass_jacobian", h, J);
      },
      py::arg("model"), py::arg("q"),
      "Jacobian (3 x nv) of the centre of mass in the world frame: J v is its velocity (m/s)."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);
}

}  // namespace soadyn_py
