// Four simulations of one tree stepped side by side: a Simulator on
// packets of four doubles (core/packet.hpp), one run per lane, compiled for
// AVX2 (packet_simulation.cpp). Each lane steps exactly as a Simulator of its
// run alone, bit for bit, as long as every branch on values goes the same
// way in the four lanes; when one does not, or a step fails, the caller runs
// the four again one by one (parallel/rollout.cpp), so each run's trajectory,
// status and message are the single Simulator's.
#pragma once
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "soadyn/model/model.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn {

class PacketModel;  // algorithms/packet_dynamics.hpp

struct PacketSimulation {
  static constexpr int lanes = 4;
  const Model* model = nullptr;  // a tree without loops (PacketDynamics::serves)
  const PacketModel* packets = nullptr;  // the model in packets (its lanes may differ in values: PacketModel::of_lanes)
  // Each lane's model, whose values the packets hold in that lane (null: `model`): the flexible appendages'
  // update runs each lane on its own (sweeps/packet_appendage_update.hpp).
  const Model* lane_models[4] = {};
  double dt = 1e-3;
  Integrator integrator = Integrator::rk4;
  std::int64_t steps = 0, record_every = 1;
  const double* initial_states[lanes] = {};  // each nq + nv values
  // Each run's torques of step 0 (nv values, prescribed DOFs' ignored), the
  // next step's `control_stride` values further on; null: none.
  const double* controls[lanes] = {};
  std::int64_t control_stride = 0;
  // Prescribed motions shared by the four runs (no callback source), given
  // before the state as a Simulator of each run is given them; null: none.
  const std::vector<std::pair<int, MotionSource<double>>>* sources = nullptr;
  // Lock and release events of the same kinds and DOFs in the four runs
  // (null: none), each run at its own times: event_times[l] holds run l's,
  // one per event. They are scheduled after the state, as for each run
  // alone; the four stand as one packet when each event falls due in the
  // same step in every lane (and a lock meets the same velocity, zero or
  // not, in every lane).
  const std::vector<std::pair<EventKind, int>>* events = nullptr;
  const double* event_times[lanes] = {};
  // Each run's recorded rows: 1 + steps / record_every of nq (nv) values.
  double* q[lanes] = {};
  double* v[lanes] = {};
  // Asked before each step: true stops the runs there (their later rows left
  // as they are), and run_packet_simulation returns true.
  bool (*stop)(void* context) = nullptr;
  void* context = nullptr;
};

// The event capacity of each run's Simulator: room for every scheduled event.
inline int rollout_event_capacity(std::size_t events) { return std::max<int>(64, static_cast<int>(events)); }

// Steps the four runs of `s` and records them. False when the lanes took
// different branches, a step failed or the Simulator refused a source or an
// event: the rows are then to be computed again run by run. Call only where
// PacketDynamics::available().
bool run_packet_simulation(const PacketSimulation& s);

}  // namespace soadyn
