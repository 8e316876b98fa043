// Many independent simulations of one model, stepped in parallel: the
// equivalent of MuJoCo's rollout. Run r starts from its own state, may set
// its own parameter values (parameters.hpp) and event times, applies its own
// (or shared) torques on the regular DOFs at every step, and is recorded
// every `record_every` steps. Each run is exactly the sequence of Simulator
// calls it stands for (set the parameters on a copy of the model, build the
// Simulator, prescribe the sources, set the state, schedule the events, then
// per step set the inputs and step), so its trajectory equals, bit for bit,
// the one a single Simulator gives. A run whose step fails stops there: its
// status, step and message are kept and its later rows are NaN (the status
// says so). A run whose setup is refused (a parameter value or an initial
// state the model rejects) has the refusal as its message, failed step -1
// and every row NaN.
//
// One model copy per thread; a Simulator per run (built in the worker, not
// real-time).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "soadyn/parallel/thread_pool.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn {

struct RolloutRequest {
  std::int64_t runs = 0, steps = 0;
  double dt = 1e-3;
  Integrator integrator = Integrator::rk4;
  std::int64_t record_every = 1;  // rows: 1 + steps / record_every (steps a multiple of it)
  const double* initial_states = nullptr;  // runs x (nq + nv)
  // Torques of the regular DOFs (prescribed DOFs' entries ignored): nullptr
  // (none), steps x nv shared by every run, or runs x steps x nv.
  const double* controls = nullptr;
  bool controls_per_run = false;
  // ParameterTable entries set before each run, and their values: runs x
  // (sum of the entries' sizes), each entry's values column-major.
  std::vector<int> parameters;
  const double* parameter_values = nullptr;
  // Prescribed motions, the same for every run (no callback sources).
  std::vector<std::pair<int, MotionSource<double>>> sources;
  // lock / release events and their times: runs x events.size().
  std::vector<std::pair<EventKind, int>> events;
  const double* event_times = nullptr;
  // Runs per pass: 1, or PacketSimulation::lanes (0: the widest this
  // processor runs, BatchDynamics::widest_lanes). Four runs of a tree
  // without loops, rigid or flexible, step side by side, with their shared
  // sources; with
  // parameters, each lane holds its run's values (PacketModel::of_lanes),
  // and four runs whose values change a property the model derives from
  // them go one by one. With events, runs whose events fall due in the same
  // steps step four side by side (the runs are grouped so, whatever their
  // order); the others go one by one, as do runs of other models.
  int lanes = 0;
};

struct RolloutOutputs {
  double* q = nullptr;  // runs x rows x nq
  double* v = nullptr;  // runs x rows x nv
  Status* status = nullptr;             // runs
  std::int64_t* failed_step = nullptr;  // runs (-1: none)
  std::string* message = nullptr;       // runs: empty, or why the run stopped (a run failed iff its message is
                                        // not empty: a refused setup leaves status ok and failed_step -1)
  std::int64_t* side_by_side = nullptr;  // if not null: how many runs stepped four side by side to their end
};

// Rows recorded per run.
std::int64_t rollout_rows(const RolloutRequest& request);

// Throws std::invalid_argument naming what is inconsistent (counts, a
// parameter value a model refuses is a failed run, not an exception).
void rollout(ThreadPool& pool, const Model& model, const RolloutRequest& request, const RolloutOutputs& outputs);

}  // namespace soadyn
