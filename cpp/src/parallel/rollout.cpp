// Parallel rollouts (parallel/rollout.hpp).
#include "soadyn/parallel/rollout.hpp"

#include "soadyn/algorithms/packet_dynamics.hpp"
#include "soadyn/sim/packet_simulation.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <memory>
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
    auto sim = std::make_unique<Simulator>(scratch, r_.dt, r_.integrator,
                                           std::max<int>(64, static_cast<int>(r_.events.size())));
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

// Runs first .. first + 3 as one PacketSimulation.
struct PoolWorker {
  ThreadPool* pool;
  int worker;
};

PacketSimulation packet_simulation(const Model& model, const PacketModel& packets, const RolloutRequest& r,
                                   const RolloutOutputs& out, std::int64_t first, ThreadPool& pool, int worker) {
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
  const std::int64_t rows = rollout_rows(r);
  for (int l = 0; l < PacketSimulation::lanes; ++l) {
    const std::int64_t run = first + l;
    s.initial_states[l] = r.initial_states + run * (nq + nv);
    s.controls[l] = r.controls ? r.controls + (r.controls_per_run ? run * r.steps * nv : 0) : nullptr;
    s.q[l] = out.q + run * rows * nq;
    s.v[l] = out.v + run * rows * nv;
  }
  s.control_stride = nv;
  s.sources = &r.sources;
  s.stop = [](void* context) {
    const PoolWorker& w = *static_cast<PoolWorker*>(context);
    return w.pool->stop_requested(w.worker);
  };
  s.context = &asked;
  return s;
}

// The packet model of runs first .. first + 3 when they set parameters:
// each run's model in `lanes` (four scratch models), then lane l holding
// run first + l's values (PacketModel::of_lanes). Null when a run refuses
// its values or the four cannot share one packet model: the runs then go
// one by one, each reporting as it would alone.
std::unique_ptr<PacketModel> packet_model_of_runs(const Model& model, const RolloutRequest& r,
                                                  const ParameterTable<double>& table, std::int64_t first,
                                                  Model* lanes) {
  std::array<const Model*, PacketSimulation::lanes> models{};
  for (int l = 0; l < PacketSimulation::lanes; ++l) {
    try {
      set_run_model(model, r, table, first + l, lanes[l]);
    } catch (const std::exception&) {
      return nullptr;
    }
    models[static_cast<std::size_t>(l)] = &lanes[l];
  }
  return PacketModel::of_lanes(models);
}

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
                       model.nloops() == 0 && request.events.empty();
  const bool own_parameters = !request.parameters.empty();
  const std::int64_t width = packets ? PacketSimulation::lanes : 1, units = (request.runs + width - 1) / width;
  // Runs without parameters share one packet model; runs with parameters
  // have one per four runs, from four model copies per thread.
  const std::unique_ptr<PacketModel> shared_packets =
      packets && !own_parameters ? std::make_unique<PacketModel>(model) : nullptr;
  std::vector<Model> lane_models(packets && own_parameters ? scratch.size() * PacketSimulation::lanes : 0, model);
  pool.parallel_for(units, 1, [&](std::int64_t begin, std::int64_t end, int worker) {
    for (std::int64_t unit = begin; unit < end; ++unit) {
      const std::int64_t first = unit * width, last = std::min(first + width, request.runs);
      if (packets && last - first == PacketSimulation::lanes) {
        const std::unique_ptr<PacketModel> runs_packets =
            own_parameters ? packet_model_of_runs(model, request, table, first,
                                                  &lane_models[static_cast<std::size_t>(worker) * PacketSimulation::lanes])
                           : nullptr;
        const PacketModel* packet_model = own_parameters ? runs_packets.get() : shared_packets.get();
        if (packet_model &&
            run_packet_simulation(packet_simulation(model, *packet_model, request, outputs, first, pool, worker)))
          continue;
      }
      for (std::int64_t run = first; run < last; ++run)
        Run(model, request, table, run, outputs)(scratch[static_cast<std::size_t>(worker)], pool, worker);
    }
  });
}

}  // namespace soadyn
