// Batched dynamics and rollouts (parallel/batch_dynamics.hpp,
// parallel/rollout.hpp): arguments checked row by row with the GIL held
// (errors name the row and the coordinate), then computed on the pool with
// the GIL released and the model's lock held. python/soadyn/batch.py shapes
// the arguments and names the results.
#include <pybind11/stl.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "arrays.hpp"
#include "dynamics_calls.hpp"
#include "errors.hpp"
#include "interrupts.hpp"
#include "model_handle.hpp"
#include "simulator_handle.hpp"
#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/parallel/batch_dynamics.hpp"
#include "soadyn/parallel/rollout.hpp"
#include "soadyn/model/parameters.hpp"

namespace soadyn_py {

namespace {

// A C-contiguous float64 array of `rows` x `cols` values (any shape with that
// many), every entry finite; errors name `arg`, the row and the entry's name.
Array rows_arg(py::handle obj, const char* arg, py::ssize_t rows, const std::vector<std::string>& names) {
  Array a = as_float_array(obj, arg);
  const py::ssize_t cols = static_cast<py::ssize_t>(names.size());
  if (a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != cols)
    throw py::value_error(std::string(arg) + " must have shape (" + std::to_string(rows) + ", " +
                          std::to_string(cols) + ")");
  const double* x = a.data();
  if (all_finite(x, rows * cols)) return a;
  for (py::ssize_t k = 0; k < rows * cols; ++k)
    if (!std::isfinite(x[k]))
      throw py::value_error(std::string(arg) + " row " + std::to_string(k / cols) + ": '" +
                            names[static_cast<std::size_t>(k % cols)] + "' is " + (std::isnan(x[k]) ? "NaN" : "infinite"));
  return a;
}

// Configurations: rows_arg plus unit quaternions, as q_arg checks one (the
// quaternions' coordinates found once for all rows).
Array configurations_arg(const ModelHandle& h, py::handle obj, const char* arg, py::ssize_t rows) {
  Array a = rows_arg(obj, arg, rows, h.model.coordinate_names);
  const soadyn::Model& m = h.model;
  const std::vector<int> starts = soadyn::quaternion_coordinates(m);
  for (py::ssize_t k = 0; !starts.empty() && k < rows; ++k) {
    const double* q = a.data() + k * m.nq;
    bool unit = true;
    for (const int s : starts) unit = unit && soadyn::unit_quaternion(q + s, kQuaternionTolerance);
    if (unit) continue;
    double norm = 0;
    const int body = soadyn::first_non_unit_quaternion<double>(m, Eigen::Map<const Eigen::VectorXd>(q, m.nq),
                                                               kQuaternionTolerance, &norm);
    if (body >= 0)
      throw py::value_error(std::string(arg) + " row " + std::to_string(k) + ": the quaternion of joint '" +
                            h.model.joint_names[static_cast<std::size_t>(body)] + "' has norm " +
                            std::to_string(norm) + "; it must be 1 within 1e-6");
  }
  return a;
}

// Optional external wrenches: None or rows x nbodies x 6.
const double* wrenches_arg(const ModelHandle& h, py::handle obj, py::ssize_t rows, py::object& keep) {
  if (obj.is_none()) return nullptr;
  std::vector<std::string> names;
  for (const std::string& body : h.model.body_names)
    for (const char* axis : {"tx", "ty", "tz", "fx", "fy", "fz"}) names.push_back(body + ":" + axis);
  Array a = as_float_array(obj, "f_ext");
  Array flat = rows_arg(a.reshape({rows, static_cast<py::ssize_t>(names.size())}), "f_ext", rows, names);
  keep = flat;
  return flat.data();
}

// The model's cached BatchDynamics for `threads`. A model keeps one per
// thread count used, up to kCachedThreadCounts (the least recently used goes
// first), so that calls alternating thread counts do not rebuild their pools
// and workspaces; all are rebuilt after a structural change. Call with the
// model's lock held.
constexpr std::size_t kCachedThreadCounts = 4;
soadyn::BatchDynamics& batch_for(ModelHandle& h, int threads) {
  const int wanted = threads > 0 ? threads : soadyn::ThreadPool::hardware_threads();
  const long pid = ::getpid();  // a system call: once per call
  if (!h.batches.empty() && h.batch_pid != pid) {
    // A forked child inherits the pool objects but not their threads: it could neither run nor join
    // them. The inherited objects are left alone (leaked on purpose) and new ones are built.
    new std::vector<std::shared_ptr<soadyn::BatchDynamics>>(std::move(h.batches));
    h.batches.clear();
  }
  if (h.batch_version != h.model.version) h.batches.clear();
  h.batch_version = h.model.version;
  h.batch_pid = pid;
  auto& cache = h.batches;
  auto found = std::find_if(cache.begin(), cache.end(), [&](const auto& b) { return b->threads() == wanted; });
  if (found == cache.end()) {
    if (cache.size() == kCachedThreadCounts) cache.pop_back();
    cache.insert(cache.begin(), std::make_shared<soadyn::BatchDynamics>(h.model, wanted));
  } else {
    std::rotate(cache.begin(), found, found + 1);  // the most recently used first
  }
  return *cache.front();
}

// Runs fn(batch) with the model locked and the GIL released; raises the
// first failed row's DynamicsError.
template <class Fn>
void run_batch(ModelHandle& h, std::uint64_t version, int threads, int lanes, const char* what, Fn&& fn) {
  if (threads < 0) throw py::value_error(std::string(what) + ": threads must be >= 0 (0: one per hardware thread)");
  if (lanes == 0) lanes = soadyn::BatchDynamics::widest_lanes();
  soadyn::BatchOutcome outcome;
  PythonInterrupt interrupt;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(h.mutex);
    refuse_changed_model(h, version);
    soadyn::BatchDynamics& batch = batch_for(h, threads);
    batch.set_lanes(lanes);
    batch.set_interrupt(interrupt.get());
    const std::unique_ptr<soadyn::BatchDynamics, void (*)(soadyn::BatchDynamics*)> forget_interrupt(
        &batch, [](soadyn::BatchDynamics* b) { b->set_interrupt(nullptr); });
    outcome = fn(batch);
  }
  interrupt.raise_if_interrupted();
  if (outcome.failed_rows > 0)
    raise_on(outcome.first_status, h.model,
             (std::string(what) + " (row " + std::to_string(outcome.first_failed_row) + ", the first of " +
              std::to_string(outcome.failed_rows) + " failed rows)").c_str());
}

// The checked (Q, V, X, f_ext) of a batched call; X is TAU, QDD or U. (The
// model's version is read first, as StateArgs does.)
struct BatchStates {
  std::uint64_t version;
  Array q, v, x;
  py::object keep;  // the checked f_ext
  const double* f = nullptr;
  BatchStates(const ModelHandle& h, py::handle Q, py::handle V, py::handle X, const char* x_name, py::handle F,
              py::ssize_t n)
      : version(h.model.version), q(configurations_arg(h, Q, "Q", n)), v(rows_arg(V, "V", n, h.model.dof_names)),
        x(rows_arg(X, x_name, n, h.model.dof_names)) {
    f = wrenches_arg(h, F, n, keep);
  }
};

#define BATCH_STATE_ARGS(x_name)                                                                              \
  py::arg("model"), py::arg("Q"), py::arg("V"), py::arg(x_name), py::arg("f_ext"), py::arg("n"), py::arg("threads"), py::arg("lanes")

py::array_t<double> stacked(py::ssize_t rows, py::ssize_t cols) { return fresh_array(rows, cols); }

py::array_t<double> stacked(py::ssize_t rows, py::ssize_t a, py::ssize_t b) {
  return py::array_t<double>({rows, a, b});
}

}  // namespace

void bind_batch(py::module_& mod) {
  mod.def("_batch_forward_dynamics", [](ModelHandle& h, py::handle Q, py::handle V, py::handle TAU, py::handle F,
                                        py::ssize_t n, int threads, int lanes) {
    const BatchStates s(h, Q, V, TAU, "TAU", F, n);
    auto qdd = stacked(n, h.model.nv);
    double* out = qdd.mutable_data();
    run_batch(h, s.version, threads, lanes, "batch.forward_dynamics", [&](soadyn::BatchDynamics& b) {
      return b.forward_dynamics(n, s.q.data(), s.v.data(), s.x.data(), s.f, out); });
    return qdd;
  }, BATCH_STATE_ARGS("TAU"), "Forward dynamics of n rows (soadyn.batch.forward_dynamics).");
  mod.def("_batch_inverse_dynamics", [](ModelHandle& h, py::handle Q, py::handle V, py::handle QDD, py::handle F,
                                        py::ssize_t n, int threads, int lanes) {
    const BatchStates s(h, Q, V, QDD, "QDD", F, n);
    auto tau = stacked(n, h.model.nv);
    double* out = tau.mutable_data();
    run_batch(h, s.version, threads, lanes, "batch.inverse_dynamics", [&](soadyn::BatchDynamics& b) {
      return b.inverse_dynamics(n, s.q.data(), s.v.data(), s.x.data(), s.f, out); });
    return tau;
  }, BATCH_STATE_ARGS("QDD"), "Inverse dynamics of n rows (soadyn.batch.inverse_dynamics).");
  mod.def("_batch_hybrid_dynamics", [](ModelHandle& h, py::handle Q, py::handle V, py::handle U, py::handle F,
                                       py::ssize_t n, int threads, int lanes) {
    const BatchStates s(h, Q, V, U, "U", F, n);
    auto qdd = stacked(n, h.model.nv), tau = stacked(n, h.model.nv);
    double *qdd_out = qdd.mutable_data(), *tau_out = tau.mutable_data();
    run_batch(h, s.version, threads, lanes, "batch.hybrid_dynamics", [&](soadyn::BatchDynamics& b) {
      return b.hybrid_dynamics(n, s.q.data(), s.v.data(), s.x.data(), s.f, qdd_out, tau_out); });
    return py::make_tuple(qdd, tau);
  }, BATCH_STATE_ARGS("U"), "Hybrid dynamics of n rows (soadyn.batch.hybrid_dynamics).");
  mod.def("_batch_mass_matrix", [](ModelHandle& h, py::handle Q, py::ssize_t n, int threads, int lanes) {
    const std::uint64_t version = h.model.version;
    const Array q = configurations_arg(h, Q, "Q", n);
    auto M = stacked(n, h.model.nv, h.model.nv);
    double* out = M.mutable_data();
    run_batch(h, version, threads, lanes, "batch.mass_matrix", [&](soadyn::BatchDynamics& b) {
      return b.mass_matrix(n, q.data(), out); });
    return M;
  }, py::arg("model"), py::arg("Q"), py::arg("n"), py::arg("threads"), py::arg("lanes"),
     "Mass matrices of n rows (soadyn.batch.mass_matrix).");
  mod.def("_batch_dynamics_derivatives", [](ModelHandle& h, py::handle Q, py::handle V, py::handle U, py::handle F,
                                            py::ssize_t n, int threads, int lanes) {
    const BatchStates s(h, Q, V, U, "U", F, n);
    std::array<py::array_t<double>, 6> d;
    std::array<double*, 6> out;
    for (std::size_t i = 0; i < 6; ++i) {
      d[i] = stacked(n, h.model.nv, h.model.nv);
      out[i] = d[i].mutable_data();
    }
    run_batch(h, s.version, threads, lanes, "batch.dynamics_derivatives", [&](soadyn::BatchDynamics& b) {
      return b.dynamics_derivatives(n, s.q.data(), s.v.data(), s.x.data(), s.f, out); });
    return py::make_tuple(d[0], d[1], d[2], d[3], d[4], d[5]);
  }, BATCH_STATE_ARGS("U"), "Dynamics derivatives of n rows (soadyn.batch.dynamics_derivatives).");

  mod.def("_batch_widest_lanes", &soadyn::BatchDynamics::widest_lanes,
          "States per pass of the batched calls' packet path on this processor (soadyn.batch.widest_lanes).");
  mod.def("_batch_packet_minimum_rows", [] { return soadyn::BatchDynamics::packet_minimum_rows; },
          "The fewest rows a batched call runs in packets (soadyn.batch.packet_minimum_rows).");

  mod.def("_batch_rollout", [](ModelHandle& h, py::handle X0, py::ssize_t runs, py::handle controls,
                               bool controls_per_run, double dt, std::int64_t steps, const std::string& integrator,
                               std::int64_t record_every, const std::vector<int>& parameters, py::handle values,
                               const std::vector<std::pair<int, Source>>& sources,
                               const std::vector<std::pair<std::string, int>>& events, py::handle event_times,
                               int threads, int lanes) {
    if (threads < 0) throw py::value_error("batch.rollout: threads must be >= 0 (0: one per hardware thread)");
    const std::uint64_t version = h.model.version;
    std::vector<std::string> state_names = h.model.coordinate_names;
    state_names.insert(state_names.end(), h.model.dof_names.begin(), h.model.dof_names.end());
    const Array x0 = rows_arg(X0, "x0s", runs, state_names);
    soadyn::RolloutRequest r;
    r.runs = runs;
    r.steps = steps;
    r.dt = dt;
    r.integrator = integrator_from(integrator);
    r.record_every = record_every;
    r.initial_states = x0.data();
    Array u, p, te;
    if (!controls.is_none()) {
      u = as_float_array(controls, "controls");
      r.controls = u.data();
      r.controls_per_run = controls_per_run;
    }
    r.parameters = parameters;
    if (!values.is_none()) r.parameter_values = (p = as_float_array(values, "parameters")).data();
    for (const auto& [dof, source] : sources) r.sources.emplace_back(dof, source.source);
    for (const auto& [kind, dof] : events)
      r.events.emplace_back(kind == "lock" ? soadyn::EventKind::lock : soadyn::EventKind::release, dof);
    if (!event_times.is_none()) r.event_times = (te = as_float_array(event_times, "event times")).data();
    // The private entry trusts soadyn.batch.rollout for shapes, but never reads past an array.
    const auto require_size = [](const Array& a, py::ssize_t size, const char* what) {
      if (a.size() != size) throw py::value_error(std::string("batch.rollout: ") + what + " has the wrong size");
    };
    const py::ssize_t nv = h.model.nv;
    if (r.controls) require_size(u, (controls_per_run ? runs : 1) * steps * nv, "controls");
    if (r.parameter_values) {
      const soadyn::ParameterTable<double> table(h.model);
      py::ssize_t width = 0;
      for (int k : parameters) width += k >= 0 && k < table.size() ? table.entry(k).size() : 0;
      require_size(p, runs * width, "parameter values");
    }
    if (r.event_times) require_size(te, runs * static_cast<py::ssize_t>(events.size()), "event times");
    r.lanes = lanes;
    const py::ssize_t rows = soadyn::rollout_rows(r);
    py::array_t<double> q({runs, rows, static_cast<py::ssize_t>(h.model.nq)}),
        v({runs, rows, static_cast<py::ssize_t>(h.model.nv)});
    std::vector<soadyn::Status> status(static_cast<std::size_t>(runs));
    std::vector<std::int64_t> failed(static_cast<std::size_t>(runs));
    std::vector<std::string> messages(static_cast<std::size_t>(runs));
    std::int64_t side_by_side = 0;
    const soadyn::RolloutOutputs out{q.mutable_data(), v.mutable_data(), status.data(), failed.data(), messages.data(),
                                     &side_by_side};
    PythonInterrupt interrupt;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(h.mutex);
      refuse_changed_model(h, version);
      soadyn::ThreadPool pool(threads);
      pool.set_interrupt(interrupt.get());
      soadyn::rollout(pool, h.model, r, out);
    }
    interrupt.raise_if_interrupted();
    return py::make_tuple(q, v, failed, messages, side_by_side);
  }, py::arg("model"), py::arg("x0s"), py::arg("runs"), py::arg("controls"), py::arg("controls_per_run"), py::arg("dt"), py::arg("steps"), py::arg("integrator"), py::arg("record_every"), py::arg("parameters"), py::arg("parameter_values"), py::arg("sources"), py::arg("events"), py::arg("event_times"), py::arg("threads"),
     py::arg("lanes"), "Parallel rollouts (soadyn.batch.rollout): (q, v, failed_step, messages).");
}

}  // namespace soadyn_py
