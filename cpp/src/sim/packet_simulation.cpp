// Four runs stepped side by side (sim/packet_simulation.hpp): the Simulator
// on packets built, fed and read here, compiled for the baseline; its step,
// the work, compiled for AVX2 in packet_step.cpp.
#include "soadyn/sim/packet_simulation.hpp"

#include "soadyn/algorithms/configuration.hxx"
#include "soadyn/algorithms/energy.hxx"
#include "soadyn/algorithms/packet_dynamics.hpp"
#include "soadyn/constraints/constrained_dynamics.hxx"
#include "soadyn/constraints/constrained_impulse.hxx"
#include "soadyn/constraints/loop_assembly.hxx"
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/core/packet.hpp"
#include "soadyn/model/model.hxx"
#include "soadyn/sim/chart.hpp"
#include "soadyn/sim/simulator.hxx"

namespace soadyn {

extern template Status SimulatorTpl<Packet4d>::step();  // packet_step.cpp

namespace {

constexpr int kLanes = PacketSimulation::lanes;

void record(const SimulatorTpl<Packet4d>& sim, const PacketSimulation& s, std::int64_t row) {
  const int nq = s.model->nq, nv = s.model->nv;
  for (int l = 0; l < kLanes; ++l) {
    for (int k = 0; k < nq; ++k) s.q[l][row * nq + k] = sim.q()[k][l];
    for (int k = 0; k < nv; ++k) s.v[l][row * nv + k] = sim.v()[k][l];
  }
}

}  // namespace

bool run_packet_simulation(const PacketSimulation& s) {
  const Model& base = *s.model;
  const int nq = base.nq, nv = base.nv;
  clear_lane_divergence();  // before the Simulator: the lanes' models may differ in their values
  SimulatorTpl<Packet4d> sim(s.packets->get(), Packet4d(s.dt), s.integrator);
  VecX<Packet4d> q(nq), v(nv);
  for (int l = 0; l < kLanes; ++l) {
    for (int k = 0; k < nq; ++k) q[k][l] = s.initial_states[l][k];
    for (int k = 0; k < nv; ++k) v[k][l] = s.initial_states[l][nq + k];
  }
  sim.set_state(q, v);
  if (lanes_diverged()) return false;
  record(sim, s, 0);
  for (std::int64_t step = 0; step < s.steps; ++step) {
    if (s.stop && s.stop(s.context)) return true;
    if (s.controls[0]) {
      for (int dof = 0; dof < nv; ++dof) {
        if (base.is_prescribed(dof)) continue;
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
