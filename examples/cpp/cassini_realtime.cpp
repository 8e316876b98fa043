// Steps the cassini scene at 1 kHz with RK4 in real time, without Python:
// step k may start at t0 + k ms and should end by t0 + (k + 1) ms on
// CLOCK_MONOTONIC; the loop sleeps to each absolute deadline (so a late step
// delays no later one), then prints how long the steps took and how many
// ended after their deadline. Usage: cassini_realtime [seconds]  (default 10)
#include <cstdio>
#include <cstdlib>

#include <soadyn_scenes/scenes.hpp>
#include <soadyn/sim/simulator.hpp>

#include "paced_clock.hpp"

namespace {
constexpr long period_ns = 1000000;  // 1 ms
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
  paced_clock::PacedRun run(steps, period_ns);  // allocated before the loop
  run.start();
  for (long k = 0; k < steps; ++k) {
    const soadyn::Status status = run.timed_step(k, [&] { return sim.step(); });
    if (!status.ok()) {
      std::printf("stopped at t = %.3f s: %s (DOF %d)\n", sim.time(), soadyn::status_message(status.code), status.index);
      return 1;
    }
  }
  std::printf("cassini: %ld steps of %.1f ms (RK4), simulated %.3f s, energy lost to the lock %.6f J\n", steps,
              dt * 1e3, sim.time(), sim.energy_lost());
  run.print_summary(steps);
  return 0;
}
