// How much of a real-time step's tail is the machine's. Paced at 1 kHz like
// `soadyn hil --spin-us` (busy-waiting to each deadline), three fixed
// workloads are timed period by period:
//   - cassini RK4: Simulator::step, what the HIL loop computes;
//   - identical dynamics: four hybrid_dynamics calls on one fixed cassini
//     state, the same instructions and data every period (no state- or
//     data-dependent variation);
//   - arithmetic: eight independent multiply-add chains in registers, no
//     memory traffic, sized to the median of the identical dynamics.
// The workloads take turns in blocks of 500 periods, so phases of the
// machine's speed hit them alike. Then a census of the interruptions the
// thread suffers: for five seconds it only reads the clock, and every gap of
// 10 us or more between two readings is a time it did not run. Output:
// markdown tables on stdout.
//
// Usage: bench_step_spread [periods per workload]   (default 10000)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>
#include "soadyn_scenes/scenes.hpp"
#include "soadyn/sim/simulator.hpp"
#include "soadyn/soadyn.hpp"

namespace {

using Clock = std::chrono::steady_clock;

volatile double sink;

// `iterations` rounds of eight independent multiply-add chains.
__attribute__((noinline)) double arithmetic(long iterations) {
  double x[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  for (long i = 0; i < iterations; ++i)
    for (int k = 0; k < 8; ++k) x[k] = x[k] * 0.9999999 + 1e-9 * k;
  double sum = 0;
  for (double value : x) sum += value;
  return sum;
}

struct Workload {
  std::string label;
  std::function<void()> run;
  std::vector<double> microseconds;
};

double percentile(std::vector<double> x, double p) {
  std::sort(x.begin(), x.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(x.size())));
  return x[std::min(std::max<std::size_t>(rank, 1), x.size()) - 1];
}

// Runs `w` once per millisecond for `periods` periods, busy-waiting between.
void paced(Workload& w, int periods) {
  Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(1);
  for (int k = 0; k < periods; ++k) {
    while (Clock::now() < deadline) {
    }
    const Clock::time_point start = Clock::now();
    w.run();
    w.microseconds.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    deadline += std::chrono::milliseconds(1);
  }
}

// Gaps of at least 10 us between consecutive clock readings over `seconds`.
std::vector<double> interruption_census(double seconds) {
  std::vector<double> gaps;
  gaps.reserve(200000);
  const Clock::time_point start = Clock::now();
  Clock::time_point previous = start;
  while (previous - start < std::chrono::duration<double>(seconds)) {
    const Clock::time_point now = Clock::now();
    const double gap = std::chrono::duration<double, std::micro>(now - previous).count();
    if (gap >= 10.0) gaps.push_back(gap);
    previous = now;
  }
  return gaps;
}

void print_census(const std::vector<double>& gaps, double seconds, double step_p50_us) {
  const double edges[] = {10, 20, 50, 100, 1e300};
  std::printf("\n| interruptions per second | 10-20 us | 20-50 us | 50-100 us | >= 100 us | all |\n");
  std::printf("|---|---:|---:|---:|---:|---:|\n| thread reading the clock, %.0f s |", seconds);
  for (int b = 0; b < 4; ++b) {
    const auto n = std::count_if(gaps.begin(), gaps.end(), [&](double g) { return g >= edges[b] && g < edges[b + 1]; });
    std::printf(" %.0f |", static_cast<double>(n) / seconds);
  }
  std::printf(" %.0f |\n", static_cast<double>(gaps.size()) / seconds);
  const auto long_ones = std::count_if(gaps.begin(), gaps.end(), [](double g) { return g >= 20.0; });
  std::printf("\nA step of the cassini median (%.1f us) overlaps an interruption of 20 us or more\n"
              "with probability about %.2f %% (rate x duration); p99.9 looks at the worst 0.1 %%.\n",
              step_p50_us, 100.0 * static_cast<double>(long_ones) / seconds * step_p50_us * 1e-6);
}

}  // namespace

int main(int argc, char** argv) {
  const int periods = argc > 1 ? std::atoi(argv[1]) : 10000;
  if (periods < 1000) {
    std::fprintf(stderr, "bench_step_spread: need at least 1000 periods per workload\n");
    return 2;
  }
  soadyn::Simulator sim(soadyn::cassini_model<double>(), 1e-3, soadyn::Integrator::rk4);
  soadyn::drive_cassini(sim);
  const soadyn::Model model = soadyn::cassini_model<double>();
  soadyn::Data data(model);
  for (int k = 0; k < 500; ++k) sim.step();  // a moving state: rates, deflections
  const Eigen::VectorXd q = sim.q(), v = sim.v(), u = Eigen::VectorXd::Zero(model.nv);
  const auto four_calls = [&] {
    for (int k = 0; k < 4; ++k) soadyn::hybrid_dynamics(model, data, q, v, u);
  };

  // Size the arithmetic to the median of the identical dynamics.
  std::vector<double> calibration;
  for (int k = 0; k < 2000; ++k) {
    const Clock::time_point start = Clock::now();
    four_calls();
    calibration.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  const double target_us = percentile(calibration, 0.5);
  long iterations = 1000;
  for (int round = 0; round < 3; ++round) {
    std::vector<double> t;
    for (int k = 0; k < 200; ++k) {
      const Clock::time_point start = Clock::now();
      sink = arithmetic(iterations);
      t.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    }
    iterations = std::max(1L, std::lround(static_cast<double>(iterations) * target_us / percentile(t, 0.5)));
  }

  std::vector<Workload> workloads;
  workloads.push_back({"cassini RK4 step (Simulator::step)", [&] { sim.step(); }, {}});
  workloads.push_back({"identical dynamics: 4 x hybrid_dynamics, one fixed state", four_calls, {}});
  workloads.push_back({"arithmetic in registers, same median", [&] { sink = arithmetic(iterations); }, {}});
  for (int done = 0; done < periods; done += 500)
    for (Workload& w : workloads) paced(w, std::min(500, periods - done));

  std::printf("| workload | p50 (us) | p99 (us) | p99.9 (us) | max (us) | p99.9 / p50 |\n");
  std::printf("|---|---:|---:|---:|---:|---:|\n");
  for (const Workload& w : workloads) {
    const double p50 = percentile(w.microseconds, 0.5), p999 = percentile(w.microseconds, 0.999);
    std::printf("| %s | %.1f | %.1f | %.1f | %.1f | %.2f |\n", w.label.c_str(), p50, percentile(w.microseconds, 0.99),
                p999, percentile(w.microseconds, 1.0), p999 / p50);
  }
  const double census_seconds = 5.0;
  print_census(interruption_census(census_seconds), census_seconds, percentile(workloads[0].microseconds, 0.5));
  return 0;
}
