// Fixed-rate pacing on CLOCK_MONOTONIC for the examples: step k may start at
// t0 + k periods and should end by t0 + (k + 1) periods; the loop sleeps to
// each absolute deadline, so a late step delays no later one.
#pragma once
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <vector>

namespace paced_clock {

inline timespec now() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t;
}

inline timespec add_nanoseconds(timespec t, long ns) {
  const long total = t.tv_nsec + ns % 1000000000L;
  t.tv_sec += static_cast<time_t>(ns / 1000000000L + total / 1000000000L);
  t.tv_nsec = total % 1000000000L;
  return t;
}

inline double microseconds_between(const timespec& a, const timespec& b) {
  return static_cast<double>(b.tv_sec - a.tv_sec) * 1e6 + static_cast<double>(b.tv_nsec - a.tv_nsec) * 1e-3;
}

// Sleeps until the absolute time `deadline` (again after a signal).
inline void sleep_until(const timespec& deadline) {
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

inline double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const std::size_t k = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
  return values[k];
}

// Step times and deadline misses of a paced run. Storage is allocated by the
// constructor, before the loop.
class PacedRun {
 public:
  PacedRun(long steps, long period_ns) : step_us_(static_cast<std::size_t>(steps)), period_ns_(period_ns) {}
  void start() { t0_ = now(); }
  // Records step k, which ran from `begin` to `end`, then sleeps to its deadline unless it is late.
  void finish_step(long k, const timespec& begin, const timespec& end) {
    step_us_[static_cast<std::size_t>(k)] = microseconds_between(begin, end);
    const timespec deadline = add_nanoseconds(t0_, (k + 1) * period_ns_);
    const double lateness_us = microseconds_between(deadline, end);
    if (lateness_us > 0.0) {
      ++late_steps_;
      worst_lateness_us_ = std::max(worst_lateness_us_, lateness_us);
    } else {
      sleep_until(deadline);
    }
  }
  // Runs step k (`step()`, whose result it returns), timed, then finish_step.
  template <class Step>
  auto timed_step(long k, Step&& step) {
    const timespec begin = now();
    auto result = step();
    finish_step(k, begin, now());
    return result;
  }
  const std::vector<double>& step_us() const { return step_us_; }
  long late_steps() const { return late_steps_; }
  double worst_lateness_us() const { return worst_lateness_us_; }
  double wall_seconds() const { return microseconds_between(t0_, now()) * 1e-6; }
  // Prints the step-time percentiles and the pacing summary of the run's `steps` steps.
  void print_summary(long steps) const {
    std::printf("step time us: p50 %.2f  p99 %.2f  p99.9 %.2f  max %.2f\n", percentile(step_us_, 0.5),
                percentile(step_us_, 0.99), percentile(step_us_, 0.999),
                *std::max_element(step_us_.begin(), step_us_.end()));
    std::printf("paced on CLOCK_MONOTONIC: wall %.3f s, %ld of %ld steps ended after their deadline (worst by %.1f us)\n",
                wall_seconds(), late_steps_, steps, worst_lateness_us_);
  }

 private:
  std::vector<double> step_us_;
  long period_ns_;
  timespec t0_{};
  long late_steps_ = 0;
  double worst_lateness_us_ = 0.0;
};

}  // namespace paced_clock
