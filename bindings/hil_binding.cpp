// The HIL runner: a HilRunner and its optional UdpLink, run with the GIL
// released. The progress display and the report live in python/soadyn/hil.py.
#include <cmath>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <stdexcept>

#include "soadyn/realtime/hil_runner.hpp"
#include "soadyn/sim/simulator.hpp"
#include "soadyn/realtime/udp_link.hpp"
#include "simulator_handle.hpp"

namespace soadyn_py {

namespace py = pybind11;

namespace {

// The runner with the link it owns; `running` refuses a second concurrent
// run(), and run() holds the simulator's lock, so no Python thread can step,
// prescribe or reset the simulator the loop is stepping.
struct HilSession {
  SimulatorHandle* sim = nullptr;
  std::unique_ptr<soadyn::UdpLink> link;
  std::unique_ptr<soadyn::HilRunner> runner;
  std::atomic<bool> running{false};
  // The step in which a Python motion source raised in the last run, or -1
  // (the step's Status is then a failed source; summary() reports it as an
  // exception in that step).
  std::int64_t source_raised_step = -1;

  soadyn::HilSummary summary() const {
    soadyn::HilSummary s = runner->summary();
    if (source_raised_step >= 0) s.exception_step = source_raised_step;
    return s;
  }

  void check_idle(const char* what) const {
    if (running.load()) throw std::runtime_error(std::string(what) + ": the HIL runner is running");
  }
};

// A fresh numpy copy of the first `rows` entries (1-D) or rows x cols block (row-major).
template <class T>
py::array_t<T> to_numpy(const std::vector<T>& x, std::int64_t rows) {
  py::array_t<T> out(static_cast<py::ssize_t>(rows));
  std::copy(x.begin(), x.begin() + rows, out.mutable_data());
  return out;
}

py::array_t<double> to_numpy(const std::vector<double>& x, std::int64_t rows, int cols) {
  py::array_t<double> out({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  std::copy(x.begin(), x.begin() + rows * cols, out.mutable_data());
  return out;
}

soadyn::CommandPolicy policy_from(const std::string& name) {
  for (auto p : {soadyn::CommandPolicy::clamp, soadyn::CommandPolicy::reject, soadyn::CommandPolicy::stop})
    if (name == soadyn::command_policy_name(p)) return p;
  throw py::value_error("command_policy '" + name + "': choose 'clamp', 'reject' or 'stop'");
}

std::unique_ptr<HilSession> make_session(SimulatorHandle& sim, double rate_hz, std::int64_t steps,
                                         std::optional<int> udp_port, int udp_destination_port,
                                         bool as_fast_as_possible, std::int64_t record_every, double spin_us,
                                         int fifo_priority, int cpu, bool lock_memory,
                                         std::optional<Eigen::VectorXd> command_limits,
                                         const std::string& command_policy, int udp_command_port,
                                         int max_packets_per_step, std::int64_t floor_periods,
                                         const std::string& floor, double preemption_margin_us, bool warm_up) {
  auto session = std::make_unique<HilSession>();
  session->sim = &sim;
  const SimulatorLock simulator_in_use(sim);  // the runner reads the simulator's model and state
  try {
    const auto& m = sim.model();
    if (udp_port) {
      session->link = std::make_unique<soadyn::UdpLink>(m.nq, m.nv, *udp_port, udp_destination_port, udp_command_port);
      session->link->set_max_packets_per_poll(max_packets_per_step);
    }
    session->runner = std::make_unique<soadyn::HilRunner>(sim, rate_hz, steps, session->link.get());
    session->runner->record_state_every(record_every);
    session->runner->set_floor_periods(floor_periods);
    if (floor != "interleaved" && floor != "after")
      throw std::invalid_argument("floor '" + floor + "': choose 'interleaved' or 'after'");
    session->runner->set_floor_mode(floor == "after" ? soadyn::FloorMode::after_run : soadyn::FloorMode::interleaved);
    if (!std::isfinite(preemption_margin_us))
      throw std::invalid_argument("preemption_margin_us must be a finite number >= 0");
    session->runner->set_preemption_margin_ns(std::llround(preemption_margin_us * 1e3));
    session->runner->set_warm_up(warm_up);
    session->runner->set_realtime(soadyn::RealtimeRequest{fifo_priority, cpu, lock_memory});
    if (command_limits) session->runner->set_command_limits(*command_limits);
    session->runner->set_command_policy(policy_from(command_policy));
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  session->runner->set_as_fast_as_possible(as_fast_as_possible);
  session->runner->set_spin_ns(std::llround(spin_us * 1e3));
  return session;
}

// Clears `running` on every way out of run().
struct RunningFlag {
  std::atomic<bool>& running;
  ~RunningFlag() { running.store(false); }
};

void run_session(HilSession& s) {
  if (s.running.exchange(true)) throw std::runtime_error("run: the HIL runner is already running");
  const RunningFlag flag{s.running};
  const SimulatorLock simulator_in_use(*s.sim);  // taken with the GIL held (simulator_handle.hpp)
  s.source_raised_step = -1;
  forget_pending_source_error();
  soadyn::Status status;
  {
    py::gil_scoped_release release;
    // Throws only what a C++ callback source threw in a step; the runner has
    // then recorded the step (summary().exception_step).
    status = s.runner->run();
  }
  // A Python source that raised failed its step with a Status: raise what
  // Simulator.step would, the DynamicsError caused by that exception.
  if (!status.ok()) {
    s.source_raised_step = s.runner->failed_step();
    raise_if_source_raised(*s.sim, status);  // returns when no source raised
    s.source_raised_step = -1;
  }
}

}  // namespace

void bind_hil(py::module_& mod) {
  using Summary = soadyn::HilSummary;
  py::class_<Summary>(mod, "_HilSummary")
      .def_readonly("steps", &Summary::steps)
      .def_readonly("requested_steps", &Summary::requested_steps)
      .def_readonly("deadline_misses", &Summary::deadline_misses)
      .def_readonly("compute_p50_us", &Summary::compute_p50_us)
      .def_readonly("compute_p99_us", &Summary::compute_p99_us)
      .def_readonly("compute_p999_us", &Summary::compute_p999_us)
      .def_readonly("compute_max_us", &Summary::compute_max_us)
      .def_readonly("lateness_p50_us", &Summary::lateness_p50_us)
      .def_readonly("lateness_p99_us", &Summary::lateness_p99_us)
      .def_readonly("lateness_max_us", &Summary::lateness_max_us)
      .def_readonly("wall_seconds", &Summary::wall_seconds)
      .def_readonly("misses_compute_overrun", &Summary::misses_compute_overrun)
      .def_readonly("misses_late_wakeup", &Summary::misses_late_wakeup)
      .def_readonly("misses_preempted", &Summary::misses_preempted)
      .def_readonly("preempted_steps", &Summary::preempted_steps)
      .def_readonly("involuntary_switches", &Summary::involuntary_switches)
      .def_readonly("preemption_margin_us", &Summary::preemption_margin_us)
      .def_readonly("cpu_p50_us", &Summary::cpu_p50_us)
      .def_readonly("cpu_p99_us", &Summary::cpu_p99_us)
      .def_readonly("cpu_p999_us", &Summary::cpu_p999_us)
      .def_readonly("cpu_max_us", &Summary::cpu_max_us)
      .def_readonly("floor_interleaved", &Summary::floor_interleaved)
      .def_readonly("warm_up", &Summary::warm_up)
      .def_readonly("floor_periods", &Summary::floor_periods)
      .def_readonly("floor_target_us", &Summary::floor_target_us)
      .def_readonly("floor_p50_us", &Summary::floor_p50_us)
      .def_readonly("floor_p99_us", &Summary::floor_p99_us)
      .def_readonly("floor_p999_us", &Summary::floor_p999_us)
      .def_readonly("floor_max_us", &Summary::floor_max_us)
      .def_readonly("dynamics_floor_evaluations", &Summary::dynamics_floor_evaluations)
      .def_readonly("dynamics_floor_p50_us", &Summary::dynamics_floor_p50_us)
      .def_readonly("dynamics_floor_p99_us", &Summary::dynamics_floor_p99_us)
      .def_readonly("dynamics_floor_p999_us", &Summary::dynamics_floor_p999_us)
      .def_readonly("dynamics_floor_max_us", &Summary::dynamics_floor_max_us)
      .def_readonly("packets_received", &Summary::packets_received)
      .def_readonly("packets_dropped", &Summary::packets_dropped)
      .def_readonly("packets_sent", &Summary::packets_sent)
      .def_readonly("packets_rejected_sender", &Summary::packets_rejected_sender)
      .def_readonly("packets_stale", &Summary::packets_stale)
      .def_readonly("kernel_drops", &Summary::kernel_drops)
      .def_readonly("kernel_drops_counted", &Summary::kernel_drops_counted)
      .def_readonly("send_failures", &Summary::send_failures)
      .def_readonly("steps_left_pending", &Summary::steps_left_pending)
      .def_readonly("max_packets_per_step", &Summary::max_packets_per_step)
      .def_readonly("commands_saturated", &Summary::commands_saturated)
      .def_readonly("commands_rejected", &Summary::commands_rejected)
      .def_readonly("saturated_per_dof", &Summary::saturated_per_dof)
      .def_property_readonly("command_policy", [](const Summary& s) { return soadyn::command_policy_name(s.command_policy); })
      .def_readonly("command_out_of_range_dof", &Summary::command_out_of_range_dof)
      .def_readonly("exception_step", &Summary::exception_step)
      .def_readonly("failed_step", &Summary::failed_step)
      .def_readonly("stopped", &Summary::stopped)
      .def_readonly("as_fast_as_possible", &Summary::as_fast_as_possible)
      .def_property_readonly("realtime", [](const Summary& s) {  // asked and granted, errno of each refusal
        const soadyn::RealtimeRequest& r = s.realtime_request;
        const soadyn::RealtimeOutcome& o = s.realtime;
        return py::dict(py::arg("fifo_priority") = r.fifo_priority, py::arg("fifo_granted") = o.fifo_granted,
                        py::arg("fifo_errno") = o.fifo_errno, py::arg("cpu") = r.cpu,
                        py::arg("cpu_granted") = o.cpu_granted, py::arg("cpu_errno") = o.cpu_errno,
                        py::arg("lock_memory") = r.lock_memory, py::arg("memory_locked") = o.memory_locked,
                        py::arg("lock_errno") = o.lock_errno); })
      .def_property_readonly("status", [](const Summary& s) {
             if (s.exception_step >= 0) return "exception in a step";
             if (s.command_out_of_range_dof >= 0) return "command out of range";
             return soadyn::status_message(s.status.code); })
      .def_property_readonly("failed_dof", [](const Summary& s) {
             return s.command_out_of_range_dof >= 0 ? s.command_out_of_range_dof : s.status.index; });

  py::class_<HilSession>(mod, "HilRunner",
                         "Fixed-rate loop over a Simulator with optional UDP I/O (see soadyn.hil.run_hil).")
      .def(py::init(&make_session), py::arg("sim"), py::arg("rate_hz"), py::arg("steps"),
           py::arg("udp_port") = py::none(), py::arg("udp_destination_port") = 0,
           py::arg("as_fast_as_possible") = false, py::arg("record_every") = 0, py::arg("spin_us") = 0.0,
           py::arg("fifo_priority") = 0, py::arg("cpu") = -1, py::arg("lock_memory") = false,
           py::arg("command_limits") = py::none(), py::arg("command_policy") = "clamp",
           py::arg("udp_command_port") = -1, py::arg("max_packets_per_step") = 16, py::arg("floor_periods") = 0,
           py::arg("floor") = "interleaved", py::arg("preemption_margin_us") = 10.0, py::arg("warm_up") = true,
           py::keep_alive<1, 2>())  // the simulator outlives the runner
      .def("run", &run_session, "Run the loop (GIL released); the outcome is in summary(). An exception raised by a "
                        "Python motion source ends the run: run() raises the DynamicsError naming its DOF, caused by that exception, "
                        "as Simulator.step does; summary() still holds the run.")
      .def("request_stop", [](HilSession& s) { s.runner->request_stop(); }, "Ask a running loop to stop (thread-safe).")
      .def("release_peer", [](HilSession& s) { if (s.link) s.link->release_peer(); },
           "Forget the latched command sender: the next valid command's sender becomes the peer (thread-safe).")
      .def_property("command_limits", [](const HilSession& s) { return s.runner->command_limits().limits(); },
           [](HilSession& s, const Eigen::VectorXd& limits) {
             // Under the simulator's lock, which run() holds for the whole run: a run
             // cannot start between the idle check and the write.
             const SimulatorLock no_run_in_between(*s.sim);
             s.check_idle("command_limits");
             try {
               s.runner->set_command_limits(limits);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             } },
           "Per-DOF limits of the command values (default a * M_ii at the start; inf: none).")
      .def_property_readonly("commands_saturated", [](const HilSession& s) { return s.runner->commands_saturated(); },
                             "Command values clamped to their limit so far (policy 'clamp').")
      .def_property_readonly("commands_rejected", [](const HilSession& s) { return s.runner->commands_rejected(); },
                             "Commands refused for a value beyond its limit so far (policy 'reject').")
      .def_property_readonly("steps_done", [](const HilSession& s) { return s.runner->steps_done(); },
                             "Steps completed so far (thread-safe during run()).")
      .def("latest_state", [](const HilSession& s) -> py::object {
             const soadyn::StateSnapshot& snapshot = s.runner->latest_state();
             std::int64_t step = 0;
             double time = 0;
             Eigen::VectorXd q(snapshot.nq()), v(snapshot.nv());
             if (!snapshot.read(step, time, q, v)) return py::none();
             return py::make_tuple(step, time, q, v); },
           "(step, t, q, v) the loop published last, read without disturbing it (thread-safe; any time during "
           "or after run()), or None before the first run.")
      .def_property_readonly("deadline_misses", [](const HilSession& s) { return s.runner->deadline_misses(); },
                             "Steps that ended after their period's deadline so far.")
      .def_property_readonly("misses_ours", [](const HilSession& s) { return s.runner->misses_ours(); },
                             "Deadline misses so far whose step's own CPU time exceeded the period (the others are the "
                             "machine's).")
      .def_property_readonly("packets_received", [](const HilSession& s) {
             return s.link ? s.link->packets_received() : std::uint64_t{0}; },
           "Valid commands received so far (0 without UDP).")
      .def_property_readonly("udp_port", [](const HilSession& s) {
             return s.link ? py::object(py::int_(s.link->port())) : py::object(py::none()); },
           "The bound UDP port (an ephemeral one when 0 was asked), or None without UDP.")
      .def("summary", [](const HilSession& s) {
             s.check_idle("summary");
             return s.summary(); },
           "The run's counts and timing percentiles (what soadyn.hil.HilReport is made from); RuntimeError while\n"
           "run() is running.")
      .def_property_readonly("compute_ns", [](const HilSession& s) {
             s.check_idle("compute_ns");
             return to_numpy(s.runner->compute_ns(), s.runner->steps_done()); },
           "Per-step compute times in ns (steps_done,); RuntimeError while run() is running.")
      .def_property_readonly("lateness_ns", [](const HilSession& s) {
             s.check_idle("lateness_ns");
             return to_numpy(s.runner->lateness_ns(), s.runner->steps_done()); },
           "Per-step lateness of the wake-up past its deadline in ns (steps_done,); RuntimeError while run() is\n"
           "running.")
      .def_property_readonly("cpu_ns", [](const HilSession& s) {
             s.check_idle("cpu_ns");
             return to_numpy(s.runner->cpu_ns(), s.runner->steps_done()); },
           "Per-step CPU time of the loop's thread in ns (steps_done,); RuntimeError while run() is running.")
      .def_property_readonly("involuntary_switches", [](const HilSession& s) {
             s.check_idle("involuntary_switches");
             const std::vector<std::int32_t>& x = s.runner->involuntary_switches();
             return py::array_t<std::int32_t>(static_cast<py::ssize_t>(s.runner->steps_done()), x.data()); },
           "Per-step involuntary context switches of the loop's thread (steps_done,); RuntimeError while run() is "
           "running.")
      .def_property_readonly("floor_ns", [](const HilSession& s) {
             s.check_idle("floor_ns");
             return to_numpy(s.runner->floor_ns(), s.runner->floor_done()); },
           "Per-period times of the machine's floor (register arithmetic of the steps' median length).")
      .def_property_readonly("dynamics_floor_ns", [](const HilSession& s) {
             s.check_idle("dynamics_floor_ns");
             return to_numpy(s.runner->dynamics_floor_ns(), s.runner->floor_done()); },
           "Per-period times of the dynamics floor (evaluations of the dynamics at the present state, about the "
           "steps' median length), in the same periods as floor_ns.")
      .def("trajectory", [](const HilSession& s) {
             s.check_idle("trajectory");
             const soadyn::HilRunner& r = *s.runner;
             const std::int64_t rows = r.recorded_rows();
             return py::make_tuple(to_numpy(r.recorded_time(), rows),
                                   to_numpy(r.recorded_q(), rows, r.simulator().model().nq),
                                   to_numpy(r.recorded_v(), rows, r.simulator().model().nv)); },
           "Recorded (t, q, v): the start and every record_every steps.");
}

}  // namespace soadyn_py
