// The parallel layer as a C++ user links it (soadyn::realtime):
//   - BatchDynamics: forward, inverse and hybrid dynamics, the mass matrix and
//     the derivatives of 64 states, with 1, 2 and 3 threads, one row per pass
//     and the widest packets, equal bit for bit to the single calls on a
//     random 20-body tree (every joint type, external wrenches, a mixed mask),
//     on the same tree with flexible bodies and on cassini, whose two booms
//     are flexible appendages (their update run lane by lane; the
//     dual-number derivatives, one row per pass whatever the lanes). Four rows per pass, a rigid model's mass matrix is the
//     baseline kernel's, bit for bit. After their
//     first call, the five calls allocate nothing on either model, on one and
//     two threads, while the model's values and prescribed flags change
//     between them. Without lane models named, a flexible appendage's update
//     on packets splits the packet;
//   - rollout: 6 pendulum-chain runs with per-run torques, masses and lock
//     times, with 1 and 2 threads, equal bit for bit to one Simulator per run;
//     a refused parameter and an overflowing step reported per run;
//   - ThreadPool: an exception thrown in a chunk comes back to the caller
//     once every thread is idle, and the pool still works after it; loops
//     back to back and after pauses (workers spinning or asleep) visit each
//     index once.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/packet_kernels.hpp"
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/parallel/batch_dynamics.hpp"
#include "soadyn/parallel/rollout.hpp"
#include "soadyn/model/parameters.hpp"
#include "soadyn_scenes/scenes.hpp"
#include "soadyn/soadyn.hpp"

namespace {

using Rows = std::vector<double>;

struct Batch {
  int n = 0;
  Rows Q, V, U, F;
};

Batch random_batch(const soadyn::Model& m, int n) {
  Batch b;
  b.n = n;
  for (int k = 0; k < n; ++k) {
    const soadyn_test::State s = soadyn_test::random_state(m, 500 + static_cast<std::uint64_t>(k));
    b.Q.insert(b.Q.end(), s.q.data(), s.q.data() + m.nq);
    b.V.insert(b.V.end(), s.v.data(), s.v.data() + m.nv);
    b.U.insert(b.U.end(), s.u.data(), s.u.data() + m.nv);
    b.F.insert(b.F.end(), s.f_ext.data(), s.f_ext.data() + 6 * m.nbodies());
  }
  return b;
}

bool same(const double* a, const Eigen::MatrixXd& b) {
  for (Eigen::Index c = 0; c < b.cols(); ++c)
    for (Eigen::Index r = 0; r < b.rows(); ++r)
      if (a[r * b.cols() + c] != b(r, c)) return false;  // row-major rows against Eigen's layout
  return true;
}

bool same(const double* a, const Eigen::VectorXd& b) {
  for (Eigen::Index r = 0; r < b.size(); ++r)
    if (a[r] != b[r]) return false;
  return true;
}

// The single call's mass matrix at q, or with four rows per pass on a rigid
// model the baseline kernel's (algorithms/packet_dynamics.hpp), into d. (A
// flexible model's mass matrix has no kernel of its own: in packets it is
// the single call's.)
void reference_mass_matrix(const soadyn::Model& m, soadyn::Data& d, const Eigen::Map<const Eigen::VectorXd>& q,
                           int lanes) {
  if (lanes > 1 && !m.has_flexible_bodies()) {
    const auto& baseline = soadyn::detail::available_mass_matrix_kernels().back();
    if (baseline.run(m, d, q).ok()) return;  // beyond the tree-frame reach: the body-frame sweeps, as the call
  }
  soadyn::mass_matrix<double>(m, d, q);
}

// The outputs of the five batched calls on a batch of n rows.
struct BatchOutputs {
  Rows qdd, tau, hq, ht, M;
  std::vector<Rows> D;
  std::array<double*, 6> derivatives;
  BatchOutputs(int n, int nv)
      : qdd(n * nv), tau(n * nv), hq(n * nv), ht(n * nv), M(n * nv * nv), D(6, Rows(n * nv * nv)),
        derivatives{D[0].data(), D[1].data(), D[2].data(), D[3].data(), D[4].data(), D[5].data()} {}
  // Forward, inverse (at the forward call's qdd) and hybrid dynamics, the mass
  // matrix and the derivatives; returns the failed rows of all five.
  long run(soadyn::BatchDynamics& batch, const Batch& b) {
    const int n = b.n;
    long failed = batch.forward_dynamics(n, b.Q.data(), b.V.data(), b.U.data(), b.F.data(), qdd.data()).failed_rows;
    failed += batch.inverse_dynamics(n, b.Q.data(), b.V.data(), qdd.data(), b.F.data(), tau.data()).failed_rows;
    failed += batch.hybrid_dynamics(n, b.Q.data(), b.V.data(), b.U.data(), b.F.data(), hq.data(), ht.data()).failed_rows;
    failed += batch.mass_matrix(n, b.Q.data(), M.data()).failed_rows;
    failed += batch.dynamics_derivatives(n, b.Q.data(), b.V.data(), b.U.data(), b.F.data(), derivatives).failed_rows;
    return failed;
  }
};

// Every batched call against the single calls; returns the rows that differ.
long batched_calls_differ(const soadyn::Model& m, int threads, int lanes) {
  using Map = Eigen::Map<const Eigen::VectorXd>;
  const int n = 64, nq = m.nq, nv = m.nv, nf = 6 * m.nbodies();
  const Batch b = random_batch(m, n);
  soadyn::BatchDynamics batch(m, threads);
  batch.set_lanes(lanes);
  BatchOutputs o(n, nv);
  const long failed = o.run(batch, b);
  const Rows &qdd = o.qdd, &tau = o.tau, &hq = o.hq, &ht = o.ht, &M = o.M;
  const std::vector<Rows>& D = o.D;
  soadyn::Data d(m);
  const bool by_dual = soadyn::BatchDynamics::derivatives_by_dual_numbers(m);
  std::unique_ptr<soadyn::DynamicsDerivatives> w;  // the analytic workspace refuses flexible models
  if (!by_dual) w = std::make_unique<soadyn::DynamicsDerivatives>(m);
  soadyn::ParameterSensitivity dual(m);
  std::array<Eigen::MatrixXd, 6> r;
  long differ = failed;
  for (int k = 0; k < n; ++k) {
    const Map q(b.Q.data() + k * nq, nq), v(b.V.data() + k * nv, nv), u(b.U.data() + k * nv, nv);
    const double* f = b.F.data() + k * nf;
    bool ok = true;
    soadyn::forward_dynamics<double>(m, d, q, v, u, f);
    ok = ok && same(qdd.data() + k * nv, d.qdd);
    soadyn::inverse_dynamics<double>(m, d, q, v, Map(qdd.data() + k * nv, nv), f);
    ok = ok && same(tau.data() + k * nv, d.tau);
    soadyn::hybrid_dynamics<double>(m, d, q, v, u, f);
    ok = ok && same(hq.data() + k * nv, d.qdd) && same(ht.data() + k * nv, d.tau);
    reference_mass_matrix(m, d, q, lanes);
    ok = ok && same(M.data() + k * nv * nv, d.mass_matrix);
    if (by_dual) {
      for (auto& x : r) x.setZero(nv, nv);
      dual.state_derivatives(m, q, v, u, f, r[0], r[1], r[2], r[3], r[4], r[5]);
    } else {
      soadyn::dynamics_derivatives<double>(m, d, *w, q, v, u, f);
      r = {w->dqdd_dq, w->dqdd_dv, w->dqdd_du, w->dtau_dq, w->dtau_dv, w->dtau_du};
    }
    for (std::size_t i = 0; i < 6; ++i) ok = ok && same(D[i].data() + k * nv * nv, r[i]);
    differ += !ok;
  }
  return differ;
}

// Batched calls allocate nothing once a BatchDynamics has made its first call
// of each kind: 40 rounds of the five calls on 64 rows, each round after a
// body's mass and a prescribed flag changed, which a packet call takes again
// into its packet model (PacketModel::refresh). Each round also checks that
// the batch followed the change: row 0's forward and hybrid dynamics, bit
// for bit the single calls'. Returns the allocations counted; `differing`
// receives the rounds that failed the check.
long batched_call_allocations(soadyn::Model m, int threads, int lanes, long& differing) {
  using Map = Eigen::Map<const Eigen::VectorXd>;
  const int n = 64, nv = m.nv;
  const Batch b = random_batch(m, n);
  soadyn::BatchDynamics batch(m, threads);
  batch.set_lanes(lanes);
  BatchOutputs o(n, nv);
  const soadyn::ParameterTable<double> table(m);
  int mass_entry = -1;  // the first body with a mass parameter (a flexible body has none)
  for (std::size_t body = 1; mass_entry < 0; ++body) mass_entry = table.find(m.body_names[body] + ".mass");
  double masses[2];
  table.get(m, mass_entry, &masses[0]);
  masses[1] = 1.5 * masses[0];
  soadyn::Data d(m);
  const Map q(b.Q.data(), m.nq), v(b.V.data(), nv), u(b.U.data(), nv);
  o.run(batch, b);
  soadyn_test::arm_counter();
  for (int round = 0; round < 40; ++round) {
    table.set(m, mass_entry, &masses[(round + 1) % 2]);
    const int dof = round % nv;
    if (!m.is_modal(dof)) m.set_prescribed(dof, !m.is_prescribed(dof));  // modal DOFs are always regular
    o.run(batch, b);
    soadyn::forward_dynamics<double>(m, d, q, v, u, b.F.data());
    bool followed = same(o.qdd.data(), d.qdd);
    soadyn::hybrid_dynamics<double>(m, d, q, v, u, b.F.data());
    followed = followed && same(o.hq.data(), d.qdd) && same(o.ht.data(), d.tau);
    differing += !followed;
  }
  return soadyn_test::disarm_counter().allocations();
}

// A flexible appendage's update on packets runs each lane's double model
// (sweeps/packet_appendage_update.hpp). The packet forward dynamics of
// `flexible` (with appendages), called directly at a random state: without
// lane models named the packet splits (its rows are then the caller's to
// compute one by one); with them it stands. Returns whether both held.
bool appendage_lanes_need_their_models(const soadyn::Model& flexible) {
  soadyn::PacketModel packets(flexible);
  soadyn::detail::PacketData d(packets.get());
  soadyn::detail::PacketVector q(flexible.nq), v(flexible.nv), tau(flexible.nv);
  const Batch b = random_batch(flexible, 1);
  for (int k = 0; k < flexible.nq; ++k) q[k] = soadyn::Packet4d(b.Q[static_cast<std::size_t>(k)]);
  for (int k = 0; k < flexible.nv; ++k) {
    v[k] = soadyn::Packet4d(b.V[static_cast<std::size_t>(k)]);
    tau[k] = soadyn::Packet4d(b.U[static_cast<std::size_t>(k)]);
  }
  const auto split = [&] {
    soadyn::clear_lane_divergence();
    const soadyn::Status status = soadyn::detail::packet_forward_dynamics(packets.get(), d, q, v, tau, nullptr);
    return !status.ok() || soadyn::lanes_diverged();
  };
  const bool split_without = split();
  soadyn::Data workspace(flexible);
  soadyn::PacketLanes lanes({&flexible, &flexible, &flexible, &flexible}, workspace);
  const soadyn::PacketLanesScope named(lanes);
  return split_without && !split();
}

// The pendulum-chain runs: per-run torques, link_2 masses and link_3 lock times.
struct Runs {
  static constexpr int runs = 6, steps = 150;
  soadyn::Model model = soadyn::pendulum_chain_model<double>(4);
  Rows x0, controls, masses, lock_times;
  Runs() {
    soadyn_test::Random rng(11);
    for (int r = 0; r < runs; ++r) {
      for (int k = 0; k < model.nq + model.nv; ++k) x0.push_back(rng.uniform(-0.5, 0.5));
      for (int k = 0; k < steps * model.nv; ++k) controls.push_back(rng.uniform(-0.3, 0.3));
      masses.push_back(rng.uniform(0.5, 2.0));
      lock_times.push_back(0.02 + 0.01 * r);
    }
  }
};

// One run on its own Simulator, recorded every step.
Rows simulate_alone(const Runs& w, int r, const soadyn::ParameterTable<double>& table, int mass_entry) {
  soadyn::Model model = w.model;
  table.set(model, mass_entry, &w.masses[static_cast<std::size_t>(r)]);
  soadyn::Simulator sim(model, 1e-3, soadyn::Integrator::rk4);
  const int nq = model.nq, nv = model.nv;
  const double* x0 = w.x0.data() + r * (nq + nv);
  sim.set_state(Eigen::Map<const Eigen::VectorXd>(x0, nq), Eigen::Map<const Eigen::VectorXd>(x0 + nq, nv));
  sim.schedule(w.lock_times[static_cast<std::size_t>(r)], soadyn::EventKind::lock, model.dof_index("link_3"));
  Rows q(sim.q().data(), sim.q().data() + nq);
  for (int k = 0; k < Runs::steps; ++k) {
    const double* u = w.controls.data() + (r * Runs::steps + k) * nv;
    for (int dof = 0; dof < nv; ++dof)
      if (!sim.model().is_prescribed(dof)) sim.set_input(dof, u[dof]);
    sim.step();
    q.insert(q.end(), sim.q().data(), sim.q().data() + nq);
  }
  return q;
}

long rollouts_differ(int threads, long& failures_reported) {
  Runs w;
  const soadyn::ParameterTable<double> table(w.model);
  const int mass_entry = table.find("link_2.mass");
  soadyn::RolloutRequest r;
  r.runs = Runs::runs;
  r.steps = Runs::steps;
  r.initial_states = w.x0.data();
  r.controls = w.controls.data();
  r.controls_per_run = true;
  r.parameters = {mass_entry};
  r.parameter_values = w.masses.data();
  r.events = {{soadyn::EventKind::lock, w.model.dof_index("link_3")}};
  r.event_times = w.lock_times.data();
  const std::int64_t rows = soadyn::rollout_rows(r);
  Rows q(Runs::runs * rows * w.model.nq), v(Runs::runs * rows * w.model.nv);
  std::vector<soadyn::Status> status(Runs::runs);
  std::vector<std::int64_t> failed(Runs::runs);
  std::vector<std::string> messages(Runs::runs);
  soadyn::ThreadPool pool(threads);
  soadyn::rollout(pool, w.model, r, {q.data(), v.data(), status.data(), failed.data(), messages.data()});
  long differ = 0;
  for (int run = 0; run < Runs::runs; ++run) {
    const Rows alone = simulate_alone(w, run, table, mass_entry);
    for (std::size_t k = 0; k < alone.size(); ++k)
      if (alone[k] != q[static_cast<std::size_t>(run * rows * w.model.nq) + k]) {
        ++differ;
        break;
      }
    differ += !messages[static_cast<std::size_t>(run)].empty();
  }
  // A refused parameter (run 1) and an overflowing step from step 40 (run 3).
  w.masses[1] = -1.0;
  for (int k = 40 * w.model.nv; k < Runs::steps * w.model.nv; ++k)
    w.controls[static_cast<std::size_t>(3 * Runs::steps * w.model.nv + k)] = 1e308;
  r.parameter_values = w.masses.data();
  r.controls = w.controls.data();
  soadyn::rollout(pool, w.model, r, {q.data(), v.data(), status.data(), failed.data(), messages.data()});
  failures_reported = (messages[1].find("link_2.mass") != std::string::npos && failed[1] == -1 &&
                       std::isnan(q[static_cast<std::size_t>(1 * rows * w.model.nq)])) +
                      (!messages[3].empty() && failed[3] == 40 && !status[3].ok()) +
                      (messages[0].empty() && messages[2].empty());
  return differ;
}

bool pool_rethrows_and_recovers() {
  soadyn::ThreadPool pool(2);
  bool thrown = false;
  try {
    pool.parallel_for(100, 1, [](std::int64_t begin, std::int64_t, int) {
      if (begin == 57) throw std::runtime_error("chunk 57");
    });
  } catch (const std::runtime_error& e) {
    thrown = std::string(e.what()) == "chunk 57";
  }
  std::vector<int> hits(1000, 0);
  pool.parallel_for(1000, 7, [&](std::int64_t begin, std::int64_t end, int) {
    for (std::int64_t k = begin; k < end; ++k) ++hits[static_cast<std::size_t>(k)];
  });
  bool each_once = true;
  for (int h : hits) each_once = each_once && h == 1;
  return thrown && each_once;
}

// Back-to-back loops, and loops after pauses longer than the pool's spin
// (its workers asleep again), on 2 and 3 threads: every index is visited once
// in each loop. Returns the loops that missed or repeated an index.
int pool_handoffs_miss() {
  int missed = 0;
  for (int threads : {2, 3}) {
    soadyn::ThreadPool pool(threads);
    std::vector<std::atomic<int>> hits(257);
    for (int loop = 0; loop < 600; ++loop) {
      const std::int64_t n = 1 + loop % 257, grain = 1 + loop % 5;
      for (std::int64_t k = 0; k < n; ++k) hits[static_cast<std::size_t>(k)].store(0);
      if (loop % 50 == 49) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      pool.parallel_for(n, grain, [&](std::int64_t begin, std::int64_t end, int) {
        for (std::int64_t k = begin; k < end; ++k) hits[static_cast<std::size_t>(k)].fetch_add(1);
      });
      bool once = true;
      for (std::int64_t k = 0; k < n; ++k) once = once && hits[static_cast<std::size_t>(k)].load() == 1;
      missed += !once;
    }
  }
  return missed;
}

}  // namespace

int main() {
  soadyn::Model tree = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  soadyn_test::Random rng(5);
  soadyn_test::apply_mask(tree, soadyn_test::random_mask(tree.nv, rng, 0.5));
  soadyn::Model flexible = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  soadyn_test::add_flexible_bodies(flexible);
  soadyn::Model cassini = soadyn::cassini_model<double>();  // two flexible appendages
  long differ = 0;
  const int widest = soadyn::BatchDynamics::widest_lanes();
  for (int lanes : {1, widest})
    for (int threads : {1, 2, 3})
      for (const soadyn::Model* m : {&tree, &flexible, &cassini}) differ += batched_calls_differ(*m, threads, lanes);
  std::printf("batched calls: 3 models x 3 thread counts x lanes 1 and %d x 64 rows, rows differing from the single "
              "calls: %ld\n", widest, differ);
  long allocations = 0, changes_missed = 0;
  for (int lanes : {1, widest})
    for (int threads : {1, 2})
      for (const soadyn::Model* m : {&tree, &flexible, &cassini})
        allocations += batched_call_allocations(*m, threads, lanes, changes_missed);
  const bool appendage_lanes = appendage_lanes_need_their_models(cassini);
  std::printf("packet appendage update without lane models: the packet splits; with them: it stands: %s\n",
              appendage_lanes ? "yes" : "no");
  const bool counter_works = soadyn_test::allocation_counter_works(64);
  std::printf("batched calls after a mass and a prescribed flag changed, 3 models x 2 thread counts x lanes 1 and "
              "%d x 40 rounds of the five calls: allocations %ld (counter works: %s), rounds whose row 0 differs from "
              "the single call: %ld\n", widest, allocations, counter_works ? "yes" : "no", changes_missed);
  long rollout_differ = 0, reported = 0;
  for (int threads : {1, 2}) {
    long r = 0;
    rollout_differ += rollouts_differ(threads, r);
    reported += r;
  }
  std::printf("rollouts: 2 thread counts x 6 runs, runs differing from one Simulator each: %ld; "
              "failures reported as expected: %ld of 6\n", rollout_differ, reported);
  const int handoffs_missed = pool_handoffs_miss();
  const bool pool_ok = pool_rethrows_and_recovers() && handoffs_missed == 0;
  std::printf("thread pool: exception rethrown and pool reused: %s; loops of 1200 that missed or repeated an "
              "index: %d\n", pool_ok ? "yes" : "no", handoffs_missed);
  const bool pass = differ == 0 && appendage_lanes && allocations == 0 && counter_works && changes_missed == 0 &&
                    rollout_differ == 0 && reported == 6 && pool_ok;
  std::printf("test_batch: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
