// The simulator's step never touches the heap: 10^5 steps of each built-in
// scene with every integrator's fixed-step loop, scheduled lock/release and
// prescribe events firing throughout, and immediate lock/release calls, with
// every allocation of the process counted (allocation_counter.cpp); then the
// HIL loop (HilRunner::run) over cassini, paced and as fast as possible, with
// real-time scheduling asked for (granted or not). Zero allocations, zero
// frees and every Status ok are required.
#include <cstdio>
#include <string>
#include "allocation_counter.hpp"
#include "soadyn/scenes.hpp"
#include "soadyn/sim/hil_runner.hpp"

using namespace soadyn_test;

namespace {

constexpr long kSteps = 100000;
constexpr int kEventEvery = 1000;  // steps between scheduled events

// Scheduled events (stored before the counter is armed): alternate lock and
// release of one DOF, plus a cycloidal prescribe near the end.
void schedule_events(soadyn::Simulator& sim, const char* dof_name) {
  const int dof = sim.model().dof_index(dof_name);
  const double dt = sim.dt();
  for (long k = 1; k * kEventEvery < kSteps - kEventEvery; ++k)
    sim.schedule(dt * static_cast<double>(k * kEventEvery), k % 2 ? soadyn::EventKind::lock : soadyn::EventKind::release,
                 dof);
  soadyn::Cycloidal<double> move;
  move.t0 = dt * static_cast<double>(kSteps - kEventEvery / 2);
  move.duration = 0.2;
  move.q1 = 0.3;
  sim.schedule_prescribe(move.t0, dof, move);
}

// Steps with counting armed; immediate lock/release in between.
AllocationCounts run_armed(soadyn::Simulator& sim, const char* dof_name, long& failed) {
  const int dof = sim.model().dof_index(dof_name);
  arm_counter();
  for (long k = 0; k < kSteps; ++k) {
    if (k % 7919 == 5000) failed += !sim.lock(dof).ok();
    if (k % 7919 == 5500) failed += !sim.release(dof).ok();
    failed += !sim.step().ok();
  }
  return disarm_counter();
}

// HilRunner::run with counting armed: `steps` steps of cassini at 10 kHz
// (paced, spinning the last 50 us) or as fast as possible, recording every
// 10th state, SCHED_FIFO, CPU pinning and memory locking requested.
bool hil_run_allocates_nothing(bool as_fast_as_possible, long steps) {
  soadyn::Simulator sim(soadyn::cassini_model<double>(), 1e-4, soadyn::Integrator::rk4);
  soadyn::drive_cassini(sim);
  soadyn::HilRunner runner(sim, 1e4, steps);
  runner.record_state_every(10);
  runner.set_as_fast_as_possible(as_fast_as_possible);
  runner.set_spin_ns(50000);
  runner.set_realtime(soadyn::RealtimeRequest{1, 0, true});
  arm_counter();
  const soadyn::Status status = runner.run();
  const AllocationCounts counts = disarm_counter();
  const soadyn::RealtimeOutcome& rt = runner.summary().realtime;
  std::printf("hil runner (%s): %ld steps, %ld allocations, %ld frees, status %s; SCHED_FIFO %s, CPU %s, memory %s\n",
              as_fast_as_possible ? "as fast as possible" : "paced", static_cast<long>(runner.steps_done()),
              counts.allocations(), counts.frees, status.ok() ? "ok" : "failed",
              rt.fifo_granted ? "granted" : "refused", rt.cpu_granted ? "pinned" : "refused",
              rt.memory_locked ? "locked" : "not locked");
  return counts.allocations() == 0 && counts.frees == 0 && status.ok() && runner.steps_done() == steps;
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_sim_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  bool pass = true;
  const soadyn::Integrator integrators[2] = {soadyn::Integrator::rk4, soadyn::Integrator::semi_implicit_euler};
  for (soadyn::Integrator integrator : integrators) {
    soadyn::Simulator cassini(soadyn::cassini_model<double>(), 1e-3, integrator, 256);
    soadyn::drive_cassini(cassini);
    cassini.set_input(cassini.model().dof_index("scan_az"), 0.5);
    cassini.set_input(cassini.model().dof_index("wheel_1"), 0.1);
    soadyn::Simulator chain(soadyn::pendulum_chain_model<double>(10), 1e-3, integrator, 256);
    chain.set_input(0, 0.2);
    struct Case {
      const char* name;
      soadyn::Simulator* sim;
      const char* dof;
    } cases[2] = {{"cassini", &cassini, "scan_az"}, {"pendulum-chain", &chain, "link_3"}};
    for (Case& c : cases) {
      schedule_events(*c.sim, c.dof);
      long failed = 0;
      const AllocationCounts counts = run_armed(*c.sim, c.dof, failed);
      const double lost = c.sim->energy_lost();
      std::printf("%s (%s): %ld steps, %ld allocations, %ld frees, %ld failed statuses, t = %.3f s, "
                  "energy lost to locks %.6g J\n",
                  c.name, integrator == soadyn::Integrator::rk4 ? "rk4" : "euler", kSteps, counts.allocations(),
                  counts.frees, failed, c.sim->time(), lost);
      pass = pass && counts.allocations() == 0 && counts.frees == 0 && failed == 0 && lost >= 0;
    }
  }
  for (const bool fast : {false, true}) pass = hil_run_allocates_nothing(fast, 20000) && pass;
  std::printf("test_sim_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
