// Fixed-rate stepping of a Simulator against the wall clock, for
// hardware-in-the-loop runs, with optional UDP I/O to an external controller.
//
// Each step k has the absolute deadline start + k / rate on CLOCK_MONOTONIC.
// The loop sleeps until the deadline (clock_nanosleep, TIMER_ABSTIME), then
// reads the pending commands, applies the latest to the regular DOFs, steps
// the simulator, sends the sensor packet and records the state. A late step
// does not shift the schedule: the steps after it run at once until the loop
// has caught up, so simulation time stays locked to the wall clock.
//
// With a spin margin, the loop sleeps until `spin` before the deadline and
// busy-waits the rest: the core stays awake and its caches warm, so neither
// the wake-up latency of a sleeping core nor cold caches reach the step (the
// usual practice on a core dedicated to the simulation; it costs that share
// of the core). While spinning, the loop also warms the caches (set_warm_up,
// on by default): shortly before the deadline (twice the last step's compute
// time, at least 20 us, at most half the spin) it evaluates the dynamics once
// at the present state (Simulator::evaluate_now, which changes nothing a step
// reads), so the step finds its model and data in the caches even when other
// processes evicted them during the wait.
//
// Per step it records the compute time (wake-up to the end of the step,
// I/O included, wall clock), the thread's own CPU time in that window
// (CLOCK_THREAD_CPUTIME_ID) and the involuntary context switches around it
// (getrusage(RUSAGE_THREAD)), and the lateness (wake-up minus deadline); a
// step whose compute ends after the next deadline is a deadline miss. A step
// whose wall time exceeds its CPU time by more than the pre-emption margin,
// or that was switched out involuntarily, was pre-empted. A miss is ours when
// the step's own CPU time exceeded the period, or when the step started late
// only because the previous step's miss was ours (a backlog of our own); any
// other miss is the machine's (the thread woke up, or was let run, too late,
// or was pre-empted). In as-fast-as-possible mode it never sleeps, lateness
// is 0 and no step is a miss.
//
// The machine's floor: a workload that cannot vary by itself — multiply-add
// chains in registers, calibrated to the median compute time of the first
// tenth of the steps (at most 100) — timed over `floor_periods` periods. Interleaved (the
// default), it runs in the steps' own periods under the same conditions as
// the step: when the loop spins, inside the spin window shortly before the
// deadline (before the warm-up), on the same awake core, without adding busy
// time; when it sleeps (or the window is too short), at the period's
// midpoint, woken by the same sleep. Step and floor see the same phases of a
// shared host, and the run takes no longer. After the run (FloorMode::after_run, a completed run
// only), it runs over as many more periods. Its spread is what the machine
// adds to any computation of that length; the step's p99.9 over the floor's
// p99.9 is the part of the tail that is the step's own. A period without
// room for it (a late wake-up, a step past the midpoint) times no floor.
//
// Register arithmetic does not see what the machine does to memory: on a host
// whose caches are shared with other guests, the same instructions on the same
// data vary far more than arithmetic in registers. So each floor period also
// times a second workload right after the arithmetic, the dynamics floor:
// Simulator::evaluate_now at the present state (which changes nothing a step
// reads), as many evaluations as come closest to the same length, after one
// untimed evaluation when the loop warms the caches for the step. It is the
// step's own kind of work with no data-dependent cost (one pass of the
// recursions, the same for every state), so its spread is the machine's for
// memory-touching work; the step's spread beyond it is the step's own.
//
// Real-time scheduling (optional, set_realtime): run() applies SCHED_FIFO,
// CPU pinning and memory locking to its thread before the loop and undoes
// them after it (realtime/realtime_scheduling.hpp); the summary says what the
// kernel granted.
//
// Commands: each step, the latest valid command from the link is judged
// against the command limits (sim/command_limits.hpp; default from the model
// at the state the runner is built with) and, clamped, applied to the
// regular DOFs until the next one; a command rejected by the policy leaves the
// previous one applied, and the stop policy ends the run before the step
// (summary().command_out_of_range_dof names the DOF).
//
// The latest state: after every step (and once before the first) the loop
// publishes (step, time, q, v) into a sequence-locked snapshot
// (realtime/state_snapshot.hpp) that other threads read at their own pace, e.g. a
// viewer; publishing never waits for a reader.
//
// Memory policy: the constructor and record_state_every() allocate every
// buffer; run() allocates nothing, takes no lock, never throws and makes no
// blocking call besides the sleep. A step whose Status is not ok stops the
// run; the status and the step index are kept. If the simulator's step throws
// (only a callback motion source, such as a Python function, can), run()
// records the step (summary().exception_step), finishes its bookkeeping and
// lets the exception through. steps_done(), deadline_misses(),
// commands_saturated(), commands_rejected(), request_stop() and
// latest_state().read() may be used
// from another thread while run() is going; everything else only before or
// after it.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "soadyn/sim/command_limits.hpp"
#include "soadyn/realtime/realtime_scheduling.hpp"
#include "soadyn/sim/simulator.hpp"
#include "soadyn/realtime/state_snapshot.hpp"
#include "soadyn/realtime/udp_link.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn {

struct HilSummary {
  std::int64_t steps = 0;            // steps completed
  std::int64_t requested_steps = 0;  // steps asked for
  std::int64_t deadline_misses = 0;
  double compute_p50_us = 0, compute_p99_us = 0, compute_p999_us = 0, compute_max_us = 0;
  double lateness_p50_us = 0, lateness_p99_us = 0, lateness_max_us = 0;
  // The step's own CPU time (thread CPU clock) between wake-up and the end of the step.
  double cpu_p50_us = 0, cpu_p99_us = 0, cpu_p999_us = 0, cpu_max_us = 0;
  double wall_seconds = 0;  // wall-clock time of the loop (an after-run floor pass excluded)
  std::int64_t misses_compute_overrun = 0;  // misses whose CPU time, or our own backlog, exceeded the period (ours)
  std::int64_t misses_late_wakeup = 0;      // the other misses (the machine's)
  std::int64_t misses_preempted = 0;        // the machine's misses whose step was pre-empted
  std::int64_t preempted_steps = 0;         // steps pre-empted (wall - CPU > margin, or switched out)
  std::int64_t involuntary_switches = 0;    // over the steps
  double preemption_margin_us = 0;
  // The machine's floor (see above): periods timed (0: not measured), the
  // workload's calibrated length and its percentiles.
  std::int64_t floor_periods = 0;
  bool floor_interleaved = true;  // timed in the steps' periods (false: after the run)
  bool warm_up = false;           // the caches were warmed before each deadline (spinning, set_warm_up)
  double floor_target_us = 0, floor_p50_us = 0, floor_p99_us = 0, floor_p999_us = 0, floor_max_us = 0;
  // The dynamics floor, timed in the same periods: evaluations per period and its percentiles.
  std::int64_t dynamics_floor_evaluations = 0;
  double dynamics_floor_p50_us = 0, dynamics_floor_p99_us = 0, dynamics_floor_p999_us = 0,
         dynamics_floor_max_us = 0;
  // Counters accumulate over the runner's (and the link's) life, across
  // runs. The link's counters (udp_link.hpp): accepted commands, malformed, sensor
  // packets sent, from another sender, stale sequence, dropped by the kernel,
  // failed sends, steps that left datagrams waiting (the per-step read bound).
  std::uint64_t packets_received = 0, packets_dropped = 0, packets_sent = 0, packets_rejected_sender = 0,
                packets_stale = 0, kernel_drops = 0, send_failures = 0, steps_left_pending = 0;
  bool kernel_drops_counted = false;  // SO_MEMINFO available
  int max_packets_per_step = 0;       // the read bound (0: no link)
  // The command limits: commands clamped (and per DOF) or rejected.
  std::uint64_t commands_saturated = 0, commands_rejected = 0;
  std::vector<std::uint64_t> saturated_per_dof;
  CommandPolicy command_policy = CommandPolicy::clamp;
  Status status;                  // the status of the failed step, or ok
  std::int64_t failed_step = -1;  // the step index the status came from
  int command_out_of_range_dof = -1;  // the stop policy ended the run: the DOF at fault
  std::int64_t exception_step = -1;   // the step whose simulator step threw
  bool stopped = false;           // request_stop() ended the run early
  bool as_fast_as_possible = false;
  RealtimeRequest realtime_request;  // what set_realtime asked for
  RealtimeOutcome realtime;          // what the kernel granted during the last run
};

enum class FloorMode { interleaved, after_run };

class HilRunner {
 public:
  // Runs `steps` steps of `sim` at `rate_hz` (the simulator's dt should be
  // 1 / rate_hz for real-time simulation; the runner does not enforce it).
  // `link` (optional, not owned) must have the model's nq and nv. Turns the
  // simulator's divergence guard on (Simulator::set_divergence_guard(false)
  // after construction turns it off): a run stops with StatusCode::diverging
  // before its state stops being finite.
  HilRunner(Simulator& sim, double rate_hz, std::int64_t steps, UdpLink* link = nullptr);

  // Setup, before run().
  void set_as_fast_as_possible(bool on) { as_fast_as_possible_ = on; }
  // Busy-wait the last `ns` nanoseconds before each deadline (0: sleep all the way).
  void set_spin_ns(std::int64_t ns) { spin_ns_ = ns > 0 ? ns : 0; }
  // Real-time scheduling of the thread that calls run(), for the loop's
  // duration. Throws std::invalid_argument naming a bad field.
  void set_realtime(const RealtimeRequest& request) {
    request.validate();
    realtime_request_ = request;
  }
  // Limits of the commands from the link (sim/command_limits.hpp; nv
  // values, +inf: none) and the policy beyond them. Throw
  // std::invalid_argument naming a bad DOF.
  void set_command_limits(const Eigen::VectorXd& limits) { limits_.set_limits(limits); }
  void set_command_policy(CommandPolicy policy) { limits_.set_policy(policy); }
  const CommandLimits& command_limits() const { return limits_; }
  // Periods of the machine's floor (0: none; at most one per step). Allocates the buffer.
  void set_floor_periods(std::int64_t periods);
  void set_floor_mode(FloorMode mode) { floor_mode_ = mode; }
  // The warm-up evaluation before each deadline while spinning (on by default).
  void set_warm_up(bool on) { warm_up_ = on; }
  // Wall time beyond the CPU time that marks a step pre-empted (default 10 us); throws
  // std::invalid_argument for a negative or non-finite margin.
  void set_preemption_margin_ns(std::int64_t ns);
  // Records time, q and v at the start and after every `every` steps
  // (0: no recording). Allocates the buffers.
  void record_state_every(std::int64_t every);

  // The loop. Returns ok, or the status of the step that failed.
  Status run();

  // Thread-safe progress and control.
  std::int64_t steps_done() const { return steps_done_.load(std::memory_order_relaxed); }
  std::int64_t deadline_misses() const { return deadline_misses_.load(std::memory_order_relaxed); }
  // The misses that are ours (CPU time over the period), so far.
  std::int64_t misses_ours() const { return misses_ours_.load(std::memory_order_relaxed); }
  // The step the last run's failing status came from, or -1 (read after run()).
  std::int64_t failed_step() const { return failed_step_; }
  std::uint64_t commands_saturated() const { return limits_.saturated(); }
  std::uint64_t commands_rejected() const { return limits_.rejected(); }
  void request_stop() { stop_requested_.store(true, std::memory_order_relaxed); }
  // The state the loop published last (read() from any thread).
  const StateSnapshot& latest_state() const { return latest_state_; }

  // Results, after run(). The per-step arrays hold steps_done() valid entries.
  HilSummary summary() const;
  const std::vector<std::int64_t>& compute_ns() const { return compute_ns_; }
  const std::vector<std::int64_t>& lateness_ns() const { return lateness_ns_; }
  const std::vector<std::int64_t>& cpu_ns() const { return cpu_ns_; }
  const std::vector<std::int32_t>& involuntary_switches() const { return switches_; }
  const std::vector<std::int64_t>& floor_ns() const { return floor_ns_; }  // floor_done() valid entries
  std::int64_t floor_done() const { return floor_done_; }
  // The dynamics floor's periods (floor_done() valid entries, the same periods as floor_ns()).
  const std::vector<std::int64_t>& dynamics_floor_ns() const { return dynamics_floor_ns_; }
  std::int64_t recorded_rows() const { return recorded_rows_; }
  std::int64_t record_every() const { return record_every_; }
  const std::vector<double>& recorded_time() const { return recorded_time_; }
  const std::vector<double>& recorded_q() const { return recorded_q_; }  // rows x nq, row-major
  const std::vector<double>& recorded_v() const { return recorded_v_; }  // rows x nv, row-major

  double rate_hz() const { return rate_hz_; }
  std::int64_t requested_steps() const { return steps_; }
  const Simulator& simulator() const { return sim_; }

 private:
  void reset();
  std::int64_t deadline_ns(std::int64_t step) const;
  // One step's work after the wake-up: commands in, step, sensor state out,
  // record. False when the run must stop (status_ or out_of_range_dof_ say why).
  bool advance(std::int64_t step);
  // Judges a new command from the link; false when the stop policy applies.
  bool take_command();
  void apply_command();
  class RunBookkeeping;
  void record_state();
  // The floor (allocation free): its length from the first steps, one period of it, the pass after the loop.
  void calibrate_floor();
  void set_floor_target(std::int64_t steps_timed);
  void floor_period(std::int64_t deadline);
  // Busy time an interleaved floor period may take: each workload twice its target, and the gap after it.
  std::int64_t floor_span_ns() const { return 4 * floor_target_ns_ + floor_gap_ns_; }
  std::int64_t time_evaluations(std::int64_t evaluations);  // ns of `evaluations` evaluate_now calls
  bool floor_due() const { return floor_iterations_ > 0 && floor_done_ < static_cast<std::int64_t>(floor_ns_.size()); }
  void measure_floor_after_run();

  Simulator& sim_;
  UdpLink* link_;
  double rate_hz_;
  std::int64_t steps_;
  bool as_fast_as_possible_ = false;
  std::int64_t spin_ns_ = 0;
  RealtimeRequest realtime_request_;
  RealtimeOutcome realtime_outcome_;
  std::int64_t start_ns_ = 0, end_ns_ = 0;
  std::vector<std::int64_t> compute_ns_, lateness_ns_, cpu_ns_;
  std::vector<std::int32_t> switches_;
  // The floors' periods (arithmetic, dynamics); steps sampled for their length.
  std::vector<std::int64_t> floor_ns_, dynamics_floor_ns_, median_sample_;
  std::int64_t floor_done_ = 0, floor_target_ns_ = 0, floor_iterations_ = 0, floor_ns_per_iteration_x1000_ = 0;
  std::int64_t evaluation_ns_ = 0, floor_evaluations_ = 0;  // one evaluate_now (fastest of three); per period
  static constexpr std::int64_t floor_gap_ns_ = 10000;  // between the end of an interleaved floor and what follows
  FloorMode floor_mode_ = FloorMode::interleaved;
  bool warm_up_ = true;
  VecX<double> warm_qdd_, warm_tau_;
  std::int64_t preemption_margin_ns_ = 10000;
  std::int64_t misses_compute_overrun_ = 0, misses_late_wakeup_ = 0, misses_preempted_ = 0, preempted_steps_ = 0;
  std::int64_t record_every_ = 0, recorded_rows_ = 0;
  std::vector<double> recorded_time_, recorded_q_, recorded_v_;
  CommandLimits limits_;
  Eigen::VectorXd applied_command_;
  bool has_applied_command_ = false;
  Status status_;
  std::int64_t failed_step_ = -1, exception_step_ = -1;
  int out_of_range_dof_ = -1;
  std::atomic<std::int64_t> steps_done_{0}, deadline_misses_{0}, misses_ours_{0};
  std::atomic<bool> stop_requested_{false};
  StateSnapshot latest_state_;
  bool stopped_ = false;
};

}  // namespace soadyn
