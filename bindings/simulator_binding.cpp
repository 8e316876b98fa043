// Simulator and motion sources. DOF names are resolved in python/soadyn/simulator.py.
//
// Every call on a simulator holds its lock (simulator_handle.hpp), so calls
// from several Python threads run one after another. Errors, one type per
// cause: a bad argument is ValueError or TypeError; a dynamics failure (a
// failing Status, from a step, a run, a lock or a setup call) is
// DynamicsError naming the DOF, chained to the exception a Python motion
// source raised when that was the cause; a full event queue or a re-entrant
// call is RuntimeError.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include "arrays.hpp"
#include "interrupts.hpp"
#include "model_handle.hpp"
#include "simulator_handle.hpp"
#include "soadyn_scenes/scenes.hpp"

namespace soadyn_py {

soadyn::Integrator integrator_from(const std::string& name) {
  if (name == "euler" || name == "semi-implicit-euler") return soadyn::Integrator::semi_implicit_euler;
  if (name == "rk4") return soadyn::Integrator::rk4;
  if (name == "dopri5") return soadyn::Integrator::dopri5;
  throw py::value_error("unknown integrator '" + name + "' (choose 'euler', 'rk4' or 'dopri5')");
}


using Sim = SimulatorHandle;

namespace {

PyObject* dynamics_error_type = nullptr;  // soadyn._soadyn.DynamicsError, set by bind_simulator

// The exception the last Python motion source raised on this thread, not yet
// reported (an owned reference, or null).
thread_local PyObject* pending_source_error = nullptr;

// Call with the GIL held.
void forget_source_error() { Py_CLEAR(pending_source_error); }

py::object take_source_error() { return py::reinterpret_steal<py::object>(std::exchange(pending_source_error, nullptr)); }

// A Python callable fn(t) -> (q, v, a) as a C++ source. The C++ step must not
// throw: an exception (or a result that is not three numbers) is kept for the
// binding to report, and the sample comes back NaN, which the step turns into
// a Status naming the DOF. Copies and destruction take the GIL.
struct PythonSource {
  py::object fn;

  explicit PythonSource(py::object f) : fn(std::move(f)) {}
  PythonSource(const PythonSource& other) {
    py::gil_scoped_acquire gil;
    fn = other.fn;
  }
  PythonSource& operator=(const PythonSource&) = delete;
  ~PythonSource() {
    py::gil_scoped_acquire gil;
    fn = py::object();
  }

  soadyn::MotionSample<double> operator()(double t) const {
    py::gil_scoped_acquire gil;
    try {
      const auto r = fn(t).cast<std::tuple<double, double, double>>();
      return {std::get<0>(r), std::get<1>(r), std::get<2>(r)};
    } catch (py::error_already_set& e) {
      remember(e.value());
    } catch (const py::cast_error&) {
      remember(py::reinterpret_borrow<py::object>(PyExc_TypeError)(
          "a motion source function must return three numbers (q, v, a)"));
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }

  static void remember(const py::object& error) {
    forget_source_error();
    pending_source_error = error.inc_ref().ptr();
  }
};

// A DynamicsError carrying `message`, caused by the pending source error if any.
py::object dynamics_error(const std::string& message) {
  py::object error = py::reinterpret_borrow<py::object>(dynamics_error_type)(message);
  py::object cause = take_source_error();
  if (cause) PyException_SetCause(error.ptr(), cause.release().ptr());  // steals the reference
  return error;
}

[[noreturn]] void raise(const py::object& error) {
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
  throw py::error_already_set();
}

}  // namespace

void forget_pending_source_error() { forget_source_error(); }

void raise_if_source_raised(const SimulatorHandle& sim, const soadyn::Status& s) {
  if (s.ok() || !pending_source_error) return;
  raise(dynamics_error(sim.describe(s)));
}

namespace {

void raise_on(const soadyn::Status& s, const Sim& sim) {
  if (s.ok()) return;
  if (s.code == soadyn::StatusCode::invalid_dof) throw py::value_error(sim.describe(s));
  raise(dynamics_error(sim.describe(s)));
}

// A setup call under the simulator's lock: C++ exceptions as Python's.
template <class Fn>
auto locked_setup(Sim& sim, Fn&& fn) {
  SimulatorLock lock(sim);
  forget_source_error();
  try {
    return fn();
  } catch (const soadyn::SimulationError& e) {
    raise(dynamics_error(e.what()));
  } catch (const std::length_error& e) {  // the event queue is full
    throw std::runtime_error(e.what());
  }
}

// A read under the simulator's lock.
template <class Fn>
auto locked_read(Sim& sim, Fn&& fn) {
  SimulatorLock lock(sim);
  return fn();
}

double finite(double x, const char* what) {
  if (!std::isfinite(x)) throw py::value_error(std::string(what) + " is not finite");
  return x;
}

const char* integrator_name(soadyn::Integrator i) {
  switch (i) {
    case soadyn::Integrator::semi_implicit_euler: return "euler";
    case soadyn::Integrator::rk4: return "rk4";
    case soadyn::Integrator::dopri5: return "dopri5";
  }
  return "?";
}

// `steps` steps under the lock, the GIL released; returns (t, q, v, tau,
// steps done, DynamicsError or None). Row 0 is the state before the run.
py::tuple run(Sim& s, long steps) {
  if (steps < 0) throw py::value_error("steps must be >= 0");
  SimulatorLock lock(s);
  forget_source_error();
  const int nq = s.model().nq, nv = s.model().nv;
  py::array_t<double> t = fresh_array(steps + 1), q = fresh_array(steps + 1, nq), v = fresh_array(steps + 1, nv),
                      tau = fresh_array(steps, nv);
  double *tp = t.mutable_data(), *qp = q.mutable_data(), *vp = v.mutable_data(), *fp = tau.mutable_data();
  tp[0] = s.time();
  Eigen::Map<Eigen::VectorXd>(qp, nq) = s.q();
  Eigen::Map<Eigen::VectorXd>(vp, nv) = s.v();
  soadyn::Status st;
  long done = 0;
  PythonInterrupt interrupt;
  {
    py::gil_scoped_release release;
    for (; done < steps && !interrupt.get()->requested(); ++done) {
      st = s.step();
      if (!st.ok()) break;
      const long row = done + 1;
      tp[row] = s.time();
      Eigen::Map<Eigen::VectorXd>(qp + row * nq, nq) = s.q();
      Eigen::Map<Eigen::VectorXd>(vp + row * nv, nv) = s.v();
      Eigen::Map<Eigen::VectorXd>(fp + done * nv, nv) = s.forces();
    }
  }
  interrupt.raise_if_interrupted();
  const py::object error = st.ok() ? py::none() : dynamics_error("simulation stopped: " + s.describe(st));
  return py::make_tuple(t, q, v, tau, done, error);
}

void bind_sources(py::module_& mod) {
  py::class_<Source>(mod, "MotionSource", "Position, velocity and acceleration of one DOF as functions of time.")
      .def_static("constant_acceleration", [](double a, double v0, double q0, double t0) {
            return Source{soadyn::ConstantAcceleration<double>{finite(t0, "t0"), finite(q0, "q0"), finite(v0, "v0"), finite(a, "a")}}; },
          py::arg("acceleration"), py::arg("v0") = 0.0, py::arg("q0") = 0.0, py::arg("t0") = 0.0,
          "q(t) = q0 + v0 (t - t0) + acceleration (t - t0)^2 / 2 (rad or m, s); ValueError naming a non-finite\n"
          "argument.")
      .def_static("constant_velocity", [](double v, double q0, double t0) {
            return Source{soadyn::ConstantAcceleration<double>{finite(t0, "t0"), finite(q0, "q0"), finite(v, "velocity"), 0.0}}; },
          py::arg("velocity"), py::arg("q0") = 0.0, py::arg("t0") = 0.0,
          "q(t) = q0 + velocity (t - t0) (rad or m, s); ValueError naming a non-finite argument.")
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
            if (!(finite(duration, "cycloidal duration") > 0)) throw py::value_error("cycloidal duration must be positive");
            return Source{soadyn::Cycloidal<double>{finite(t0, "t0"), duration, finite(q0, "q0"), finite(q1, "q1")}}; },
          py::arg("q0"), py::arg("q1"), py::arg("t0"), py::arg("duration"),
          "Rest-to-rest cycloidal motion from q0 to q1 (Saha, Shah & Nandihal 2013, Eq. 34).")
      .def_static("spline", [](const std::vector<double>& t, const std::vector<double>& q) {
            for (double x : t) finite(x, "spline time");
            for (double x : q) finite(x, "spline value");
            try {
              return Source{soadyn::CubicSpline<double>(t, q)};
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            } },
          py::arg("times"), py::arg("values"), "Natural cubic spline through the table (held outside it).")
      .def_static("function", [](py::function f) { return Source{soadyn::CallbackSource<double>{PythonSource(f)}}; },
          py::arg("fn"),
          "fn(t) -> (q, v, a): a Python callable (not real-time), a function of time: a Simulator keeps its last "
          "finite result and reuses it when asked for the same time again. If it raises or returns a non-finite value, "
          "the step stops with DynamicsError naming the DOF (chained to the exception raised).")
      .def("sample", [](const Source& s, double t) {
            forget_source_error();
            const auto m = soadyn::sample_source(s.source, t);
            if (py::object error = take_source_error()) raise(error);
            return py::make_tuple(m.position, m.velocity, m.acceleration); },
          py::arg("t"), "(q, v, a) at time t.");
}

}  // namespace

void bind_simulator(py::module_& mod) {
  dynamics_error_type = py::object(mod.attr("DynamicsError")).release().ptr();  // registered by bind_algorithms
  bind_sources(mod);

  // The C++ simulator, for the bindings that take one (HilRunner).
  py::class_<soadyn::Simulator>(mod, "_SimulatorCore");
  py::class_<Sim, soadyn::Simulator>(mod, "_Simulator")
      .def(py::init([](ModelHandle& h, py::handle dt, py::handle integrator, py::handle capacity) {
             const double step = checked_real(dt, "dt");
             const soadyn::Integrator chosen = integrator_from(checked_text(integrator, "integrator"));
             const int events = static_cast<int>(
                 checked_integer(capacity, "event_capacity", 0, std::numeric_limits<int>::max()));
             const auto lock = h.lock_for_computation();  // waits for a computation without the GIL
             return std::make_unique<Sim>(h.model, step, chosen, events);
           }),
           py::arg("model"), py::arg("dt"), py::arg("integrator") = "rk4", py::arg("event_capacity") = 64)
      .def("_set_state", [](Sim& s, py::handle q, py::handle v, double t) {
             const auto& m = s.model();
             const Array qa = checked_vector(q, "q", m.coordinate_names), va = checked_vector(v, "v", m.dof_names);
             locked_setup(s, [&] {
               s.set_state(Eigen::Map<const Eigen::VectorXd>(qa.data(), m.nq),
                           Eigen::Map<const Eigen::VectorXd>(va.data(), m.nv), finite(t, "t"));
             });
           })
      .def("_set_input", [](Sim& s, int dof, double tau) {
             finite(tau, "input");
             locked_setup(s, [&] { s.set_input(dof, tau); }); })
      .def("_set_external_wrench", [](Sim& s, int body, py::handle wrench) {
             static const std::vector<std::string> components{"tx", "ty", "tz", "fx", "fy", "fz"};
             const Array w = checked_vector(wrench, "wrench", components);
             locked_setup(s, [&] { s.set_external_wrench(body, Eigen::Map<const soadyn::Vec6<double>>(w.data())); }); })
      .def_property_readonly("external_wrenches", [](Sim& s) {
             return locked_read(s, [&] {
               return Eigen::MatrixXd(Eigen::Map<const Eigen::MatrixXd>(s.external_wrenches().data(), 6,
                                                                      s.model().nbodies()).transpose()); }); },
             "Each body's external wrench, (nbodies, 6): [torque; force] in its frame about its origin.")
      .def("_prescribe", [](Sim& s, int dof, const Source& src) { locked_setup(s, [&] { s.prescribe(dof, src.source); }); })
      .def("_schedule", [](Sim& s, double t, const std::string& kind, int dof) {
             finite(t, "time");
             soadyn::EventKind k = soadyn::EventKind::lock;
             if (kind == "release") k = soadyn::EventKind::release;
             else if (kind != "lock")
               throw py::value_error("unknown event '" + kind + "' (lock, release, or prescribe with a source)");
             return locked_setup(s, [&] { return s.schedule(t, k, dof); });
           })
      .def("_schedule_prescribe", [](Sim& s, double t, int dof, const Source& src) {
             finite(t, "time");
             return locked_setup(s, [&] { return s.schedule_prescribe(t, dof, src.source); }); })
      .def("_drive_cassini", [](Sim& s) { locked_setup(s, [&] { soadyn::drive_cassini<double>(s); }); })
      .def("_lock", [](Sim& s, int dof) { locked_setup(s, [&] { raise_on(s.lock(dof), s); }); })
      .def("_release", [](Sim& s, int dof) { locked_setup(s, [&] { raise_on(s.release(dof), s); }); })
      .def("step", [](Sim& s) {
             SimulatorLock lock(s);
             forget_source_error();
             soadyn::Status st;
             {
               py::gil_scoped_release release;
               st = s.step();
             }
             raise_on(st, s); },
           "Advance one step; on failure raises DynamicsError and leaves the state as before the step.")
      .def("_run", &run, py::arg("steps"))
      .def_property_readonly("q", [](Sim& s) { return locked_read(s, [&] { return Eigen::VectorXd(s.q()); }); },
                             "The coordinates now, (nq,), a fresh array.")
      .def_property_readonly("v", [](Sim& s) { return locked_read(s, [&] { return Eigen::VectorXd(s.v()); }); },
                             "The velocities now, (nv,), a fresh array.")
      .def_property_readonly("inputs", [](Sim& s) { return locked_read(s, [&] { return Eigen::VectorXd(s.inputs()); }); },
                             "The torques (N m) or forces (N) applied to the regular DOFs, (nv,).")
      .def_property_readonly("forces", [](Sim& s) { return locked_read(s, [&] { return Eigen::VectorXd(s.forces()); }); },
                             "Generalized forces at the start of the last step (drive torques on prescribed DOFs).")
      .def_property_readonly("time", [](Sim& s) { return locked_read(s, [&] { return s.time(); }); },
                             "Simulation time now, in s.")
      .def_property_readonly("dt", &Sim::dt, "The step, in s.")
      .def_property_readonly("integrator", [](const Sim& s) { return std::string(integrator_name(s.integrator())); },
                             "'euler', 'rk4' or 'dopri5'.")
      .def_property_readonly("energy_lost", [](Sim& s) { return locked_read(s, [&] { return s.energy_lost(); }); },
                             "Kinetic energy removed by lock impulses so far.")
      .def_property_readonly("steps_taken", [](Sim& s) { return locked_read(s, [&] { return s.steps_taken(); }); },
                             "Steps completed since construction (a failed step does not count).")
      .def_property(
          "divergence_guard", [](Sim& s) { return locked_read(s, [&] { return s.divergence_guard(); }); },
          [](Sim& s, py::handle on) {
            const bool flag = checked_flag(on, "divergence_guard");
            locked_setup(s, [&] { s.set_divergence_guard(flag); });
          },
          "Whether a step that makes the state's energy grow beyond what the applied forces can supply (or a\n"
          "velocity pass its limit) stops with DynamicsError 'diverging' before the state is non-finite. Off by\n"
          "default; on in HIL runs. Turning it on takes the current state as the energy's reference.")
      .def_property(
          "velocity_limits", [](Sim& s) { return locked_read(s, [&] { return Eigen::VectorXd(s.velocity_limits()); }); },
          [](Sim& s, py::handle limits) {
            const Array a = as_float_array(limits, "velocity_limits");
            require_vector_shape(a, "velocity_limits", s.model().nv, "nv");
            const Eigen::VectorXd values = Eigen::Map<const Eigen::VectorXd>(a.data(), a.size());
            locked_setup(s, [&] { s.set_velocity_limits(values); });
          },
          "Per-DOF |v| limits the divergence guard enforces (nv values; inf: none, the default).")
      .def_property_readonly("pending_events", [](Sim& s) { return locked_read(s, [&] { return s.pending_events(); }); },
                             "Scheduled events not yet applied.")
      .def_property_readonly("event_capacity", &Sim::event_capacity, "Most events that can be pending at once.")
      .def_property_readonly("last_substeps", [](Sim& s) { return locked_read(s, [&] { return s.last_substeps(); }); },
                             "dopri5: sub-step attempts of the last step.")
      .def_property_readonly("prescribed", [](Sim& s) {
        return locked_read(s, [&] {
          py::array_t<bool> mask(s.model().nv);
          for (int k = 0; k < s.model().nv; ++k) mask.mutable_at(k) = s.model().is_prescribed(k);
          return mask;
        }); }, "Bool array (nv,): True where the DOF is prescribed now (locks and prescribe events included).")
      .def_property_readonly("_dof_names", [](const Sim& s) { return s.model().dof_names; })
      .def_property("rtol", [](Sim& s) { return locked_read(s, [&] { return s.rtol; }); },
          [](Sim& s, double x) {
            if (!(finite(x, "rtol") >= 0)) throw py::value_error("rtol must be >= 0");
            locked_read(s, [&] { s.rtol = x; }); },
          "dopri5: relative error tolerance of a sub-step (>= 0; ValueError otherwise).")
      .def_property("atol", [](Sim& s) { return locked_read(s, [&] { return s.atol; }); },
          [](Sim& s, double x) {
            if (!(finite(x, "atol") > 0)) throw py::value_error("atol must be > 0");
            locked_read(s, [&] { s.atol = x; }); },
          "dopri5: absolute error tolerance of a sub-step, in the state's units (> 0; ValueError otherwise).")
      .def_property("max_substeps", [](Sim& s) { return locked_read(s, [&] { return s.max_substeps; }); },
          [](Sim& s, int n) {
            if (n < 1) throw py::value_error("max_substeps must be >= 1");
            locked_read(s, [&] { s.max_substeps = n; }); },
          "dopri5: sub-step attempts allowed in one step; beyond it the step fails (DynamicsError).")
      .def_property("loop_tolerance", [](Sim& s) { return locked_read(s, [&] { return s.loop_tolerance; }); },
          [](Sim& s, double x) {
            if (!(finite(x, "loop_tolerance") > 0)) throw py::value_error("loop_tolerance must be > 0");
            locked_read(s, [&] { s.loop_tolerance = x; }); },
          "Largest loop-closure residual |Psi_i| the projection after each step leaves.")
      .def_property("loop_max_iterations", [](Sim& s) { return locked_read(s, [&] { return s.loop_max_iterations; }); },
          [](Sim& s, int n) {
            if (n < 1) throw py::value_error("loop_max_iterations must be >= 1");
            locked_read(s, [&] { s.loop_max_iterations = n; }); },
          "Gauss-Newton steps the closure projection may take after a step; beyond it the step fails.")
      .def_property_readonly("loop_drift", [](Sim& s) {
            return locked_read(s, [&] { return py::make_tuple(s.last_loop_drift_position(), s.last_loop_drift_velocity()); }); },
          "(position, velocity): the largest |Psi_i| and |(C v)_i| the integrator left at the end of the last step,\n"
          "before the closure projection.")
      .def_property_readonly("max_loop_drift", [](Sim& s) {
            return locked_read(s, [&] { return py::make_tuple(s.max_loop_drift_position(), s.max_loop_drift_velocity()); }); },
          "(position, velocity): the largest loop_drift over all steps so far.");
}

}  // namespace soadyn_py
