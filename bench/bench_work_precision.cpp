// Run time against error: each scene simulated for kHorizon seconds with every
// integrator, several step sizes (Dormand-Prince: several tolerances at a
// 20 ms output step, so that its error control chooses the sub-steps), in
// double and float; error = largest coordinate error at the end against a
// Dormand-Prince run in double (0.1 ms output step, rtol 1e-13); cost =
// CPU seconds per simulated second (the median of kRepeats runs).
//
// Scenes: cassini (turntable at 3 rpm and the gimbal under velocity
// control, the scan platform and a wheel torqued, flexible booms), a
// 10-link pendulum chain released from a bent pose, and a 7-DOF arm under
// constant joint torques and gravity.
//
// Energy drift: (E(end) - E(0)) / (E(0) - E(rest)), total energy relative to
// the swing energy, for the pendulum chain, the one conservative scene (the
// others are driven or torqued); -nan elsewhere. Then, after the CSV, the
// drift of each integrator over 100 s at 1 ms on the chain, sampled every
// 10 s (lines starting with '#drift,').
//
// Output: CSV on stdout, one row per run:
//   scene,integrator,scalar,dt,rtol,error,cpu_s_per_sim_s,energy_drift
// bench/bench_work_precision.py plots it and writes the tables.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>
#include "random_tree.hpp"  // tests/cpp: the 7-DOF arm spec shared with bench_core
#include "soadyn/algorithms/energy.hpp"
#include "soadyn_scenes/scenes.hpp"

namespace {

constexpr double kHorizon = 1.0;  // simulated seconds
constexpr int kRepeats = 3;

template <class S>
using Setup = std::function<void(soadyn::SimulatorTpl<S>&)>;

// A scene: its model and the drives/inputs/initial state of its simulator.
template <class S>
struct Scene {
  std::string name;
  soadyn::ModelTpl<S> model;
  Setup<S> setup;
};

template <class S>
std::vector<Scene<S>> scenes() {
  std::vector<Scene<S>> out;
  out.push_back({"cassini", soadyn::cassini_model<S>(), [](soadyn::SimulatorTpl<S>& sim) {
                   soadyn::drive_cassini(sim);
                   sim.set_input(sim.model().dof_index("scan_az"), S(2));
                   sim.set_input(sim.model().dof_index("wheel_1"), S(0.2));
                 }});
  out.push_back({"pendulum-chain", soadyn::pendulum_chain_model<S>(10), [](soadyn::SimulatorTpl<S>& sim) {
                   soadyn::VecX<S> q = soadyn::VecX<S>::Constant(sim.model().nq, S(0.3));
                   sim.set_state(q, soadyn::VecX<S>::Zero(sim.model().nv));
                 }});
  out.push_back({"7-DOF arm", soadyn_test::build_model<S>(soadyn_test::seven_dof_arm_spec()), [](soadyn::SimulatorTpl<S>& sim) {
                   for (int k = 0; k < sim.model().nv; ++k) sim.set_input(k, S(0.5) * S(k % 3 - 1));
                   soadyn::VecX<S> q = soadyn::VecX<S>::Constant(sim.model().nq, S(0.2));
                   sim.set_state(q, soadyn::VecX<S>::Zero(sim.model().nv));
                 }});
  return out;
}

struct Run {
  Eigen::VectorXd q;
  double seconds = 0;
  bool ok = true;
  double energy_drift = NAN;
};

// Total energy (kinetic + potential) of the simulator's state.
template <class S>
double total_energy(soadyn::SimulatorTpl<S>& sim) {
  return static_cast<double>(soadyn::kinetic_energy<S>(sim.model(), sim.data(), sim.q(), sim.v()) +
                             soadyn::potential_energy<S>(sim.model(), sim.data(), sim.q()));
}

// The energy the chain's pose holds above rest: the scale of its drift.
template <class S>
double swing_energy(soadyn::SimulatorTpl<S>& sim) {
  const soadyn::VecX<S> rest = soadyn::VecX<S>::Zero(sim.model().nq);
  return total_energy(sim) -
         static_cast<double>(soadyn::potential_energy<S>(sim.model(), sim.data(), rest));
}

template <class S>
Run simulate(const Scene<S>& scene, soadyn::Integrator integrator, double dt, double rtol) {
  soadyn::SimulatorTpl<S> sim(scene.model, S(dt), integrator, 16);
  sim.rtol = S(rtol);
  sim.atol = S(rtol * 1e-2);
  scene.setup(sim);
  sim.max_substeps = 1000000;  // the reference's 0.1 ms steps at rtol 1e-13 take many
  const long steps = std::lround(kHorizon / dt);
  Run run;
  const bool conservative = scene.name == "pendulum-chain";
  const double e0 = conservative ? total_energy(sim) : 0.0, swing = conservative ? swing_energy(sim) : 1.0;
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < steps && run.ok; ++k) run.ok = sim.step().ok();
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.q = sim.q().template cast<double>();
  if (conservative) run.energy_drift = (total_energy(sim) - e0) / swing;
  return run;
}

const char* integrator_name(soadyn::Integrator i) {
  switch (i) {
    case soadyn::Integrator::semi_implicit_euler: return "euler";
    case soadyn::Integrator::rk4: return "rk4";
    default: return "dopri5";
  }
}

template <class S>
void sweep(const char* scalar, const std::vector<Eigen::VectorXd>& references) {
  const std::vector<Scene<S>> all = scenes<S>();
  const double fixed_steps[] = {1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4};
  const double tolerances[] = {1e-4, 1e-6, 1e-8, 1e-10};
  for (std::size_t s = 0; s < all.size(); ++s) {
    auto emit = [&](soadyn::Integrator integrator, double dt, double rtol) {
      std::vector<double> times;
      Run run;
      for (int r = 0; r < kRepeats; ++r) {
        run = simulate(all[s], integrator, dt, rtol);
        times.push_back(run.seconds);
      }
      std::sort(times.begin(), times.end());
      const double error = run.ok && run.q.allFinite() ? (run.q - references[s]).cwiseAbs().maxCoeff() : INFINITY;
      std::printf("%s,%s,%s,%g,%g,%.6e,%.6e,%.3e\n", all[s].name.c_str(), integrator_name(integrator), scalar, dt,
                  integrator == soadyn::Integrator::dopri5 ? rtol : 0.0, error, times[kRepeats / 2] / kHorizon,
                  run.energy_drift);
      std::fflush(stdout);
    };
    for (double dt : fixed_steps) {
      emit(soadyn::Integrator::semi_implicit_euler, dt, 0);
      emit(soadyn::Integrator::rk4, dt, 0);
    }
    // float cannot meet tolerances below its rounding
    for (double rtol : tolerances)
      if (std::is_same_v<S, double> || rtol >= 1e-6) emit(soadyn::Integrator::dopri5, 0.02, rtol);
  }
}

// The 10-link chain for 100 s at 1 ms (dopri5: 1 ms output steps, rtol
// 1e-10), double: the relative energy drift every 10 s.
void long_drift() {
  const Scene<double> chain = scenes<double>()[1];
  for (soadyn::Integrator integrator :
       {soadyn::Integrator::semi_implicit_euler, soadyn::Integrator::rk4, soadyn::Integrator::dopri5}) {
    soadyn::Simulator sim(chain.model, 1e-3, integrator, 0);
    chain.setup(sim);
    const double e0 = total_energy(sim), swing = swing_energy(sim);
    std::printf("#drift,%s", integrator_name(integrator));
    for (int block = 0; block < 10; ++block) {
      for (int k = 0; k < 10000; ++k)
        if (!sim.step().ok()) return;
      std::printf(",%.3e", (total_energy(sim) - e0) / swing);
    }
    std::printf("\n");
  }
}

}  // namespace

int main() {
  std::vector<Eigen::VectorXd> references;
  for (const Scene<double>& scene : scenes<double>())
    references.push_back(simulate(scene, soadyn::Integrator::dopri5, 1e-4, 1e-13).q);
  std::printf("scene,integrator,scalar,dt,rtol,error,cpu_s_per_sim_s,energy_drift\n");
  sweep<double>("double", references);
  sweep<float>("float", references);
  long_drift();
  return 0;
}
