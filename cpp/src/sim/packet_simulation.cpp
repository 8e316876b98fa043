// Four runs stepped side by side (sim/packet_simulation.hpp): the Simulator
// on packets built, fed and read here, compiled for the baseline; its step,
// the work, compiled for AVX2 in packet_step.cpp.
#include "soadyn/sim/packet_simulation.hpp"

#include "soadyn/algorithms/configuration.hxx"
#include "soadyn/algorithms/energy.hxx"
#include "soadyn/algorithms/packet_dynamics.hpp"
#include "soadyn/sweeps/packet_appendage_update.hpp"
#include "soadyn/constraints/constrained_dynamics.hxx"
#include "soadyn/constraints/constrained_impulse.hxx"
#include "soadyn/constraints/loop_assembly.hxx"
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/core/packet.hpp"
#include "soadyn/model/model.hxx"
#include "soadyn/sim/chart.hpp"
#include "soadyn/sim/simulator.hxx"

namespace soadyn {

// The step, and the setup's members that reach the dynamics (a source's
// switch and its impulse, the divergence guard's energies), are compiled for
// AVX2 in packet_step.cpp. Were they also instantiated here, for the
// baseline, the linker could keep this copy of every function they share
// with the step (the sweeps, the hinge updates), and the step would run it.
extern template Status SimulatorTpl<Packet4d>::step();
extern template Status SimulatorTpl<Packet4d>::switch_mode(int, Drive, int, bool);
extern template void SimulatorTpl<Packet4d>::restart_divergence_guard();
extern template bool detail::fires_after<Packet4d>(const Event<Packet4d>&, const Event<Packet4d>&);

namespace {

constexpr int kLanes = PacketSimulation::lanes;

void record(const SimulatorTpl<Packet4d>& sim, const PacketSimulation& s, std::int64_t row) {
  const int nq = s.model->nq, nv = s.model->nv;
  for (int l = 0; l < kLanes; ++l) {
    for (int k = 0; k < nq; ++k) s.q[l][row * nq + k] = sim.q()[k][l];
    for (int k = 0; k < nv; ++k) s.v[l][row * nv + k] = sim.v()[k][l];
  }
}

// A source shared by the four runs, its values in every lane; false for a
// callback source, which has no packet form.
bool packet_source(const MotionSource<double>& source, MotionSource<Packet4d>& out) {
  using P = Packet4d;
  if (const auto* x = std::get_if<ConstantAcceleration<double>>(&source)) {
    out = ConstantAcceleration<P>{x->t0, x->q0, x->v0, x->a};
  } else if (const auto* x = std::get_if<Polynomial<double>>(&source)) {
    Polynomial<P> p;
    p.t0 = x->t0;
    std::copy(x->c.begin(), x->c.end(), p.c.begin());
    p.degree = x->degree;
    out = p;
  } else if (const auto* x = std::get_if<Cycloidal<double>>(&source)) {
    out = Cycloidal<P>{x->t0, x->duration, x->q0, x->q1};
  } else if (const auto* x = std::get_if<CubicSpline<double>>(&source)) {
    CubicSpline<P> spline;  // the knots and their second derivatives as they are
    spline.t.assign(x->t.begin(), x->t.end());
    spline.q.assign(x->q.begin(), x->q.end());
    spline.second.assign(x->second.begin(), x->second.end());
    out = spline;
  } else {
    return false;
  }
  return true;
}

// The shared sources given to `sim`; false if one has no packet form or the
// Simulator refuses it.
bool prescribe_sources(const PacketSimulation& s, SimulatorTpl<Packet4d>& sim) {
  if (!s.sources) return true;
  for (const auto& [dof, source] : *s.sources) {
    MotionSource<Packet4d> packets;
    if (!packet_source(source, packets)) return false;
    try {
      sim.prescribe(dof, std::move(packets));
    } catch (const std::exception&) {  // the runs one by one report it
      return false;
    }
  }
  return true;
}

// The runs' events scheduled on `sim`, lane l at run l's times; false if the
// Simulator refuses one (a time that is not finite in some lane).
bool schedule_events(const PacketSimulation& s, SimulatorTpl<Packet4d>& sim) {
  if (!s.events) return true;
  for (std::size_t e = 0; e < s.events->size(); ++e) {
    Packet4d time;
    for (int l = 0; l < kLanes; ++l) time[l] = s.event_times[l][e];
    try {
      sim.schedule(time, (*s.events)[e].first, (*s.events)[e].second);
    } catch (const std::exception&) {  // the runs one by one report it
      return false;
    }
  }
  return true;
}

}  // namespace

bool run_packet_simulation(const PacketSimulation& s) {
  const Model& base = *s.model;
  const int nq = base.nq, nv = base.nv;
  std::array<const Model*, kLanes> models;
  for (int l = 0; l < kLanes; ++l) models[static_cast<std::size_t>(l)] = s.lane_models[l] ? s.lane_models[l] : &base;
  Data workspace(base);
  PacketLanes lanes(models, workspace);
  const PacketLanesScope lanes_in_use(lanes);
  clear_lane_divergence();  // before the Simulator: the lanes' models may differ in their values
  SimulatorTpl<Packet4d> sim(s.packets->get(), Packet4d(s.dt), s.integrator,
                             rollout_event_capacity(s.events ? s.events->size() : 0));
  if (!prescribe_sources(s, sim)) return false;
  VecX<Packet4d> q(nq), v(nv);
  for (int l = 0; l < kLanes; ++l) {
    for (int k = 0; k < nq; ++k) q[k][l] = s.initial_states[l][k];
    for (int k = 0; k < nv; ++k) v[k][l] = s.initial_states[l][nq + k];
  }
  sim.set_state(q, v);
  if (!schedule_events(s, sim) || lanes_diverged()) return false;
  record(sim, s, 0);
  for (std::int64_t step = 0; step < s.steps; ++step) {
    if (s.stop && s.stop(s.context)) return true;
    if (s.controls[0]) {
      for (int dof = 0; dof < nv; ++dof) {
        if (sim.model().is_prescribed(dof)) continue;  // the sourced DOFs too, as the runs alone
        Packet4d u;
        for (int l = 0; l < kLanes; ++l) u[l] = s.controls[l][step * s.control_stride + dof];
        sim.set_input(dof, u);
      }
    }
    if (!sim.step().ok() || lanes_diverged()) return false;
    if ((step + 1) % s.record_every == 0) record(sim, s, (step + 1) / s.record_every);
  }
  return true;
}

}  // namespace soadyn
