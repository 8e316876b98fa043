// Steps the cassini scene for 10 s at 1 kHz with RK4, without Python, and
// prints how long each step took. Usage: cassini_realtime [seconds]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <soadyn/scenes.hpp>
#include <soadyn/sim/simulator.hpp>

namespace {

double percentile(std::vector<double> sorted, double p) {
  std::sort(sorted.begin(), sorted.end());
  const std::size_t k = static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1));
  return sorted[k];
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const double dt = 1e-3;
  soadyn::Simulator sim(soadyn::cassini_model<double>(), dt, soadyn::Integrator::rk4);
  soadyn::drive_cassini(sim);  // turntable at 3 rpm
  const int scan_az = sim.model().dof_index("scan_az");
  sim.set_input(scan_az, 1.0);                              // slew the scan platform...
  sim.schedule(seconds / 2, soadyn::EventKind::lock, scan_az);  // ...and lock it halfway

  const long steps = static_cast<long>(seconds / dt + 0.5);
  std::vector<double> step_us(static_cast<std::size_t>(steps));  // allocated before the loop
  for (long k = 0; k < steps; ++k) {
    const auto start = std::chrono::steady_clock::now();
    const soadyn::Status status = sim.step();
    step_us[static_cast<std::size_t>(k)] =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    if (!status.ok()) {
      std::printf("stopped at t = %.3f s: %s (DOF %d)\n", sim.time(), soadyn::status_message(status.code), status.index);
      return 1;
    }
  }
  std::printf("cassini: %ld steps of %.1f ms (RK4), simulated %.3f s, energy lost to the lock %.6f J\n", steps,
              dt * 1e3, sim.time(), sim.energy_lost());
  std::printf("step time us: p50 %.2f  p99 %.2f  p99.9 %.2f  max %.2f\n", percentile(step_us, 0.5),
              percentile(step_us, 0.99), percentile(step_us, 0.999), *std::max_element(step_us.begin(), step_us.end()));
  return 0;
}
