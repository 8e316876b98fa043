// Parallel rollouts (parallel/rollout.hpp).
#include "soadyn/parallel/rollout.hpp"

#include "soadyn/algorithms/packet_dynamics.hpp"
#include "soadyn/sim/packet_simulation.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

#include "soadyn/model/parameters.hpp"

namespace soadyn {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;

void check(const Model& model, const RolloutRequest& r, const ParameterTable<double>& table) {
  if (r.runs < 0 || r.steps < 0) throw std::invalid_argument("rollout: runs and steps must be >= 0");
  if (!(r.dt > 0) || !std::isfinite(r.dt)) throw std::invalid_argument("rollout: dt must be a finite number > 0");
  if (r.record_every < 1 || r.steps % r.record_every != 0)
    throw std::invalid_argument("rollout: record_every must be >= 1 and divide the number of steps");
  if (r.runs > 0 && !r.initial_states) throw std::invalid_argument("rollout: initial states are missing");
  if (!r.parameters.empty() && !r.parameter_values) throw std::invalid_argument("rollout: parameter values are missing");
  if (!r.events.empty() && !r.event_times) throw std::invalid_argument("rollout: event times are missing");
  for (int k : r.parameters)
    if (k < 0 || k >= table.size()) throw std::invalid_argument("rollout: parameter entry out of range");
  for (const auto& [dof, source] : r.sources) {
    if (dof < 0 || dof >= model.nv) throw std::invalid_argument("rollout: source DOF out of range");
    if (std::holds_alternative<CallbackSource<double>>(source))
      throw std::invalid_argument("rollout: callback sources cannot run in parallel");
  }
  for (const auto& [kind, dof] : r.events)
    if (dof < 0 || dof >= model.nv || kind == EventKind::prescribe)
      throw std::invalid_argument("rollout: events are lock or release of a DOF in range");
}

// scratch = base with run `run`'s parameter values set; throws
// ParameterError when the model refuses one (parameters.hpp).
void set_run_model(const Model& base, const RolloutRequest& r, const ParameterTable<double>& table, std::int64_t run,
                   Model& scratch) {
  scratch = base;
  const double* value = r.parameter_values;
  if (value) {
    std::int64_t width = 0;
    for (int k : r.parameters) width += table.entry(k).size();
    value += run * width;
  }
  for (int k : r.parameters) {
    table.set(scratch, k, value);
    value += table.entry(k).size();
  }
}

// One run, recorded into its rows; the message says why it stopped early.
class Run {
 public:
  Run(const Model& base, const RolloutRequest& r, const ParameterTable<double>& table, std::int64_t run,
      const RolloutOutputs& out)
      : base_(base), r_(r), table_(table), run_(run), out_(out), rows_(rollout_rows(r)) {}

  // Runs on `worker` of `pool`; stops early (its rows left as they are) when
  // the pool is stopping (ThreadPool::stop_requested).
  void operator()(Model& scratch, ThreadPool& pool, int worker) {
    std::unique_ptr<Simulator> sim;
    try {
      sim = setup(scratch);
    } catch (const std::exception& e) {
      out_.message[run_] = e.what();
      fill_nan(0);
      return;
    }
    record(*sim, 0);
    const int nv = base_.nv;
    for (std::int64_t k = 0; k < r_.steps; ++k) {
      if (pool.stop_requested(worker)) return;
      if (r_.controls) {
        const double* u = r_.controls + (r_.controls_per_run ? run_ * r_.steps * nv : 0) + k * nv;
        for (int dof = 0; dof < nv; ++dof)
          if (!sim->model().is_prescribed(dof)) sim->set_input(dof, u[dof]);
      }
      const Status status = sim->step();
      if (!status.ok()) {
        out_.status[run_] = status;
        out_.failed_step[run_] = k;
        out_.message[run_] = sim->describe(status);
        fill_nan(k / r_.record_every + 1);
        return;
      }
      if ((k + 1) % r_.record_every == 0) record(*sim, (k + 1) / r_.record_every);
    }
  }

 private:
  std::unique_ptr<Simulator> setup(Model& scratch) {
    set_run_model(base_, r_, table_, run_, scratch);
    auto sim = std::make_unique<Simulator>(scratch, r_.dt, r_.integrator, rollout_event_capacity(r_.events.size()));
    for (const auto& [dof, source] : r_.sources) sim->prescribe(dof, source);
    const double* x0 = r_.initial_states + run_ * (base_.nq + base_.nv);
    sim->set_state(Map(x0, base_.nq), Map(x0 + base_.nq, base_.nv));
    for (std::size_t e = 0; e < r_.events.size(); ++e)
      sim->schedule(r_.event_times[run_ * static_cast<std::int64_t>(r_.events.size()) + static_cast<std::int64_t>(e)],
                    r_.events[e].first, r_.events[e].second);
    return sim;
  }

  void record(const Simulator& sim, std::int64_t row) {
    const int nq = base_.nq, nv = base_.nv;
    Eigen::Map<Eigen::VectorXd>(out_.q + (run_ * rows_ + row) * nq, nq) = sim.q();
    Eigen::Map<Eigen::VectorXd>(out_.v + (run_ * rows_ + row) * nv, nv) = sim.v();
  }

  void fill_nan(std::int64_t from_row) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const int nq = base_.nq, nv = base_.nv;
    std::fill(out_.q + (run_ * rows_ + from_row) * nq, out_.q + (run_ + 1) * rows_ * nq, nan);
    std::fill(out_.v + (run_ * rows_ + from_row) * nv, out_.v + (run_ + 1) * rows_ * nv, nan);
  }

  const Model& base_;
  const RolloutRequest& r_;
  const ParameterTable<double>& table_;
  std::int64_t run_;
  const RolloutOutputs& out_;
  std::int64_t rows_;
};

// The runs of a unit of four as one PacketSimulation.
struct PoolWorker {
  ThreadPool* pool;
  int worker;
};

PacketSimulation packet_simulation(const Model& model, const PacketModel& packets, const Model* lane_models,
                                   const RolloutRequest& r, const RolloutOutputs& out, const std::int64_t* runs,
                                   ThreadPool& pool, int worker) {
  thread_local PoolWorker asked;
  asked = PoolWorker{&pool, worker};
  PacketSimulation s;
  s.model = &model;
  s.packets = &packets;
  s.dt = r.dt;
  s.integrator = r.integrator;
  s.steps = r.steps;
  s.record_every = r.record_every;
  const int nq = model.nq, nv = model.nv;
  const std::int64_t rows = rollout_rows(r), events = static_cast<std::int64_t>(r.events.size());
  for (int l = 0; l < PacketSimulation::lanes; ++l) {
    const std::int64_t run = runs[l];
    s.initial_states[l] = r.initial_states + run * (nq + nv);
    s.controls[l] = r.controls ? r.controls + (r.controls_per_run ? run * r.steps * nv : 0) : nullptr;
    s.event_times[l] = events ? r.event_times + run * events : nullptr;
    s.lane_models[l] = lane_models ? &lane_models[l] : nullptr;
    s.q[l] = out.q + run * rows * nq;
    s.v[l] = out.v + run * rows * nv;
  }
  s.control_stride = nv;
  s.sources = &r.sources;
  s.events = events ? &r.events : nullptr;
  s.stop = [](void* context) {
    const PoolWorker& w = *static_cast<PoolWorker*>(context);
    return w.pool->stop_requested(w.worker);
  };
  s.context = &asked;
  return s;
}

// The packet model of a unit's four runs when they set parameters: each
// run's model in `lanes` (four scratch models), then lane l holding run
// runs[l]'s values (PacketModel::of_lanes). Null when a run refuses its
// values or the four cannot share one packet model: the runs then go one by
// one, each reporting as it would alone.
std::unique_ptr<PacketModel> packet_model_of_runs(const Model& model, const RolloutRequest& r,
                                                  const ParameterTable<double>& table, const std::int64_t* runs,
                                                  Model* lanes) {
  std::array<const Model*, PacketSimulation::lanes> models{};
  for (int l = 0; l < PacketSimulation::lanes; ++l) {
    try {
      set_run_model(model, r, table, runs[l], lanes[l]);
    } catch (const std::exception&) {
      return nullptr;
    }
    models[static_cast<std::size_t>(l)] = &lanes[l];
  }
  return PacketModel::of_lanes(models);
}

// The step at which each of run `run`'s events falls due (the first whose
// start time is not before the event's, within Simulator::step's 1e-9 dt),
// clamped to [0, steps + 1]: runs with the same steps can step side by side.
// A time that is not finite gives -1 (refused: the run goes alone).
std::vector<double> due_steps(const RolloutRequest& r, std::int64_t run) {
  std::vector<double> due(r.events.size());
  for (std::size_t e = 0; e < due.size(); ++e) {
    const double t = r.event_times[run * static_cast<std::int64_t>(due.size()) + static_cast<std::int64_t>(e)];
    const double step = std::ceil(t / r.dt - 1e-9);
    due[e] = std::isfinite(t) ? std::clamp(step, 0.0, static_cast<double>(r.steps + 1)) : -1.0;
  }
  return due;
}

// The order in which the runs step and the units they step in: four runs
// side by side, or one alone (`packets` false: every run alone). Without
// events, runs 4k .. 4k + 3 make unit k and the last runs go alone. With
// events, the runs are ordered by the steps at which their events fall due,
// and four consecutive runs with the same steps make a unit: a packet's
// lanes must meet each event in the same step.
struct Units {
  std::vector<std::int64_t> runs;  // every run once, in stepping order
  std::vector<std::size_t> start;  // unit u is runs[start[u]] .. runs[start[u + 1] - 1]

  Units(const RolloutRequest& r, bool packets) : runs(static_cast<std::size_t>(r.runs)) {
    std::iota(runs.begin(), runs.end(), std::int64_t{0});
    std::vector<std::vector<double>> due;
    if (packets && !r.events.empty()) {
      for (std::int64_t run = 0; run < r.runs; ++run) due.push_back(due_steps(r, run));
      std::stable_sort(runs.begin(), runs.end(), [&](std::int64_t a, std::int64_t b) {
        return due[static_cast<std::size_t>(a)] < due[static_cast<std::size_t>(b)];
      });
    }
    const auto same_steps = [&](std::size_t k) {  // runs[k .. k + 3] meet their events in the same steps
      if (due.empty()) return true;
      for (std::size_t j = k + 1; j < k + PacketSimulation::lanes; ++j)
        if (due[static_cast<std::size_t>(runs[j])] != due[static_cast<std::size_t>(runs[k])]) return false;
      return true;
    };
    constexpr std::size_t width = PacketSimulation::lanes;
    for (std::size_t k = 0; k < runs.size();) {
      start.push_back(k);
      k += packets && k + width <= runs.size() && same_steps(k) ? width : 1;
    }
    start.push_back(runs.size());
  }
  std::int64_t count() const { return static_cast<std::int64_t>(start.size()) - 1; }
};

}  // namespace

std::int64_t rollout_rows(const RolloutRequest& request) {
  return 1 + request.steps / std::max<std::int64_t>(1, request.record_every);
}

void rollout(ThreadPool& pool, const Model& model, const RolloutRequest& request, const RolloutOutputs& outputs) {
  const ParameterTable<double> table(model);
  check(model, request, table);
  for (std::int64_t run = 0; run < request.runs; ++run) {
    outputs.status[run] = Status{};
    outputs.failed_step[run] = -1;
    outputs.message[run].clear();
  }
  std::vector<Model> scratch(static_cast<std::size_t>(pool.size()), model);  // one model copy per thread
  const bool packets = request.lanes != 1 && PacketDynamics::available() && PacketDynamics::serves(model) &&
                       model.nloops() == 0;
  const bool own_parameters = !request.parameters.empty();
  const Units units(request, packets);
  // Runs without parameters share one packet model; runs with parameters
  // have one per four runs, from four model copies per thread.
  const std::unique_ptr<PacketModel> shared_packets =
      packets && !own_parameters ? std::make_unique<PacketModel>(model) : nullptr;
  std::vector<Model> lane_models(packets && own_parameters ? scratch.size() * PacketSimulation::lanes : 0, model);
  std::atomic<std::int64_t> side_by_side{0};
  pool.parallel_for(units.count(), 1, [&](std::int64_t begin, std::int64_t end, int worker) {
    for (std::int64_t unit = begin; unit < end; ++unit) {
      const std::size_t first = units.start[static_cast<std::size_t>(unit)],
                        last = units.start[static_cast<std::size_t>(unit) + 1];
      const std::int64_t* runs = &units.runs[first];
      if (last - first == PacketSimulation::lanes) {
        Model* runs_models =
            own_parameters ? &lane_models[static_cast<std::size_t>(worker) * PacketSimulation::lanes] : nullptr;
        const std::unique_ptr<PacketModel> runs_packets =
            own_parameters ? packet_model_of_runs(model, request, table, runs, runs_models) : nullptr;
        const PacketModel* packet_model = own_parameters ? runs_packets.get() : shared_packets.get();
        if (packet_model && run_packet_simulation(packet_simulation(model, *packet_model, runs_models, request,
                                                                    outputs, runs, pool, worker))) {
          side_by_side += PacketSimulation::lanes;
          continue;
        }
      }
      for (std::size_t k = first; k < last; ++k)
        Run(model, request, table, units.runs[k], outputs)(scratch[static_cast<std::size_t>(worker)], pool, worker);
    }
  });
  if (outputs.side_by_side) *outputs.side_by_side = side_by_side;
}

}  // namespace soadyn
