// The fixed-rate HIL loop; the timing model is described in hil_runner.hpp.
#include "soadyn/realtime/hil_runner.hpp"

#include <sys/resource.h>
#include <time.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace soadyn {

namespace {

constexpr std::int64_t ns_per_s = 1000000000;

std::int64_t now_ns() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * ns_per_s + t.tv_nsec;
}

// The calling thread's own CPU time, and its involuntary context switches so far (Linux: RUSAGE_THREAD).
std::int64_t thread_cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<std::int64_t>(t.tv_sec) * ns_per_s + t.tv_nsec;
}

std::int64_t involuntary_switches_now() {
#ifdef RUSAGE_THREAD
  rusage usage;
  if (getrusage(RUSAGE_THREAD, &usage) == 0) return usage.ru_nivcsw;
#endif
  return 0;
}

// Linux lets a sleeping thread wake up to 50 us late by default ("timer
// slack"); the loop asks for 1 ns while it runs and restores the old value.
class TightTimerSlack {
 public:
#ifdef __linux__
  TightTimerSlack() : previous_(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0)) {
    if (previous_ > 0) prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
  }
  ~TightTimerSlack() {
    if (previous_ > 0) prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(previous_), 0, 0, 0);
  }

 private:
  int previous_;
#endif
};

void sleep_until_ns(std::int64_t deadline) {
  timespec t;
  t.tv_sec = static_cast<time_t>(deadline / ns_per_s);
  t.tv_nsec = static_cast<long>(deadline % ns_per_s);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

// The first n entries of x, sorted (after the run: this allocates).
std::vector<std::int64_t> sorted_first(const std::vector<std::int64_t>& x, std::int64_t n) {
  std::vector<std::int64_t> out(x.begin(), x.begin() + n);
  std::sort(out.begin(), out.end());
  return out;
}

// Nearest-rank percentile (p in [0, 1]) of sorted nanoseconds, in microseconds.
double percentile_us(const std::vector<std::int64_t>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const double rank = std::ceil(p * static_cast<double>(sorted.size()));
  const std::size_t index = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  return static_cast<double>(sorted[std::min(index, sorted.size() - 1)]) * 1e-3;
}

// p50, p99, p99.9 and max (us) of the first `n` entries of `x` (ns).
void summarise_us(const std::vector<std::int64_t>& x, std::int64_t n, double& p50, double& p99, double& p999,
                  double& max) {
  const std::vector<std::int64_t> sorted = sorted_first(x, n);
  p50 = percentile_us(sorted, 0.5);
  p99 = percentile_us(sorted, 0.99);
  p999 = percentile_us(sorted, 0.999);
  max = percentile_us(sorted, 1.0);
}

// `iterations` rounds of eight independent multiply-add chains in registers:
// no memory traffic, no data-dependent timing (the machine's floor).
volatile double floor_sink;
__attribute__((noinline)) void register_arithmetic(std::int64_t iterations) {
  double x[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  for (std::int64_t i = 0; i < iterations; ++i)
    for (int k = 0; k < 8; ++k) x[k] = x[k] * 0.9999999 + 1e-9 * k;
  double sum = 0;
  for (double value : x) sum += value;
  floor_sink = sum;
}

constexpr std::int64_t min_warm_lead_ns = 20000;  // the warm-up evaluation starts at least this long before the deadline
constexpr std::size_t median_sample_size = 1001;  // steps sampled for the floor's length
constexpr std::int64_t interleaved_floor_warmup = 100;  // at most this many steps' median sets the interleaved floor's length
constexpr std::int64_t calibration_iterations = 20000;

}  // namespace

HilRunner::HilRunner(Simulator& sim, double rate_hz, std::int64_t steps, UdpLink* link)
    : sim_(sim), link_(link), rate_hz_(rate_hz), steps_(steps), limits_(sim.model().nv),
      applied_command_(Eigen::VectorXd::Zero(sim.model().nv)), latest_state_(sim.model().nq, sim.model().nv) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw std::invalid_argument("HIL rate must be a positive number");
  if (steps < 0) throw std::invalid_argument("HIL step count must be >= 0");
  if (link && (link->nq() != sim.model().nq || link->nv() != sim.model().nv))
    throw std::invalid_argument("the UDP link's nq and nv differ from the simulator's model");
  compute_ns_.assign(static_cast<std::size_t>(steps), 0);
  lateness_ns_.assign(static_cast<std::size_t>(steps), 0);
  cpu_ns_.assign(static_cast<std::size_t>(steps), 0);
  switches_.assign(static_cast<std::size_t>(steps), 0);
  warm_qdd_.setZero(sim.model().nv);
  warm_tau_.setZero(sim.model().nv);
  median_sample_.assign(median_sample_size, 0);
  limits_.set_limits(default_command_limits(sim.model(), sim.q()));
  sim.set_divergence_guard(true);  // on in every HIL run (sim/divergence_guard.hpp); the caller may turn it off
}

// Finishes run()'s bookkeeping on every way out, an exception from the
// simulator's step included (then `finished` is still false).
class HilRunner::RunBookkeeping {
 public:
  explicit RunBookkeeping(HilRunner& runner) : runner_(runner) {}
  ~RunBookkeeping() {
    if (!finished) runner_.end_ns_ = now_ns();
    runner_.stop_requested_.store(false, std::memory_order_relaxed);
    if (!finished) runner_.exception_step_ = runner_.steps_done();
  }
  bool finished = false;

 private:
  HilRunner& runner_;
};

void HilRunner::record_state_every(std::int64_t every) {
  if (every < 0) throw std::invalid_argument("recording interval must be >= 0");
  record_every_ = every;
  const std::int64_t rows = every > 0 ? 1 + steps_ / every : 0;
  recorded_time_.assign(static_cast<std::size_t>(rows), 0.0);
  recorded_q_.assign(static_cast<std::size_t>(rows * sim_.model().nq), 0.0);
  recorded_v_.assign(static_cast<std::size_t>(rows * sim_.model().nv), 0.0);
}

void HilRunner::set_floor_periods(std::int64_t periods) {
  if (periods < 0) throw std::invalid_argument("floor periods must be >= 0");
  floor_ns_.assign(static_cast<std::size_t>(std::min(periods, steps_)), 0);  // at most one per step
  dynamics_floor_ns_.assign(floor_ns_.size(), 0);
}

void HilRunner::set_preemption_margin_ns(std::int64_t ns) {
  if (ns < 0) throw std::invalid_argument("the pre-emption margin must be >= 0");
  preemption_margin_ns_ = ns;
}

void HilRunner::reset() {
  floor_done_ = floor_target_ns_ = floor_iterations_ = floor_evaluations_ = 0;
  misses_compute_overrun_ = misses_late_wakeup_ = misses_preempted_ = preempted_steps_ = 0;
  misses_ours_.store(0, std::memory_order_relaxed);
  status_ = Status{};
  failed_step_ = exception_step_ = -1;
  out_of_range_dof_ = -1;
  stopped_ = false;
  realtime_outcome_ = RealtimeOutcome{};
  recorded_rows_ = 0;
  steps_done_.store(0, std::memory_order_relaxed);
  deadline_misses_.store(0, std::memory_order_relaxed);
}

std::int64_t HilRunner::deadline_ns(std::int64_t step) const {
  // Computed from the start each time, so a non-integer period does not drift.
  return start_ns_ + std::llround(static_cast<double>(step) * 1e9 / rate_hz_);
}

Status HilRunner::run() {
  reset();
  record_state();
  latest_state_.publish(0, sim_.time(), sim_.q(), sim_.v());
  [[maybe_unused]] TightTimerSlack slack;
  const RealtimeScope realtime(realtime_request_);
  realtime_outcome_ = realtime.outcome();
  RunBookkeeping bookkeeping(*this);
  const bool interleave = floor_mode_ == FloorMode::interleaved && !as_fast_as_possible_ && !floor_ns_.empty();
  if (interleave) calibrate_floor();
  // The first tenth of the steps, at most 100, set the interleaved floor's length.
  const std::int64_t warmup = std::min(interleaved_floor_warmup, std::max<std::int64_t>(1, steps_ / 10));
  start_ns_ = now_ns();
  std::int64_t previous_end = start_ns_, previous_compute = 0;
  bool previous_miss_ours = false;
  for (std::int64_t k = 0; k < steps_; ++k) {
    if (stop_requested_.load(std::memory_order_relaxed)) {
      stopped_ = true;
      break;
    }
    const std::int64_t deadline = deadline_ns(k), next_deadline = deadline_ns(k + 1);
    if (!as_fast_as_possible_) {
      sleep_until_ns(deadline - spin_ns_);
      const std::int64_t warm_lead =
          warm_up_ && spin_ns_ > 0 ? std::clamp(2 * previous_compute, min_warm_lead_ns, spin_ns_ / 2) : 0;
      // Spinning: the floor inside the spin window, on the same warm core as the step and without adding
      // busy time (a real-time thread busy all the period would be throttled by the kernel).
      const std::int64_t floor_lead = warm_lead + floor_span_ns();
      if (interleave && spin_ns_ > 0 && floor_due() && floor_lead < spin_ns_ && now_ns() < deadline - floor_lead)
        floor_period(deadline - floor_lead);
      if (warm_lead > 0) {  // the dynamics' data into the caches just before the step
        while (now_ns() < deadline - warm_lead) {
        }
        sim_.evaluate_now(warm_qdd_, warm_tau_);  // changes nothing the step reads
      }
      while (now_ns() < deadline) {
      }
    }
    // The CPU clock inside the wall window: wall - CPU >= 0 but for the clocks' own reading.
    const std::int64_t switches_before = involuntary_switches_now();
    const std::int64_t wake = now_ns();
    const std::int64_t cpu_start = thread_cpu_ns();
    const bool go_on = advance(k);
    const std::int64_t cpu_end = thread_cpu_ns();
    const std::int64_t end = now_ns();
    const std::int64_t switches = involuntary_switches_now() - switches_before;
    if (!go_on) {
      failed_step_ = k;
      break;
    }
    const std::size_t i = static_cast<std::size_t>(k);
    compute_ns_[i] = end - wake;
    cpu_ns_[i] = cpu_end - cpu_start;
    switches_[i] = static_cast<std::int32_t>(std::min<std::int64_t>(switches, std::numeric_limits<std::int32_t>::max()));
    const bool preempted = compute_ns_[i] - cpu_ns_[i] > preemption_margin_ns_ || switches > 0;
    preempted_steps_ += preempted ? 1 : 0;
    lateness_ns_[i] = as_fast_as_possible_ ? 0 : wake - deadline;
    bool ours = false;
    if (!as_fast_as_possible_ && end > next_deadline) {
      deadline_misses_.fetch_add(1, std::memory_order_relaxed);
      // Ours when this step's own CPU time exceeded the period, or when it started late only because the
      // previous step, a miss of ours, was still running; else the machine woke us late or pre-empted us.
      ours = cpu_ns_[i] > next_deadline - deadline || (previous_end > deadline && previous_miss_ours);
      if (ours) {
        ++misses_compute_overrun_;
        misses_ours_.fetch_add(1, std::memory_order_relaxed);
      } else {
        ++misses_late_wakeup_;
        misses_preempted_ += preempted ? 1 : 0;
      }
    }
    previous_miss_ours = ours;
    previous_end = end;
    previous_compute = compute_ns_[i];
    steps_done_.store(k + 1, std::memory_order_relaxed);
    if (!interleave) continue;
    if (k + 1 == warmup) set_floor_target(warmup);
    // Sleeping (or a spin window too short for it): the floor at the period's midpoint, woken like the step,
    // when the step ended before the wake-up and the floor fits before the next deadline.
    const std::int64_t midpoint = deadline + (next_deadline - deadline) / 2;
    const bool in_spin_window = spin_ns_ > 0 && floor_span_ns() + 2 * min_warm_lead_ns < spin_ns_;
    if (floor_due() && !in_spin_window && end < midpoint - spin_ns_ && midpoint + floor_span_ns() < next_deadline)
      floor_period(midpoint);
  }
  end_ns_ = now_ns();
  // An after-run floor: a whole paced run only.
  if (floor_mode_ == FloorMode::after_run && !as_fast_as_possible_ && !stopped_ && failed_step_ < 0)
    measure_floor_after_run();
  bookkeeping.finished = true;
  return status_;
}

// Iterations per nanosecond of the floor's arithmetic, and the time of one evaluation of the dynamics (after
// one untimed, so in warm caches): the fastest of three timings each.
void HilRunner::calibrate_floor() {
  std::int64_t fastest = std::numeric_limits<std::int64_t>::max();
  for (int trial = 0; trial < 3; ++trial) {
    const std::int64_t t0 = now_ns();
    register_arithmetic(calibration_iterations);
    fastest = std::min(fastest, std::max<std::int64_t>(1, now_ns() - t0));
  }
  floor_ns_per_iteration_x1000_ = std::max<std::int64_t>(1, fastest * 1000 / calibration_iterations);
  time_evaluations(1);
  evaluation_ns_ = std::numeric_limits<std::int64_t>::max();
  for (int trial = 0; trial < 3; ++trial) evaluation_ns_ = std::min(evaluation_ns_, std::max<std::int64_t>(1, time_evaluations(1)));
}

std::int64_t HilRunner::time_evaluations(std::int64_t evaluations) {
  const std::int64_t start = now_ns();
  for (std::int64_t i = 0; i < evaluations; ++i) sim_.evaluate_now(warm_qdd_, warm_tau_);  // changes nothing a step reads
  return now_ns() - start;
}

// The floor's length: the median compute time of the first `steps_timed` steps (sampled evenly).
void HilRunner::set_floor_target(std::int64_t steps_timed) {
  const std::int64_t n = steps_timed, m = std::min<std::int64_t>(n, static_cast<std::int64_t>(median_sample_.size()));
  if (m == 0) return;
  for (std::int64_t i = 0; i < m; ++i)
    median_sample_[static_cast<std::size_t>(i)] = compute_ns_[static_cast<std::size_t>(i * n / m)];
  const auto middle = median_sample_.begin() + m / 2;
  std::nth_element(median_sample_.begin(), middle, median_sample_.begin() + m);
  floor_target_ns_ = *middle;
  floor_iterations_ = std::max<std::int64_t>(1, floor_target_ns_ * 1000 / floor_ns_per_iteration_x1000_);
  // The whole number of evaluations closest to the target, at least one.
  floor_evaluations_ = std::max<std::int64_t>(1, (floor_target_ns_ + evaluation_ns_ / 2) / evaluation_ns_);
}

// One period of the floor, paced like a step: woken at `deadline` by the same sleep and spin.
void HilRunner::floor_period(std::int64_t deadline) {
  sleep_until_ns(deadline - spin_ns_);
  while (now_ns() < deadline) {
  }
  const std::int64_t wake = now_ns();
  register_arithmetic(floor_iterations_);
  floor_ns_[static_cast<std::size_t>(floor_done_)] = now_ns() - wake;
  if (warm_up_ && spin_ns_ > 0) time_evaluations(1);  // the caches as the step finds them after its warm-up
  dynamics_floor_ns_[static_cast<std::size_t>(floor_done_)] = time_evaluations(floor_evaluations_);
  ++floor_done_;
}

void HilRunner::measure_floor_after_run() {
  const std::int64_t periods = std::min<std::int64_t>(steps_done(), static_cast<std::int64_t>(floor_ns_.size()));
  if (periods == 0) return;
  calibrate_floor();
  set_floor_target(steps_done());
  // Paced like the steps, from the next period on.
  const std::int64_t period = std::llround(1e9 / rate_hz_), start = now_ns() + period;
  for (std::int64_t k = 0; k < periods; ++k) {
    if (stop_requested_.load(std::memory_order_relaxed)) break;
    floor_period(start + k * period);
  }
}

bool HilRunner::advance(std::int64_t step) {
  if (link_) {
    if (link_->poll() && !take_command()) return false;
    apply_command();
  }
  status_ = sim_.step();
  if (!status_.ok()) return false;
  if (link_) link_->send_state(sim_.time(), sim_.q(), sim_.v());
  if (record_every_ > 0 && (step + 1) % record_every_ == 0) record_state();
  latest_state_.publish(step + 1, sim_.time(), sim_.q(), sim_.v());
  return true;
}

bool HilRunner::take_command() {
  int dof = -1;
  switch (limits_.judge(link_->command(), applied_command_, dof)) {
    case CommandLimits::Verdict::within:
    case CommandLimits::Verdict::saturated: has_applied_command_ = true; return true;
    case CommandLimits::Verdict::rejected: return true;
    case CommandLimits::Verdict::stop: out_of_range_dof_ = dof; return false;
  }
  return true;
}

void HilRunner::apply_command() {
  if (!has_applied_command_) return;
  // Applied every step, so a DOF released after the command arrived gets it too.
  for (int dof = 0; dof < sim_.model().nv; ++dof)  // dof is in range: never throws
    if (!sim_.model().is_prescribed(dof)) sim_.set_input(dof, applied_command_[dof]);
}

void HilRunner::record_state() {
  if (record_every_ == 0 || recorded_rows_ >= static_cast<std::int64_t>(recorded_time_.size())) return;
  const std::size_t row = static_cast<std::size_t>(recorded_rows_++);
  const std::size_t nq = static_cast<std::size_t>(sim_.model().nq), nv = static_cast<std::size_t>(sim_.model().nv);
  recorded_time_[row] = sim_.time();
  std::copy(sim_.q().data(), sim_.q().data() + nq, recorded_q_.begin() + static_cast<std::ptrdiff_t>(row * nq));
  std::copy(sim_.v().data(), sim_.v().data() + nv, recorded_v_.begin() + static_cast<std::ptrdiff_t>(row * nv));
}

HilSummary HilRunner::summary() const {
  HilSummary s;
  s.steps = steps_done();
  s.requested_steps = steps_;
  s.deadline_misses = deadline_misses();
  summarise_us(compute_ns_, s.steps, s.compute_p50_us, s.compute_p99_us, s.compute_p999_us, s.compute_max_us);
  double lateness_p999_us = 0;
  summarise_us(lateness_ns_, s.steps, s.lateness_p50_us, s.lateness_p99_us, lateness_p999_us, s.lateness_max_us);
  summarise_us(cpu_ns_, s.steps, s.cpu_p50_us, s.cpu_p99_us, s.cpu_p999_us, s.cpu_max_us);
  for (std::int64_t k = 0; k < s.steps; ++k) s.involuntary_switches += switches_[static_cast<std::size_t>(k)];
  s.preempted_steps = preempted_steps_;
  s.misses_preempted = misses_preempted_;
  s.preemption_margin_us = static_cast<double>(preemption_margin_ns_) * 1e-3;
  s.floor_interleaved = floor_mode_ == FloorMode::interleaved;
  s.warm_up = warm_up_ && spin_ns_ > 0 && !as_fast_as_possible_;
  s.wall_seconds = static_cast<double>(end_ns_ - start_ns_) * 1e-9;
  s.misses_compute_overrun = misses_compute_overrun_;
  s.misses_late_wakeup = misses_late_wakeup_;
  s.floor_periods = floor_done_;
  s.floor_target_us = static_cast<double>(floor_target_ns_) * 1e-3;
  summarise_us(floor_ns_, floor_done_, s.floor_p50_us, s.floor_p99_us, s.floor_p999_us, s.floor_max_us);
  s.dynamics_floor_evaluations = floor_evaluations_;
  summarise_us(dynamics_floor_ns_, floor_done_, s.dynamics_floor_p50_us, s.dynamics_floor_p99_us,
               s.dynamics_floor_p999_us, s.dynamics_floor_max_us);
  if (link_) {
    s.packets_received = link_->packets_received();
    s.packets_dropped = link_->packets_dropped();
    s.packets_sent = link_->packets_sent();
    s.packets_rejected_sender = link_->packets_rejected_sender();
    s.packets_stale = link_->packets_stale();
    s.kernel_drops = link_->kernel_drops();
    s.kernel_drops_counted = link_->kernel_drops_counted();
    s.send_failures = link_->send_failures();
    s.steps_left_pending = link_->polls_left_pending();
    s.max_packets_per_step = link_->max_packets_per_poll();
  }
  s.commands_saturated = limits_.saturated();
  s.commands_rejected = limits_.rejected();
  s.saturated_per_dof = limits_.saturated_per_dof();
  s.command_policy = limits_.policy();
  s.status = status_;
  s.failed_step = failed_step_;
  s.command_out_of_range_dof = out_of_range_dof_;
  s.exception_step = exception_step_;
  s.stopped = stopped_;
  s.as_fast_as_possible = as_fast_as_possible_;
  s.realtime_request = realtime_request_;
  s.realtime = realtime_outcome_;
  return s;
}

}  // namespace soadyn
