// Simulator and motion sources. DOF names are resolved in python/soadyn/simulator.py.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "model_handle.hpp"
#include "soadyn/scenes.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn_py {

using Sim = soadyn::Simulator;

// A motion source as a Python object (a struct, so pybind11 does not turn the
// variant into its alternatives).
struct Source {
  soadyn::MotionSource<double> source;
};

namespace {

soadyn::Integrator integrator_from(const std::string& name) {
  if (name == "euler" || name == "semi-implicit-euler") return soadyn::Integrator::semi_implicit_euler;
  if (name == "rk4") return soadyn::Integrator::rk4;
  if (name == "dopri5") return soadyn::Integrator::dopri5;
  throw py::value_error("unknown integrator '" + name + "' (choose 'euler', 'rk4' or 'dopri5')");
}

const char* integrator_name(soadyn::Integrator i) {
  switch (i) {
    case soadyn::Integrator::semi_implicit_euler: return "euler";
    case soadyn::Integrator::rk4: return "rk4";
    case soadyn::Integrator::dopri5: return "dopri5";
  }
  return "?";
}

void raise_on(const soadyn::Status& s, const Sim& sim) {
  if (s.ok()) return;
  std::string where = s.index >= 0 && s.index < sim.model().nv
                          ? " (DOF '" + sim.model().dof_names[static_cast<std::size_t>(s.index)] + "')"
                          : "";
  throw py::value_error(std::string(soadyn::status_message(s.code)) + where + " at t = " + std::to_string(sim.time()));
}

double finite(double x, const char* what) {
  if (!std::isfinite(x)) throw py::value_error(std::string(what) + " is not finite");
  return x;
}

}  // namespace

void bind_simulator(py::module_& mod) {
  py::class_<Source>(mod, "MotionSource", "Position, velocity and acceleration of one DOF as functions of time.")
      .def_static("constant_acceleration", [](double a, double v0, double q0, double t0) {
            return Source{soadyn::ConstantAcceleration<double>{finite(t0, "t0"), finite(q0, "q0"), finite(v0, "v0"), finite(a, "a")}}; },
          py::arg("acceleration"), py::arg("v0") = 0.0, py::arg("q0") = 0.0, py::arg("t0") = 0.0)
      .def_static("constant_velocity", [](double v, double q0, double t0) {
            return Source{soadyn::ConstantAcceleration<double>{finite(t0, "t0"), finite(q0, "q0"), finite(v, "velocity"), 0.0}}; },
          py::arg("velocity"), py::arg("q0") = 0.0, py::arg("t0") = 0.0)
      .def_static("polynomial", [](const std::vector<double>& c, double t0) {
            if (c.empty() || c.size() > soadyn::Polynomial<double>::max_degree + 1)
              throw py::value_error("polynomial needs 1 to 8 coefficients (constant term first)");
            soadyn::Polynomial<double> p;
            p.t0 = finite(t0, "t0");
            p.degree = static_cast<int>(c.size()) - 1;
            for (std::size_t k = 0; k < c.size(); ++k) p.c[k] = finite(c[k], "coefficient");
            return Source{p}; },
          py::arg("coefficients"), py::arg("t0") = 0.0, "q(t) = sum c_k (t - t0)^k, constant term first.")
      .def_static("cycloidal", [](double q0, double q1, double t0, double duration) {
            if (!(duration > 0)) throw py::value_error("cycloidal duration must be positive");
            return Source{soadyn::Cycloidal<double>{finite(t0, "t0"), duration, finite(q0, "q0"), finite(q1, "q1")}}; },
          py::arg("q0"), py::arg("q1"), py::arg("t0"), py::arg("duration"),
          "Rest-to-rest cycloidal motion from q0 to q1 (seed 001 Eq. 34).")
      .def_static("spline", [](const std::vector<double>& t, const std::vector<double>& q) {
            for (double x : t) finite(x, "spline time");
            for (double x : q) finite(x, "spline value");
            try {
              return Source{soadyn::CubicSpline<double>(t, q)};
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            } },
          py::arg("times"), py::arg("values"), "Natural cubic spline through the table (held outside it).")
      .def_static("function", [](const std::function<std::tuple<double, double, double>(double)>& f) {
            return Source{soadyn::CallbackSource<double>{[f](double t) {
              const auto r = f(t);
              return soadyn::MotionSample<double>{std::get<0>(r), std::get<1>(r), std::get<2>(r)};
            }}}; },
          py::arg("fn"), "fn(t) -> (q, v, a): a Python callable (not real-time).")
      .def("sample", [](const Source& s, double t) {
            const auto m = soadyn::sample_source(s.source, t);
            return py::make_tuple(m.position, m.velocity, m.acceleration); },
          py::arg("t"), "(q, v, a) at time t.");

  py::class_<Sim>(mod, "_Simulator")
      .def(py::init([](ModelHandle& h, double dt, const std::string& integrator, int capacity) {
             std::lock_guard<std::mutex> lock(h.mutex);
             try {
               return std::make_unique<Sim>(h.model, dt, integrator_from(integrator), capacity);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
           }),
           py::arg("model"), py::arg("dt"), py::arg("integrator") = "rk4", py::arg("event_capacity") = 64)
      .def("_set_state", [](Sim& s, py::handle q, py::handle v, double t) {
             const auto& m = s.model();
             const Array qa = checked_vector(q, "q", m.coordinate_names), va = checked_vector(v, "v", m.dof_names);
             s.set_state(Eigen::Map<const Eigen::VectorXd>(qa.data(), m.nq), Eigen::Map<const Eigen::VectorXd>(va.data(), m.nv),
                         finite(t, "t"));
           })
      .def("_set_input", [](Sim& s, int dof, double tau) { s.set_input(dof, finite(tau, "input")); })
      .def("_prescribe", [](Sim& s, int dof, const Source& src) { s.prescribe(dof, src.source); })
      .def("_schedule", [](Sim& s, double t, const std::string& kind, int dof) {
             if (kind == "lock") return s.schedule(finite(t, "time"), soadyn::EventKind::lock, dof);
             if (kind == "release") return s.schedule(finite(t, "time"), soadyn::EventKind::release, dof);
             throw py::value_error("unknown event '" + kind + "' (lock, release, or prescribe with a source)");
           })
      .def("_schedule_prescribe", [](Sim& s, double t, int dof, const Source& src) {
             return s.schedule_prescribe(finite(t, "time"), dof, src.source); })
      .def("_drive_cassini", [](Sim& s) { soadyn::drive_cassini(s); })
      .def("_lock", [](Sim& s, int dof) { raise_on(s.lock(dof), s); })
      .def("_release", [](Sim& s, int dof) { raise_on(s.release(dof), s); })
      .def("step", [](Sim& s) {
             soadyn::Status st;
             {
               py::gil_scoped_release release;
               st = s.step();
             }
             raise_on(st, s); },
           "Advance one step.")
      .def("_run", [](Sim& s, long steps, py::array_t<double> t, py::array_t<double> q, py::array_t<double> v,
                      py::array_t<double> tau) {
             // Records rows 1..steps; row 0 is the caller's. Returns (steps done, message).
             double *tp = t.mutable_data(), *qp = q.mutable_data(), *vp = v.mutable_data(), *fp = tau.mutable_data();
             const int nq = s.model().nq, nv = s.model().nv;
             soadyn::Status st;
             long done = 0;
             {
               py::gil_scoped_release release;
               for (; done < steps; ++done) {
                 st = s.step();
                 if (!st.ok()) break;
                 const long row = done + 1;
                 tp[row] = s.time();
                 Eigen::Map<Eigen::VectorXd>(qp + row * nq, nq) = s.q();
                 Eigen::Map<Eigen::VectorXd>(vp + row * nv, nv) = s.v();
                 Eigen::Map<Eigen::VectorXd>(fp + done * nv, nv) = s.forces();
               }
             }
             std::string message;
             if (!st.ok()) {
               try {
                 raise_on(st, s);
               } catch (const py::value_error& e) {
                 message = e.what();
               }
             }
             return py::make_tuple(done, message);
           })
      .def_property_readonly("q", [](const Sim& s) { return Eigen::VectorXd(s.q()); })
      .def_property_readonly("v", [](const Sim& s) { return Eigen::VectorXd(s.v()); })
      .def_property_readonly("inputs", [](const Sim& s) { return Eigen::VectorXd(s.inputs()); })
      .def_property_readonly("forces", [](const Sim& s) { return Eigen::VectorXd(s.forces()); },
                             "Generalized forces at the start of the last step (drive torques on prescribed DOFs).")
      .def_property_readonly("time", &Sim::time)
      .def_property_readonly("dt", &Sim::dt)
      .def_property_readonly("integrator", [](const Sim& s) { return std::string(integrator_name(s.integrator())); })
      .def_property_readonly("energy_lost", &Sim::energy_lost, "Kinetic energy removed by lock impulses so far.")
      .def_property_readonly("prescribed", [](const Sim& s) {
        py::array_t<bool> mask(s.model().nv);
        for (int k = 0; k < s.model().nv; ++k) mask.mutable_at(k) = s.model().is_prescribed(k);
        return mask; })
      .def_property_readonly("_dof_names", [](const Sim& s) { return s.model().dof_names; })
      .def_readwrite("rtol", &Sim::rtol)
      .def_readwrite("atol", &Sim::atol);
}

}  // namespace soadyn_py
