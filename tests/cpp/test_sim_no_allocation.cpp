// The simulator's step never touches the heap: 10^5 steps of each built-in
// scene with every integrator's fixed-step loop, scheduled lock/release and
// prescribe events firing throughout, and immediate lock/release calls, with
// every allocation of the process counted (allocation_counter.cpp) and the
// divergence guard on (sim/divergence_guard.hpp: it must not trip); then
// the failures a step reports (a source returning NaN, dopri5 at its sub-step
// bound) and a queue of 10^5 pending events; then the HIL loop
// (HilRunner::run) over cassini, paced and as fast as possible, with
// real-time scheduling asked for (granted or not), the machine's floors (arithmetic and dynamics) timed
// after a paced run at 10 kHz and interleaved in the spin windows of one at
// 2 kHz (the caches warmed before each deadline), and another thread reading
// the published state throughout; the state snapshot's sequence lock under
// 10^6 publications against a concurrent reader (no torn copy); then the HIL loop over the
// UDP link under hostile traffic (udp_link.hpp, command_limits.hpp): a flood
// queued before the run (kernel drops, the per-step read bound) and, during
// it, valid commands mixed with 1e30 torques (clamped or rejected), commands
// from another socket, stale sequence numbers and malformed datagrams; and
// the stop policy ending the run at the first 1e30 command. Zero allocations,
// zero frees, every Status ok and every counter seen moving are required
// (but kernel drops, which depend on the host's socket buffer size: the
// drop-counting read runs either way).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>
#include "allocation_counter.hpp"
#include "soadyn_scenes/scenes.hpp"
#include "soadyn/realtime/hil_runner.hpp"
#include "soadyn/realtime/state_snapshot.hpp"

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

// Reads the runner's latest state on another thread while the loop runs (a
// viewer's part): allocation-free reads, each a consistent state (its time is
// its step's, q and v finite), steps never going back.
class SnapshotReader {
 public:
  explicit SnapshotReader(const soadyn::HilRunner& runner)
      : runner_(runner), q_(runner.simulator().model().nq), v_(runner.simulator().model().nv) {}
  void start() { thread_ = std::thread([this] { loop(); }); }
  void stop() {
    done_.store(true);
    thread_.join();
  }
  long reads = 0, inconsistent = 0;
  std::int64_t last_step = -1;

 private:
  void loop() {
    const double dt = runner_.simulator().dt();
    while (!done_.load()) {
      std::int64_t step = 0;
      double time = 0;
      if (!runner_.latest_state().read(step, time, q_, v_)) continue;
      ++reads;
      if (step < last_step || std::abs(time - static_cast<double>(step) * dt) > 1e-9 || !q_.allFinite() || !v_.allFinite()) ++inconsistent;
      last_step = step;
    }
  }
  const soadyn::HilRunner& runner_;
  Eigen::VectorXd q_, v_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// HilRunner::run with counting armed: `steps` steps of cassini at `rate`
// (paced, spinning the last `spin_us`, the floor timed as `floor` says) or as
// fast as possible, recording every 10th state, SCHED_FIFO, CPU pinning and
// memory locking requested, while a SnapshotReader reads the published states.
bool hil_run_allocates_nothing(bool as_fast_as_possible, long steps, double rate, std::int64_t spin_us,
                               soadyn::FloorMode floor) {
  soadyn::Simulator sim(soadyn::cassini_model<double>(), 1e-4, soadyn::Integrator::rk4);
  soadyn::drive_cassini(sim);
  soadyn::HilRunner runner(sim, rate, steps);
  runner.record_state_every(10);
  runner.set_as_fast_as_possible(as_fast_as_possible);
  runner.set_spin_ns(spin_us * 1000);
  runner.set_realtime(soadyn::RealtimeRequest{1, 0, true});
  runner.set_floor_periods(steps / 4);  // the machine's floor, in run() too
  runner.set_floor_mode(floor);
  SnapshotReader reader(runner);
  reader.start();  // allocates its thread before the counter is armed
  arm_counter();
  const soadyn::Status status = runner.run();
  const AllocationCounts counts = disarm_counter();
  reader.stop();
  std::int64_t final_step = -1;
  double final_time = 0;
  Eigen::VectorXd q(sim.model().nq), v(sim.model().nv);
  const bool final_read = runner.latest_state().read(final_step, final_time, q, v);
  const bool final_state = final_read && final_step == steps && final_time == sim.time() && q == sim.q() && v == sim.v();
  const soadyn::RealtimeOutcome& rt = runner.summary().realtime;
  std::printf("hil runner (%s, %g Hz, floor %s): %ld steps, %ld allocations, %ld frees, status %s; SCHED_FIFO %s, "
              "CPU %s, memory %s; snapshots read by another thread %ld, inconsistent %ld, last snapshot %s; floor "
              "periods %ld\n",
              as_fast_as_possible ? "as fast as possible" : "paced", rate,
              floor == soadyn::FloorMode::interleaved ? "interleaved" : "after the run",
              static_cast<long>(runner.steps_done()),
              counts.allocations(), counts.frees, status.ok() ? "ok" : "failed",
              rt.fifo_granted ? "granted" : "refused", rt.cpu_granted ? "pinned" : "refused",
              rt.memory_locked ? "locked" : "not locked", reader.reads, reader.inconsistent,
              final_state ? "the final state" : "wrong", static_cast<long>(runner.floor_done()));
  return counts.allocations() == 0 && counts.frees == 0 && status.ok() && runner.steps_done() == steps &&
         reader.reads > 0 && reader.inconsistent == 0 && final_state &&
         runner.floor_done() == (as_fast_as_possible ? 0 : steps / 4) &&
         std::all_of(runner.dynamics_floor_ns().begin(), runner.dynamics_floor_ns().begin() + runner.floor_done(),
                     [](std::int64_t ns) { return ns > 0; });
}

// The sequence lock itself under contention: a writer publishes 10^6 states
// whose every value is its step number while a reader copies as fast as it
// can; a copy mixing two states (a torn read) is counted. Nothing allocates.
bool snapshot_reads_are_never_torn() {
  constexpr int nq = 40, nv = 39;
  constexpr std::int64_t kPublished = 1000000;
  soadyn::StateSnapshot snapshot(nq, nv);
  Eigen::VectorXd wq(nq), wv(nv), rq(nq), rv(nv);
  std::atomic<bool> writing{true};
  long reads = 0, torn = 0, failed_reads = 0;
  std::thread reader_thread([&] {  // started (allocated) before the counter is armed
    while (writing.load()) {
      std::int64_t step = 0;
      double time = 0;
      if (!snapshot.read(step, time, rq, rv, 8)) {
        ++failed_reads;
        continue;
      }
      ++reads;
      const double k = static_cast<double>(step);
      if (time != k || (rq.array() != k).any() || (rv.array() != -k).any()) ++torn;
    }
  });
  arm_counter();
  for (std::int64_t k = 1; k <= kPublished; ++k) {
    wq.setConstant(static_cast<double>(k));
    wv.setConstant(-static_cast<double>(k));
    snapshot.publish(k, static_cast<double>(k), wq, wv);
  }
  const AllocationCounts counts = disarm_counter();
  writing.store(false);
  reader_thread.join();
  std::printf("state snapshot: %ld published, %ld read by another thread, %ld torn, %ld reads given up, "
              "%ld allocations, %ld frees\n",
              static_cast<long>(snapshot.published()), reads, torn, failed_reads, counts.allocations(), counts.frees);
  return snapshot.published() == kPublished && reads > 0 && torn == 0 && counts.allocations() == 0 &&
         counts.frees == 0;
}

// Failures are Statuses and cost no allocation either: a C++ source that
// turns NaN (each later step fails and restores the state), dopri5 at its
// sub-step bound, and steps past a queue of 10^5 pending events.
bool failures_and_full_queues_allocate_nothing() {
  using soadyn::Integrator;
  using soadyn::StatusCode;
  soadyn::Simulator sourced(soadyn::pendulum_chain_model<double>(4), 1e-3, Integrator::rk4, 0);
  sourced.prescribe(1, soadyn::CallbackSource<double>{[](double t) {
                      return soadyn::MotionSample<double>{t < 0.0105 ? 0.1 * t : NAN, 0.1, 0.0};
                    }});
  soadyn::Simulator bounded(soadyn::pendulum_chain_model<double>(5), 0.5, Integrator::dopri5, 0);
  bounded.rtol = 1e-13;
  bounded.atol = 1e-15;
  bounded.max_substeps = 10;
  bounded.set_state(Eigen::VectorXd::Constant(5, 0.4), Eigen::VectorXd::Zero(5));
  constexpr long kFuture = 100000;
  soadyn::Simulator queued(soadyn::pendulum_chain_model<double>(4), 1e-3, Integrator::rk4, kFuture);
  for (long k = 0; k < kFuture; ++k) queued.schedule(10.0 + 1e-3 * static_cast<double>(k), soadyn::EventKind::lock, 2);
  long source_failures = 0, bound_failures = 0, failed = 0;
  arm_counter();
  for (int k = 0; k < 1000; ++k) {
    const soadyn::Status s = sourced.step();
    source_failures += s.code == StatusCode::non_finite_source && s.index == 1;
  }
  for (int k = 0; k < 20; ++k) bound_failures += bounded.step().code == StatusCode::substep_limit;
  for (int k = 0; k < 5000; ++k) failed += !queued.step().ok();
  const AllocationCounts counts = disarm_counter();
  const bool restored = sourced.steps_taken() == 10 && sourced.q().allFinite() && bounded.time() == 0.0;
  std::printf("failures: %ld source and %ld sub-step-bound statuses, %ld failed steps past %ld pending events, "
              "%ld allocations, %ld frees, state %s\n",
              source_failures, bound_failures, failed, static_cast<long>(queued.pending_events()),
              counts.allocations(), counts.frees, restored ? "restored" : "NOT restored");
  return counts.allocations() == 0 && counts.frees == 0 && source_failures == 990 && bound_failures == 20 &&
         failed == 0 && queued.pending_events() == static_cast<std::size_t>(kFuture) && restored;
}

// A loopback UDP socket on a free port, for the controller and the intruder.
struct LoopbackSocket {
  int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in address{};
  LoopbackSocket() {
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    ::bind(fd, reinterpret_cast<sockaddr*>(&address), length);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  }
  ~LoopbackSocket() { ::close(fd); }
  int port() const { return ntohs(address.sin_port); }
  void send(const std::vector<unsigned char>& packet, int port) const {
    sockaddr_in to = address;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    ::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  }
};

// A command datagram (udp_link.hpp's format), built before the counter is armed.
std::vector<unsigned char> command_packet(std::uint32_t sequence, int nv, double torque) {
  std::vector<unsigned char> p(soadyn::udp_packet::bytes_for(static_cast<std::size_t>(nv)));
  auto put = [&p](std::size_t at, std::uint64_t x, int bytes) {
    for (int k = 0; k < bytes; ++k) p[at + static_cast<std::size_t>(k)] = static_cast<unsigned char>(x >> (8 * k));
  };
  auto put_f64 = [&put](std::size_t at, double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    put(at, bits, 8);
  };
  std::memcpy(p.data(), soadyn::udp_packet::magic, 4);
  put(4, soadyn::udp_packet::version, 2);
  put(6, soadyn::udp_packet::kind_command, 2);
  put(8, sequence, 4);
  put(12, static_cast<std::uint64_t>(nv), 4);
  put_f64(16, 0.0);
  for (int k = 0; k < nv; ++k) put_f64(soadyn::udp_packet::header_bytes + 8 * static_cast<std::size_t>(k), torque);
  return p;
}

// HilRunner::run over the link with counting armed (see the file comment).
bool hil_link_allocates_nothing(soadyn::CommandPolicy policy) {
  constexpr long kSteps = 20000;
  constexpr std::uint32_t kCommands = 4000, kFlood = 5000;
  soadyn::Simulator sim(soadyn::pendulum_chain_model<double>(3), 1e-4, soadyn::Integrator::rk4);
  const int nq = sim.model().nq, nv = sim.model().nv;
  LoopbackSocket controller, intruder;
  soadyn::UdpLink link(nq, nv, 0, controller.port());  // commands only from the controller
  soadyn::HilRunner runner(sim, 1e4, kSteps, &link);
  runner.set_command_limits(Eigen::VectorXd::Constant(nv, 2.0));
  runner.set_command_policy(policy);
  runner.set_spin_ns(50000);
  std::vector<std::vector<unsigned char>> valid, huge;
  for (std::uint32_t k = 0; k < kCommands; ++k) {
    valid.push_back(command_packet(kFlood + 2 * k + 1, nv, 0.5));
    huge.push_back(command_packet(kFlood + 2 * k + 2, nv, 1e30));
  }
  const std::vector<unsigned char> stale = command_packet(1, nv, 0.1);
  std::vector<unsigned char> malformed = command_packet(0, nv, 0.1);
  malformed[0] = 'X';
  const std::vector<unsigned char> flood = command_packet(kFlood, nv, 0.0);
  for (std::uint32_t k = 0; k < kFlood; ++k) controller.send(flood, link.port());  // more than the buffer holds
  std::atomic<bool> go{false}, release{false};
  // Allocates nothing once started; it ends only after the counter is
  // disarmed, since std::thread frees its state when its function returns.
  std::thread sender([&] {
    while (!go.load()) {
    }
    for (std::uint32_t k = 0; k < kCommands; ++k) {
      controller.send(valid[k], link.port());
      if (k % 10 == 0) controller.send(huge[k], link.port());
      if (k % 7 == 0) intruder.send(valid[k], link.port());
      if (k % 13 == 0) controller.send(stale, link.port());
      if (k % 17 == 0) controller.send(malformed, link.port());
      ::usleep(200);
    }
    while (!release.load()) ::usleep(1000);
  });
  arm_counter();
  go.store(true);
  const soadyn::Status status = runner.run();
  const AllocationCounts counts = disarm_counter();
  release.store(true);
  sender.join();
  const soadyn::HilSummary s = runner.summary();
  const bool clamp = policy == soadyn::CommandPolicy::clamp;
  const bool finite = sim.q().allFinite() && sim.v().allFinite();
  if (policy == soadyn::CommandPolicy::stop) {  // the first 1e30 command ends the run, naming DOF 0
    std::printf("hil runner over UDP (stop): %ld allocations, %ld frees, stopped at step %ld of %ld by DOF %d\n",
                counts.allocations(), counts.frees, static_cast<long>(s.failed_step), kSteps,
                s.command_out_of_range_dof);
    return counts.allocations() == 0 && counts.frees == 0 && status.ok() && s.command_out_of_range_dof == 0 &&
           s.failed_step == s.steps && s.steps < kSteps && finite;
  }
  std::printf("hil runner over UDP (%s): %ld steps, %ld allocations, %ld frees, status %s; received %lu, malformed "
              "%lu, other sender %lu, stale %lu, kernel drops %lu, steps at the read bound %lu, saturated %lu, "
              "rejected %lu, sent %lu, send failures %lu\n",
              soadyn::command_policy_name(policy), static_cast<long>(s.steps), counts.allocations(), counts.frees,
              status.ok() ? "ok" : "failed", static_cast<unsigned long>(s.packets_received),
              static_cast<unsigned long>(s.packets_dropped), static_cast<unsigned long>(s.packets_rejected_sender),
              static_cast<unsigned long>(s.packets_stale), static_cast<unsigned long>(s.kernel_drops),
              static_cast<unsigned long>(s.steps_left_pending), static_cast<unsigned long>(s.commands_saturated),
              static_cast<unsigned long>(s.commands_rejected), static_cast<unsigned long>(s.packets_sent),
              static_cast<unsigned long>(s.send_failures));
  return counts.allocations() == 0 && counts.frees == 0 && status.ok() && s.steps == kSteps && finite &&
         s.packets_received > 0 && s.packets_dropped > 0 && s.packets_rejected_sender > 0 && s.packets_stale > 0 &&
         s.steps_left_pending > 0 && (clamp ? s.commands_saturated : s.commands_rejected) > 0 &&
         (clamp ? s.commands_rejected : s.commands_saturated) == 0 && s.packets_sent + s.send_failures == kSteps;
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
    // A wheel's lock and release move its constant P+ out of and into the
    // bus's starting sum (Model::refresh_leaf_presums), and its P into it.
    soadyn::Simulator wheel_locks(soadyn::cassini_model<double>(), 1e-3, integrator, 256);
    soadyn::drive_cassini(wheel_locks);
    wheel_locks.set_input(wheel_locks.model().dof_index("wheel_2"), 0.1);
    soadyn::Simulator chain(soadyn::pendulum_chain_model<double>(10), 1e-3, integrator, 256);
    chain.set_input(0, 0.2);
    struct Case {
      const char* name;
      soadyn::Simulator* sim;
      const char* dof;
    } cases[3] = {{"cassini", &cassini, "scan_az"}, {"cassini (wheel locks)", &wheel_locks, "wheel_2"},
                  {"pendulum-chain", &chain, "link_3"}};
    for (Case& c : cases) {
      schedule_events(*c.sim, c.dof);
      c.sim->set_divergence_guard(true);  // its energy checks allocate nothing and never trip on these runs
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
  pass = failures_and_full_queues_allocate_nothing() && pass;
  pass = hil_run_allocates_nothing(false, 20000, 1e4, 50, soadyn::FloorMode::after_run) && pass;
  pass = hil_run_allocates_nothing(true, 20000, 1e4, 50, soadyn::FloorMode::after_run) && pass;
  pass = hil_run_allocates_nothing(false, 4000, 2e3, 200, soadyn::FloorMode::interleaved) && pass;
  pass = snapshot_reads_are_never_torn() && pass;
  for (const auto policy : {soadyn::CommandPolicy::clamp, soadyn::CommandPolicy::reject, soadyn::CommandPolicy::stop})
    pass = hil_link_allocates_nothing(policy) && pass;
  std::printf("test_sim_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
