// Steps the cassini scene at 1 kHz with RK4 in real time, without Python:
// step k may start at t0 + k ms and should end by t0 + (k + 1) ms on
// CLOCK_MONOTONIC; the loop sleeps to each absolute deadline (so a late step
// delays no later one), then prints how long the steps took and how many
// ended after their deadline. Usage: cassini_realtime [seconds]  (default 10)
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <soadyn/scenes.hpp>
#include <soadyn/sim/simulator.hpp>

namespace {

constexpr long period_ns = 1000000;  // 1 ms

timespec now() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t;
}

timespec add_nanoseconds(timespec t, long ns) {
  const long total = t.tv_nsec + ns % 1000000000L;
  t.tv_sec += static_cast<time_t>(ns / 1000000000L + total / 1000000000L);
  t.tv_nsec = total % 1000000000L;
  return t;
}

double microseconds_between(const timespec& a, const timespec& b) {
  return static_cast<double>(b.tv_sec - a.tv_sec) * 1e6 + static_cast<double>(b.tv_nsec - a.tv_nsec) * 1e-3;
}

// Sleeps until the absolute time `deadline` (again after a signal).
void sleep_until(const timespec& deadline) {
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

double percentile(std::vector<double> sorted, double p) {
  std::sort(sorted.begin(), sorted.end());
  const std::size_t k = static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1));
  return sorted[k];
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const double dt = static_cast<double>(period_ns) * 1e-9;
  soadyn::Simulator sim(soadyn::cassini_model<double>(), dt, soadyn::Integrator::rk4);
  soadyn::drive_cassini(sim);  // turntable at 3 rpm
  const int scan_az = sim.model().dof_index("scan_az");
  sim.set_input(scan_az, 1.0);                              // slew the scan platform...
  sim.schedule(seconds / 2, soadyn::EventKind::lock, scan_az);  // ...and lock it halfway

  const long steps = static_cast<long>(seconds / dt + 0.5);
  std::vector<double> step_us(static_cast<std::size_t>(steps));  // allocated before the loop
  long late_steps = 0;
  double worst_lateness_us = 0.0;
  const timespec t0 = now();
  for (long k = 0; k < steps; ++k) {
    const timespec start = now();
    const soadyn::Status status = sim.step();
    const timespec end = now();
    if (!status.ok()) {
      std::printf("stopped at t = %.3f s: %s (DOF %d)\n", sim.time(), soadyn::status_message(status.code), status.index);
      return 1;
    }
    step_us[static_cast<std::size_t>(k)] = microseconds_between(start, end);
    const timespec deadline = add_nanoseconds(t0, (k + 1) * period_ns);
    const double lateness_us = microseconds_between(deadline, end);
    if (lateness_us > 0.0) {
      ++late_steps;
      worst_lateness_us = std::max(worst_lateness_us, lateness_us);
    } else {
      sleep_until(deadline);
    }
  }
  std::printf("cassini: %ld steps of %.1f ms (RK4), simulated %.3f s, energy lost to the lock %.6f J\n", steps,
              dt * 1e3, sim.time(), sim.energy_lost());
  std::printf("step time us: p50 %.2f  p99 %.2f  p99.9 %.2f  max %.2f\n", percentile(step_us, 0.5),
              percentile(step_us, 0.99), percentile(step_us, 0.999), *std::max_element(step_us.begin(), step_us.end()));
  std::printf("paced on CLOCK_MONOTONIC: wall %.3f s, %ld of %ld steps ended after their deadline (worst by %.1f us)\n",
              microseconds_between(t0, now()) * 1e-6, late_steps, steps, worst_lateness_us);
  return 0;
}
