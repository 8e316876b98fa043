// The dynamics calls: check arguments, release the GIL, run the C++
// algorithm on the model's preallocated Data, copy the outputs into fresh
// numpy arrays.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <limits>

#include "arrays.hpp"
#include "docstrings.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "model_handle.hpp"
#include "soadyn/sweeps/appendage_update.hpp"
#include "soadyn/sweeps/joint_angles.hpp"
#include "soadyn/soadyn.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;

py::array_t<double> vector_out(py::ssize_t n) { return fresh_array(n); }

py::array_t<double> wrench_out(const ModelHandle& h) { return fresh_array(h.model.nbodies(), 6); }

// The (nbodies, 6) joint-wrench array of a call that returns it on request:
// `data` is null when it was not asked for.
struct OptionalWrenches {
  py::object array;
  double* data = nullptr;
  OptionalWrenches(const ModelHandle& h, bool wanted) {
    if (!wanted) return;
    auto a = wrench_out(h);
    data = a.mutable_data();
    array = std::move(a);
  }
};

std::vector<std::string> loop_names(const soadyn::Model& m) {
  std::vector<std::string> names;
  for (const auto& l : m.loops) names.push_back(l.name);
  return names;
}

}  // namespace

void bind_algorithms(py::module_& mod) {
  py::register_exception<DynamicsError>(mod, "DynamicsError", PyExc_ArithmeticError);
  mod.attr("QUATERNION_TOLERANCE") = kQuaternionTolerance;
  mod.def("_joint_angle_kernel", &soadyn::joint_angle_kernel,
          "The kernel of the joint angles' sines and cosines on this processor (sweeps/joint_angles.hpp): "
          "results agree bit for bit only between processes that use the same one.");
  mod.def("_mass_matrix_kernel", &soadyn::mass_matrix_kernel,
          "The kernel of rigid models' mass matrix on this processor (algorithms/crba.hpp): 'AVX2 FMA' or "
          "'baseline'; results agree bit for bit only between processes that use the same one.");
  mod.def("_appendage_kernel", &soadyn::appendage_kernel,
          "The kernel of flexible appendages' update on this processor (sweeps/appendage_update.hpp): 'AVX2 FMA' "
          "or 'baseline'; results agree bit for bit only between processes that use the same one.");

  mod.def("forward_dynamics",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle tau, py::handle f_ext) {
        const StateArgs a(h, q, v, tau, "tau", f_ext);
        auto out = vector_out(h.model.nv);
        raise_on(forward_dynamics_into(h, a.buffers(), out.mutable_data()), h.model, "forward_dynamics");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("tau"), py::arg("f_ext") = py::none(),
      "Accelerations qdd = M^-1 (tau - h + J' f_ext) by the articulated-body algorithm (every DOF regular,\n"
      "whatever the model's flags). f_ext: (nbodies, 6) body-frame wrenches [torque; force] about each body\n"
      "origin. Returns a fresh (nv,) array." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("inverse_dynamics",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle qdd, py::handle f_ext) {
        const StateArgs a(h, q, v, qdd, "qdd", f_ext);
        auto out = vector_out(h.model.nv);
        raise_on(inverse_dynamics_into(h, a.buffers(), out.mutable_data(), nullptr), h.model, "inverse_dynamics");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("qdd"), py::arg("f_ext") = py::none(),
      "Generalized forces tau = M qdd + h - J' f_ext (recursive Newton-Euler). Returns a fresh (nv,) array."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("joint_wrenches",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle qdd, py::handle f_ext, py::handle loop_wrenches) {
        const StateArgs a(h, q, v, qdd, "qdd", f_ext);
        auto out = wrench_out(h);
        if (h.model.nloops() == 0 && loop_wrenches.is_none()) {
          inverse_dynamics_into(h, a.buffers(), nullptr, out.mutable_data());  // its torques are not returned
        } else {
          if (loop_wrenches.is_none())
            throw py::value_error("joint_wrenches: the model has closed loops: pass loop_wrenches= (the (nloops, 6) "
                                  "loop wrenches constrained_dynamics returns), or call "
                                  "constrained_dynamics(..., joint_wrenches=True)");
          const Array w = checked_matrix(loop_wrenches, "loop_wrenches", 6, loop_names(h.model));
          soadyn::Status status;
          run_locked(h, a.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
            status = soadyn::loop_joint_wrenches<double>(m, d, Map(a.q.data(), m.nq), Map(a.v.data(), m.nv),
                                                         Map(a.x.data(), m.nv), w.data(), a.f_ext);
            copy_wrenches(d, out.mutable_data());
          });
          raise_on(status, h.model, "joint_wrenches");
        }
        refuse_non_finite("joint_wrenches", "joint wrench", out.data(), h.model.body_names.size(), 6, h.model.body_names);
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("qdd"), py::arg("f_ext") = py::none(),
      py::arg("loop_wrenches") = py::none(),
      "Joint reaction wrenches (nbodies, 6): the spatial force [torque; force] the parent exerts on each body\n"
      "through its hinge, in the body frame about the body origin, at the given accelerations. On a model with\n"
      "closed loops the tree is also loaded by the loop forces, so loop_wrenches (nloops, 6) is required: the\n"
      "wrenches constrained_dynamics returns (each acts on frame_a's body about frame_a's origin, its opposite\n"
      "on frame_b's body with the force at frame_b's origin, frame_a's for a prismatic loop)."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("hybrid_dynamics",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, py::handle f_ext, bool wrenches) -> py::object {
        const StateArgs a(h, q, v, u, "u", f_ext);
        auto qdd = vector_out(h.model.nv), tau = vector_out(h.model.nv);
        const OptionalWrenches w(h, wrenches);
        raise_on(hybrid_dynamics_into(h, a.buffers(), qdd.mutable_data(), tau.mutable_data(), w.data), h.model,
                 "hybrid_dynamics");
        if (w.data)
          refuse_non_finite("hybrid_dynamics", "joint wrench", w.data, h.model.body_names.size(), 6, h.model.body_names);
        if (wrenches) return py::make_tuple(qdd, tau, w.array);
        return py::make_tuple(qdd, tau);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("f_ext") = py::none(),
      py::arg("joint_wrenches") = false,
      "Hybrid dynamics (Jain & Rodriguez 1993, Eqs. 14, 28, 29): u holds the torque of each regular DOF and the acceleration of\n"
      "each prescribed DOF (model.prescribed). Returns fresh arrays (qdd, tau) with every DOF's acceleration\n"
      "and generalized force, each (nv,), plus the (nbodies, 6) joint wrenches when joint_wrenches=True."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("constrained_dynamics",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle u, py::handle f_ext, bool joint_wrenches) -> py::object {
        const StateArgs a(h, q, v, u, "u", f_ext);
        auto qdd = vector_out(h.model.nv), tau = vector_out(h.model.nv);
        auto wrenches = fresh_array(h.model.nloops(), 6);
        const OptionalWrenches hinge(h, joint_wrenches);
        double* ho = hinge.data;
        raise_on(constrained_dynamics_into(h, a.buffers(), qdd.mutable_data(), tau.mutable_data(),
                                           wrenches.mutable_data(), ho),
                 h.model, "constrained_dynamics");
        if (ho) refuse_non_finite("constrained_dynamics", "joint wrench", ho, h.model.body_names.size(), 6,
                                  h.model.body_names);
        if (joint_wrenches) return py::make_tuple(qdd, tau, wrenches, hinge.array);
        return py::make_tuple(qdd, tau, wrenches);
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("u"), py::arg("f_ext") = py::none(),
      py::arg("joint_wrenches") = false,
      "Hybrid dynamics with the model's closed loops: u as in hybrid_dynamics. Returns fresh arrays (qdd, tau,\n"
      "loop_wrenches): every DOF's acceleration and generalized force, and per loop (nloops, 6) the wrench\n"
      "[torque; force] that frame_b's side exerts on frame_a's side, world-aligned axes, about frame_a's origin;\n"
      "with joint_wrenches=True also the (nbodies, 6) joint wrenches of the tree loaded by f_ext and the loop\n"
      "forces (as joint_wrenches). Redundant loop equations give minimum-norm multipliers. With more prescribed\n"
      "DOFs than the mechanism's mobility (redundant actuation) tau holds the minimum-norm actuator forces: the\n"
      "smallest ||tau_p|| over every set of loop forces consistent with the motion. Closure accelerations that\n"
      "cannot be met (inconsistent prescribed accelerations, a driven mechanism at a dead centre) raise\n"
      "DynamicsError naming the loop. Equals hybrid_dynamics without loops." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("loop_residual",
      [](ModelHandle& h, py::handle q, py::handle v) -> py::object {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        py::object keep_v;
        const double* vp = nullptr;
        if (!v.is_none()) {
          Array va = v_arg(h, v, "v");
          vp = va.data();
          keep_v = std::move(va);
        }
        const py::ssize_t m_rows = h.model.nloop_equations;
        auto position = vector_out(m_rows), velocity = vector_out(m_rows);
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::loop_residual<double>(m, d, Map(qa.data(), m.nq), vp);
          const std::vector<std::string> rows = loop_equation_names(m);
          refuse_non_finite_rows("loop_residual", "residual", d.loops.residual, rows);
          if (vp) refuse_non_finite_rows("loop_residual", "velocity residual", d.loops.velocity_residual, rows);
          Eigen::Map<Eigen::VectorXd>(position.mutable_data(), m_rows) = d.loops.residual;
          Eigen::Map<Eigen::VectorXd>(velocity.mutable_data(), m_rows) = d.loops.velocity_residual;
        });
        if (vp) return py::make_tuple(position, velocity);
        return std::move(position);
      },
      py::arg("model"), py::arg("q"), py::arg("v") = py::none(),
      "Loop-closure residual Psi(q) (nloop_equations,), and with v the tuple (Psi(q), C(q) v): per loop, the\n"
      "cut joint's constrained relative displacements (m, rad) and velocities (m/s, rad/s)."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("loop_jacobian",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        auto out = fresh_array(h.model.nloop_equations, h.model.nv);
        double* o = out.mutable_data();
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::loop_residual<double>(m, d, Map(qa.data(), m.nq), nullptr);
          refuse_non_finite_rows("loop_jacobian", "row", d.loops.jacobian, loop_equation_names(m));
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(o, m.nloop_equations, m.nv) =
              d.loops.jacobian;
        });
        return out;
      },
      py::arg("model"), py::arg("q"),
      "Loop constraint Jacobian C(q), (nloop_equations, nv): C v is the cut joints' relative velocity."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("loop_rank",
      [](ModelHandle& h, py::handle q) {
        return at_configuration(h, q, [](const soadyn::Model& m, soadyn::Data& d, const Map& qm) {
          return soadyn::loop_rank<double>(m, d, qm);
        });
      },
      py::arg("model"), py::arg("q"),
      "Rank of the loop constraint Jacobian C(q) (column-pivoted QR; pivots below 1e3 machine epsilons times\n"
      "the largest count as zero)." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("mass_matrix",
      [](ModelHandle& h, py::handle q) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        auto out = fresh_array(h.model.nv, h.model.nv);
        double* o = out.mutable_data();
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          status = soadyn::mass_matrix<double>(m, d, Map(qa.data(), m.nq));
          Eigen::Map<Eigen::MatrixXd>(o, m.nv, m.nv) = d.mass_matrix;  // symmetric: layout does not matter
        });
        raise_on(status, h.model, "mass_matrix");
        return out;
      },
      py::arg("model"), py::arg("q"), "Joint-space mass matrix M(q), (nv, nv) (composite-rigid-body algorithm), in kg,\n"
      "kg m and kg m^2 by the DOFs' kinds." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("bias_forces",
      [](ModelHandle& h, py::handle q, py::handle v) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
        auto out = vector_out(h.model.nv);
        double* o = out.mutable_data();
        soadyn::Status status;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          status = soadyn::bias_forces<double>(m, d, Map(qa.data(), m.nq), Map(va.data(), m.nv));
          Eigen::Map<Eigen::VectorXd>(o, m.nv) = d.tau;
        });
        raise_on(status, h.model, "bias_forces");
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), "h(q, v), (nv,): Coriolis, centrifugal and gravity generalized forces (N, N m)."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("kinetic_energy",
      [](ModelHandle& h, py::handle q, py::handle v) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
        double e = 0;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          e = soadyn::kinetic_energy<double>(m, d, Map(qa.data(), m.nq), Map(va.data(), m.nv));
          if (!std::isfinite(e)) raise_non_finite_total("kinetic_energy", m, d, true);
        });
        return e;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), "Kinetic energy 1/2 v' M v, in J." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("potential_energy",
      [](ModelHandle& h, py::handle q) {
        return at_configuration(h, q, [](const soadyn::Model& m, soadyn::Data& d, const Map& qm) {
          const double e = soadyn::potential_energy<double>(m, d, qm);
          if (!std::isfinite(e)) {
            raise_non_finite_force_element("potential_energy", m, d, qm, nullptr);
            raise_non_finite_total("potential_energy", m, d, false);
          }
          return e;
        });
      },
      py::arg("model"), py::arg("q"), "Potential energy in J: gravity's, -sum m g.c (zero at the world\n"
      "origin), plus the flexible bodies' strain energy and the springs' (force_element_potential)." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("momentum",
      [](ModelHandle& h, py::handle q, py::handle v) {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
        Eigen::Matrix<double, 6, 1> p;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          p = soadyn::momentum<double>(m, d, Map(qa.data(), m.nq), Map(va.data(), m.nv));
          if (!p.allFinite()) raise_non_finite_total("momentum", m, d, true);
        });
        return Eigen::VectorXd(p);
      },
      py::arg("model"), py::arg("q"), py::arg("v"),
      "Spatial momentum (6,) [angular about the world origin, N m s; linear, N s] in world axes."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("center_of_mass",
      [](ModelHandle& h, py::handle q) {
        return at_configuration(h, q, [](const soadyn::Model& m, soadyn::Data& d, const Map& qm) {
          const Eigen::Vector3d c = soadyn::center_of_mass<double>(m, d, qm);
          if (!c.allFinite()) raise_non_finite_total("center_of_mass", m, d, false);
          return c;
        });
      },
      py::arg("model"), py::arg("q"), "Centre of mass (3,) of the whole tree in the world frame, in m."
      SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("forward_kinematics",
      [](ModelHandle& h, py::handle q, py::handle v) -> py::object {
        const std::uint64_t version = h.model.version;
        const Array qa = q_arg(h, q);
        const bool with_v = !v.is_none();
        const Array va = with_v ? v_arg(h, v, "v") : Array();
        const py::ssize_t n = h.model.nbodies();
        py::array_t<double> poses({n, py::ssize_t(4), py::ssize_t(4)});
        py::array_t<double> vel = with_v ? py::array_t<double>({n, py::ssize_t(6)}) : py::array_t<double>();
        double *po = poses.mutable_data(), *vo = with_v ? vel.mutable_data() : nullptr;
        run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) {
          soadyn::forward_kinematics<double>(m, d, qa.data(), with_v ? va.data() : nullptr);
          for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
            Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> T(po + 16 * i);
            T.setIdentity();
            T.topLeftCorner<3, 3>() = d.pose_in_world[i].rotation;
            T.topRightCorner<3, 1>() = d.pose_in_world[i].translation;
            if (vo) Eigen::Map<soadyn::Vec6<double>>(vo + 6 * i) = d.body_velocity[i];
          }
        });
        refuse_non_finite("forward_kinematics", "pose", po, static_cast<std::size_t>(n), 16, h.model.body_names);
        if (vo) refuse_non_finite("forward_kinematics", "velocity", vo, static_cast<std::size_t>(n), 6, h.model.body_names);
        if (with_v) return py::make_tuple(poses, vel);
        return py::make_tuple(poses, py::none());
      },
      py::arg("model"), py::arg("q"), py::arg("v") = py::none(),
      "(poses, velocities): (nbodies, 4, 4) homogeneous body poses in the world and, with v, (nbodies, 6)\n"
      "body-frame spatial velocities [angular rad/s; linear m/s of the body origin]." SOADYN_DOC_STATE
      SOADYN_DOC_RAISES);

  mod.def("integrate",
      [](ModelHandle& h, py::handle q, py::handle v, py::handle dt_arg) {
        const std::uint64_t version = h.model.version;
        const double dt = checked_real(dt_arg, "dt");
        const Array qa = q_arg(h, q), va = v_arg(h, v, "v");
        if (!std::isfinite(dt)) throw py::value_error("dt is not finite");
        refuse_changed_model(h, version);  // converting v may have run Python code; from here on the GIL is held
        Eigen::VectorXd out(h.model.nq);
        soadyn::integrate<double>(h.model, Map(qa.data(), h.model.nq), Map(va.data(), h.model.nv), dt, out);
        refuse_non_finite("integrate", "coordinate", out.data(), static_cast<std::size_t>(h.model.nq), 1,
                          h.model.coordinate_names);
        return out;
      },
      py::arg("model"), py::arg("q"), py::arg("v"), py::arg("dt"),
      "q (+) v dt, (nq,): each joint on its manifold (quaternions by the exponential map; free joints on\n"
      "SE(3)); dt in s." SOADYN_DOC_STATE SOADYN_DOC_RAISES);

  mod.def("neutral_configuration",
      [](const ModelHandle& h) {
        Eigen::VectorXd q(h.model.nq);
        soadyn::neutral_configuration<double>(h.model, q);
        return q;
      },
      py::arg("model"), "The neutral configuration (nq,): zero coordinates with identity quaternions.");

  mod.def("random_configuration",
      [](const ModelHandle& h, py::handle seed) {
        Eigen::VectorXd q(h.model.nq);
        soadyn::random_configuration<double>(
            h.model, static_cast<std::uint64_t>(checked_integer(seed, "seed", 0, std::numeric_limits<long long>::max())), q);
        return q;
      },
      py::arg("model"), py::arg("seed") = 0,
      "A random configuration (nq,) from the integer seed: angles in [-pi, pi] rad, offsets in [-1, 1] m,\n"
      "uniform unit quaternions.");
}

}  // namespace soadyn_py
