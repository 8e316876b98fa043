// Stepping models with closed loops never touches the heap: a planar
// five-bar (two DOFs, one point loop) and a four-bar closed by a revolute cut
// (redundant equations: 5 of rank 2), assembled before counting, then 10^4
// steps with each integrator (RK4, semi-implicit Euler, dopri5) while
// scheduled lock/release events and immediate lock/release calls change the
// loops' mobility (locking both legs of the five-bar locks it) and a
// constant-velocity drive takes over a crank; the closure after every step is
// checked against the tolerance, with the divergence guard on (it must not
// trip). Then direct calls of assemble_loops and
// project_loop_velocity, and a projection that fails (one Gauss-Newton step
// allowed from far away): a loop_not_closed Status naming the loop, no
// allocation. Every allocation of the process is counted
// (allocation_counter.cpp).
#include <cmath>
#include <cstdio>
#include <string>
#include "allocation_counter.hpp"
#include "soadyn/soadyn.hpp"

using namespace soadyn_test;

namespace {

constexpr long kSteps = 10000;
constexpr int kEventEvery = 500;

soadyn::Transform<double> at(double x) {
  soadyn::Transform<double> X;
  X.translation << x, 0.0, 0.0;
  return X;
}

// A uniform slender rod along its body x axis, hinged about z at `placement`.
void add_rod(soadyn::Model& m, const std::string& name, const std::string& parent, double placement, double length,
             double mass) {
  const double I = mass * length * length / 12.0;
  m.add_body(name, parent, soadyn::RevoluteJoint<double>{soadyn::Vec3<double>::UnitZ()}, at(placement), mass,
             soadyn::Vec3<double>(length / 2, 0, 0), soadyn::Vec3<double>(1e-6, I, I).asDiagonal());
}

soadyn::Model five_bar() {
  soadyn::Model m;
  m.gravity << 0.0, -9.81, 0.0;
  add_rod(m, "left", "", 0.0, 0.3, 1.0);
  add_rod(m, "left_upper", "left", 0.3, 0.5, 0.8);
  add_rod(m, "right", "", 0.4, 0.3, 1.2);
  add_rod(m, "right_upper", "right", 0.3, 0.5, 0.7);
  m.add_loop("apex", "left_upper", "right_upper", soadyn::LoopKind::point, at(0.5), at(0.5));
  return m;
}

soadyn::Model four_bar() {
  soadyn::Model m;
  m.gravity << 0.0, -9.81, 0.0;
  add_rod(m, "crank", "", 0.0, 0.038, 1.5);
  add_rod(m, "coupler", "crank", 0.038, 0.1152, 5.0);
  add_rod(m, "rocker", "", 0.0895, 0.1152, 3.0);
  m.add_loop("pin", "coupler", "rocker", soadyn::LoopKind::revolute, at(0.1152), at(0.1152));
  return m;
}

// Closes q (legs/crank held) and v before counting starts.
void assemble(soadyn::Simulator& sim, const Eigen::VectorXd& q_guess, const Eigen::VectorXd& v_guess, int held_dofs) {
  soadyn::Data data(sim.model());
  Eigen::VectorXd q = q_guess, v = v_guess, free = Eigen::VectorXd::Ones(sim.model().nv);
  free.head(held_dofs).setZero();
  if (!soadyn::assemble_loops(sim.model(), data, q, free, 1e-12, 50).ok() ||
      !soadyn::project_loop_velocity(sim.model(), data, q, v, free).ok())
    std::printf("assembly failed\n");
  sim.set_state(q, v);
}

struct RunResult {
  AllocationCounts counts;
  long failed = 0;
  double worst_closure = 0.0;
};

RunResult run(soadyn::Simulator& sim, int locked_dof, int other_dof) {
  // Lock at odd multiples of kEventEvery, release at even ones; the last is a release, so the drive
  // that takes over `other_dof` near the end moves a mechanism that can move.
  for (long k = 1; k * kEventEvery < kSteps - kEventEvery; ++k)
    sim.schedule(sim.dt() * static_cast<double>(k * kEventEvery),
                 k % 2 ? soadyn::EventKind::lock : soadyn::EventKind::release, locked_dof);
  soadyn::ConstantAcceleration<double> drive;
  drive.t0 = sim.dt() * static_cast<double>(kSteps - 300);
  drive.v0 = 1.5;
  sim.schedule_prescribe(drive.t0, other_dof, drive);
  soadyn::Data data(sim.model());
  RunResult r;
  sim.set_divergence_guard(true);  // a driven, locked and released mechanism never trips it
  arm_counter();
  for (long k = 0; k < kSteps; ++k) {
    if (k % 997 == 100) r.failed += !sim.lock(other_dof).ok();  // with locked_dof locked too: mobility 0
    if (k % 997 == 200) r.failed += !sim.release(other_dof).ok();
    r.failed += !sim.step().ok();
    soadyn::loop_residual(sim.model(), data, sim.q(), sim.v().data());
    r.worst_closure = std::max({r.worst_closure, data.loops.residual.lpNorm<Eigen::Infinity>(),
                                data.loops.velocity_residual.lpNorm<Eigen::Infinity>() * 1e-2});
  }
  r.counts = disarm_counter();
  return r;
}

const char* integrator_name(soadyn::Integrator i) {
  switch (i) {
    case soadyn::Integrator::rk4: return "rk4";
    case soadyn::Integrator::semi_implicit_euler: return "euler";
    case soadyn::Integrator::dopri5: return "dopri5";
  }
  return "?";
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_loop_sim_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  bool pass = true;
  for (const soadyn::Integrator integrator :
       {soadyn::Integrator::rk4, soadyn::Integrator::semi_implicit_euler, soadyn::Integrator::dopri5}) {
    soadyn::Simulator five(five_bar(), 1e-3, integrator);
    assemble(five, Eigen::Vector4d(1.8, -1.2, 1.3, 1.1), Eigen::Vector4d(1.5, 0.0, -0.7, 0.0), 2);
    const RunResult a = run(five, 0, 2);
    soadyn::Simulator four(four_bar(), 1e-3, integrator);
    assemble(four, Eigen::Vector3d(0.7, 0.9, 1.9), Eigen::Vector3d(3.0, 0.0, 0.0), 1);
    const RunResult b = run(four, 2, 0);
    for (const auto& [name, r] : {std::pair<const char*, const RunResult&>{"five-bar", a}, {"four-bar", b}}) {
      std::printf("%s (%s): %ld steps, %ld allocations, %ld frees, %ld failed statuses, worst closure %.1e\n", name,
                  integrator_name(integrator), kSteps, r.counts.allocations(), r.counts.frees, r.failed,
                  r.worst_closure);
      pass = pass && r.counts.allocations() == 0 && r.counts.frees == 0 && r.failed == 0 && r.worst_closure <= 1e-12;
    }
  }
  // Direct calls, and a projection that cannot succeed in one step.
  const soadyn::Model model = four_bar();
  soadyn::Data data(model);
  Eigen::VectorXd q(3), v(3), free = Eigen::VectorXd::Ones(3);
  free[0] = 0.0;
  long ok_calls = 0, named_failures = 0;
  arm_counter();
  for (int k = 0; k < 1000; ++k) {
    q << 0.7, 0.9 + 1e-3 * (k % 7), 1.9 - 1e-3 * (k % 5);
    v << 3.0, 0.1 * (k % 3), 0.0;
    ok_calls += soadyn::assemble_loops(model, data, q, free, 1e-12, 50).ok() &&
                soadyn::project_loop_velocity(model, data, q, v, free).ok();
    q << 0.7, 2.5, 0.0;
    const soadyn::Status s = soadyn::assemble_loops(model, data, q, free, 1e-12, 1);
    named_failures += s.code == soadyn::StatusCode::loop_not_closed && s.index == 0;
  }
  const AllocationCounts counts = disarm_counter();
  std::printf("direct calls: %ld of 1000 closed, %ld of 1000 failures named loop 0, %ld allocations, %ld frees\n",
              ok_calls, named_failures, counts.allocations(), counts.frees);
  pass = pass && ok_calls == 1000 && named_failures == 1000 && counts.allocations() == 0 && counts.frees == 0;
  std::printf("test_loop_sim_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
