// A closed-loop mechanism stepped in real time without Python: the planar
// crank-rocker four-bar of Saha, Shah & Nandihal (Mechanical Sciences 4,
// 2013, Fig. 16), the built-in scene soadyn::four_bar_model (a tree of three
// hinges closed by one revolute cut: examples/soadyn_scenes/scenes.cpp shows the add_body
// and add_loop calls), assembled at crank angle 0 from a rough guess, then
// stepped at 1 kHz with RK4: the crank driven at 1 rev/s for the first half
// (its drive torque is the actuator force of the closed chain), then released
// to swing under gravity. After every step the simulator projects the state
// back onto the closure (Simulator: loop_tolerance). Prints the crank torque
// range, the loop drift RK4 left before the projections, the closure at the
// end and the step times. Usage: four_bar_realtime [seconds]  (default 4)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <soadyn_scenes/scenes.hpp>
#include <soadyn/soadyn.hpp>

#include "paced_clock.hpp"

namespace {

constexpr long period_ns = 1000000;  // 1 ms
constexpr double kPi = 3.14159265358979323846;

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 4.0;
  const soadyn::Model model = soadyn::four_bar_model<double>();

  // Assembly (setup, may allocate): crank at 0 held, coupler and rocker from a rough guess.
  soadyn::Data data(model);
  Eigen::VectorXd q(3), v = Eigen::VectorXd::Zero(3), free = Eigen::VectorXd::Ones(3);
  q << 0.0, 1.0, 1.9;
  free[0] = 0.0;
  const double rate = 2 * kPi;  // rad/s
  v[0] = rate;
  if (!soadyn::assemble_loops(model, data, q, free, 1e-12, 50).ok() ||
      !soadyn::project_loop_velocity(model, data, q, v, free).ok()) {
    std::printf("the four-bar does not assemble\n");
    return 1;
  }
  const double dt = static_cast<double>(period_ns) * 1e-9;
  soadyn::Simulator sim(model, dt, soadyn::Integrator::rk4);
  sim.set_state(q, v);
  soadyn::ConstantAcceleration<double> drive;
  drive.v0 = rate;
  sim.prescribe(0, drive);
  sim.schedule(seconds / 2, soadyn::EventKind::release, 0);

  const long steps = static_cast<long>(seconds / dt + 0.5);
  paced_clock::PacedRun run(steps, period_ns);  // allocated before the loop
  double torque_min = 0.0, torque_max = 0.0;
  run.start();
  for (long k = 0; k < steps; ++k) {
    const soadyn::Status status = run.timed_step(k, [&] { return sim.step(); });
    if (!status.ok()) {
      std::printf("stopped at t = %.3f s: %s\n", sim.time(), sim.describe(status).c_str());
      return 1;
    }
    if (sim.model().is_prescribed(0)) {
      torque_min = std::min(torque_min, sim.forces()[0]);
      torque_max = std::max(torque_max, sim.forces()[0]);
    }
  }
  soadyn::loop_residual(sim.model(), data, sim.q(), sim.v().data());
  std::printf("four-bar: %ld steps of %.1f ms (RK4), simulated %.3f s, crank torque while driven %.4f .. %.4f N m\n",
              steps, dt * 1e3, sim.time(), torque_min, torque_max);
  std::printf("loop drift before projection: max %.1e m, %.1e m/s; closure at the end %.1e m, %.1e m/s\n",
              sim.max_loop_drift_position(), sim.max_loop_drift_velocity(),
              data.loops.residual.lpNorm<Eigen::Infinity>(), data.loops.velocity_residual.lpNorm<Eigen::Infinity>());
  run.print_summary(steps);
  return 0;
}
