// What scheduled events cost a step: the cassini RK4 step at 1 ms (the
// turntable and gimbal driven, the scan platform and a wheel torqued), timed
// step by step in three cases:
//   - no events;
//   - a lock or a release of scan_az every 5 ms, all scheduled before the run
//     (the queue starts with one event per 5 ms of the run);
//   - 10^5 events scheduled after the end of the run (none ever due).
// The cases take turns in blocks of 500 steps, so phases of the machine's
// speed hit them alike. Output: a markdown table of the median and 90th
// percentile step time per case.
//
// Usage: bench_events [steps per case]   (default 20000)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>
#include "soadyn_scenes/scenes.hpp"
#include "soadyn/sim/simulator.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kDt = 1e-3;
constexpr long kFutureEvents = 100000;
constexpr int kBlock = 500;

struct Case {
  std::string label;
  std::unique_ptr<soadyn::Simulator> sim;
  std::vector<double> microseconds;
};

std::unique_ptr<soadyn::Simulator> cassini(int event_capacity) {
  auto sim = std::make_unique<soadyn::Simulator>(soadyn::cassini_model<double>(), kDt, soadyn::Integrator::rk4,
                                                 event_capacity);
  soadyn::drive_cassini(*sim);
  sim->set_input(sim->model().dof_index("scan_az"), 0.5);
  sim->set_input(sim->model().dof_index("wheel_1"), 0.1);
  return sim;
}

double percentile(std::vector<double> x, double p) {
  std::sort(x.begin(), x.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(x.size())));
  return x[std::min(std::max<std::size_t>(rank, 1), x.size()) - 1];
}

}  // namespace

int main(int argc, char** argv) {
  const long steps = argc > 1 ? std::atol(argv[1]) : 20000;
  if (steps < kBlock) {
    std::fprintf(stderr, "bench_events: need at least %d steps\n", kBlock);
    return 2;
  }
  const double horizon = kDt * static_cast<double>(steps);
  const long toggles = steps / 5;  // one event every 5 ms
  std::vector<Case> cases;
  cases.push_back({"no events", cassini(0), {}});
  cases.push_back({"lock/release every 5 ms", cassini(static_cast<int>(toggles + 1)), {}});
  cases.push_back({"1e5 future events", cassini(static_cast<int>(kFutureEvents)), {}});
  soadyn::Simulator& toggling = *cases[1].sim;
  const int scan_az = toggling.model().dof_index("scan_az");
  for (long k = 1; k <= toggles; ++k)
    toggling.schedule(5 * kDt * static_cast<double>(k), k % 2 ? soadyn::EventKind::lock : soadyn::EventKind::release,
                      scan_az);
  soadyn::Simulator& future = *cases[2].sim;
  for (long k = 0; k < kFutureEvents; ++k)  // in time order: scheduling cost is not what is measured
    future.schedule(horizon + 1.0 + 1e-3 * static_cast<double>(k), k % 2 ? soadyn::EventKind::lock
                                                                           : soadyn::EventKind::release, scan_az);
  for (Case& c : cases) c.microseconds.reserve(static_cast<std::size_t>(steps));
  bool ok = true;
  for (long done = 0; done < steps; done += kBlock)
    for (Case& c : cases)
      for (long k = done; k < std::min(steps, done + kBlock); ++k) {
        const Clock::time_point start = Clock::now();
        ok = c.sim->step().ok() && ok;
        c.microseconds.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
      }
  if (!ok) {
    std::fprintf(stderr, "bench_events: a step failed\n");
    return 1;
  }
  std::printf("cassini RK4 at %g ms, %ld steps per case\n\n", kDt * 1e3, steps);
  std::printf("| case | median step (us) | p90 step (us) | median / no events |\n|---|---:|---:|---:|\n");
  const double base = percentile(cases[0].microseconds, 0.5);
  for (const Case& c : cases) {
    const double median = percentile(c.microseconds, 0.5);
    std::printf("| %s | %.1f | %.1f | %.2f |\n", c.label.c_str(), median, percentile(c.microseconds, 0.9),
                median / base);
  }
  return 0;
}
