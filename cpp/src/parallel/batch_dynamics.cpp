// Batched dynamics on a thread pool (parallel/batch_dynamics.hpp).
#include "soadyn/parallel/batch_dynamics.hpp"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/analysis/dynamics_derivatives.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/algorithms/rnea.hpp"

namespace soadyn {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using VectorOut = Eigen::Map<Eigen::VectorXd>;
using RowMajorOut = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

// Units (rows or packets) per chunk, about 32 chunks per thread: enough to
// make a chunk's hand-off negligible, few enough that both threads get work
// on small batches and that the thread finishing last keeps the other
// waiting for little (or a preempted thread holds back little of the rest).
std::int64_t grain(std::int64_t n, int threads) { return std::clamp<std::int64_t>(n / (32 * threads), 1, 64); }

}  // namespace

struct BatchDynamics::Workspace {
  explicit Workspace(const Model& model) : data(model) {}
  Data data;
  std::unique_ptr<PacketDynamics> packet;  // built at the first packet call
  std::unique_ptr<DynamicsDerivatives> derivatives;  // built at the first derivatives call
  std::unique_ptr<ParameterSensitivity> dual;
  std::array<Eigen::MatrixXd, 6> dual_results;
};

BatchDynamics::BatchDynamics(const Model& model, int threads)
    : model_(model), lanes_(widest_lanes()), pool_(threads) {
  for (int w = 0; w < pool_.size(); ++w) workspaces_.push_back(std::make_unique<Workspace>(model));
}

BatchDynamics::~BatchDynamics() = default;

bool BatchDynamics::derivatives_by_dual_numbers(const Model& model) {
  return model.nloops() > 0 || model.has_flexible_bodies() || !model.force_elements.point_springs.empty();
}

int BatchDynamics::widest_lanes() { return PacketDynamics::available() ? PacketDynamics::lanes : 1; }

void BatchDynamics::set_lanes(int lanes) {
  if (lanes == 1 || (lanes == PacketDynamics::lanes && PacketDynamics::available())) {
    lanes_ = lanes;
    return;
  }
  throw std::invalid_argument("lanes must be 1" +
                              std::string(PacketDynamics::available() ? " or 4" : " (this processor lacks AVX2 and FMA, "
                                                                                   "or SOADYN_BASELINE_KERNELS is set)") +
                              ", got " + std::to_string(lanes));
}

bool BatchDynamics::prepare_packets() {
  if (lanes_ == 1 || !PacketDynamics::serves(model_)) return false;
  if (packet_model_)
    packet_model_->refresh(model_);
  else
    packet_model_ = std::make_unique<PacketModel>(model_);
  for (auto& w : workspaces_)
    if (!w->packet) w->packet = std::make_unique<PacketDynamics>(model_, *packet_model_);
  return true;
}

template <class RowFn>
BatchOutcome BatchDynamics::for_rows(std::int64_t n, RowFn&& fn) {
  return for_rows(n, std::forward<RowFn>(fn), nullptr);
}

template <class RowFn, class PacketFn>
BatchOutcome BatchDynamics::for_rows(std::int64_t n, RowFn&& fn, PacketFn&& packet_fn) {
  constexpr bool has_packet_fn = !std::is_same_v<std::decay_t<PacketFn>, std::nullptr_t>;
  bool packets = false;
  if constexpr (has_packet_fn) packets = n >= packet_minimum_rows && prepare_packets();
  const std::int64_t width = packets ? PacketDynamics::lanes : 1, units = (n + width - 1) / width;
  BatchOutcome outcome;
  std::mutex failures;
  const auto record = [&](std::int64_t row, const Status& status) {
    if (status.ok()) return;
    std::lock_guard<std::mutex> lock(failures);
    ++outcome.failed_rows;
    if (outcome.first_failed_row < 0 || row < outcome.first_failed_row) {
      outcome.first_failed_row = row;
      outcome.first_status = status;
    }
  };
  pool_.parallel_for(units, grain(units, threads()), [&](std::int64_t begin, std::int64_t end, int worker) {
    Workspace& w = *workspaces_[static_cast<std::size_t>(worker)];
    for (std::int64_t unit = begin; unit < end; ++unit) {
      const std::int64_t first = unit * width, last = std::min(first + width, n);
      if constexpr (has_packet_fn) {
        if (packets && last - first == PacketDynamics::lanes) {
          Status status[PacketDynamics::lanes];
          packet_fn(first, *w.packet, status);
          for (int l = 0; l < PacketDynamics::lanes; ++l) record(first + l, status[l]);
          continue;
        }
      }
      for (std::int64_t row = first; row < last; ++row) record(row, fn(row, w));
    }
  });
  return outcome;
}

template <class Call, class PacketCall>
BatchOutcome BatchDynamics::vector_call(std::int64_t n, const double* Q, const double* V, const double* X,
                                        const double* F, double* OUT, Call&& call, PacketCall&& packet_call) {
  const int nq = model_.nq, nv = model_.nv, nf = 6 * model_.nbodies();
  return for_rows(
      n,
      [&](std::int64_t k, Workspace& w) {
        return call(w.data, Map(Q + k * nq, nq), Map(V + k * nv, nv), Map(X + k * nv, nv), F ? F + k * nf : nullptr,
                    VectorOut(OUT + k * nv, nv));
      },
      [&](std::int64_t k, PacketDynamics& p, Status* status) {
        (p.*packet_call)(Q + k * nq, V + k * nv, X + k * nv, F ? F + k * nf : nullptr, OUT + k * nv, status);
      });
}

BatchOutcome BatchDynamics::forward_dynamics(std::int64_t n, const double* Q, const double* V, const double* TAU,
                                             const double* F, double* QDD) {
  return vector_call(n, Q, V, TAU, F, QDD, [&](Data& d, const Map& q, const Map& v, const Map& tau, const double* f,
                                               VectorOut qdd) {
    const Status s = soadyn::forward_dynamics<double>(model_, d, q, v, tau, f);
    qdd = d.qdd;
    return s;
  }, &PacketDynamics::forward_dynamics);
}

BatchOutcome BatchDynamics::inverse_dynamics(std::int64_t n, const double* Q, const double* V, const double* QDD,
                                             const double* F, double* TAU) {
  return vector_call(n, Q, V, QDD, F, TAU, [&](Data& d, const Map& q, const Map& v, const Map& qdd, const double* f,
                                               VectorOut tau) {
    const Status s = soadyn::inverse_dynamics<double>(model_, d, q, v, qdd, f);
    tau = d.tau;
    return s;
  }, &PacketDynamics::inverse_dynamics);
}

BatchOutcome BatchDynamics::hybrid_dynamics(std::int64_t n, const double* Q, const double* V, const double* U,
                                            const double* F, double* QDD, double* TAU) {
  const int nq = model_.nq, nv = model_.nv, nf = 6 * model_.nbodies();
  return for_rows(n, [&](std::int64_t k, Workspace& w) {
    const Status s = soadyn::hybrid_dynamics<double>(model_, w.data, Map(Q + k * nq, nq), Map(V + k * nv, nv),
                                                     Map(U + k * nv, nv), F ? F + k * nf : nullptr,
                                                     DynamicsOutputs{false});
    VectorOut(QDD + k * nv, nv) = w.data.qdd;
    VectorOut(TAU + k * nv, nv) = w.data.tau;
    return s;
  }, [&](std::int64_t k, PacketDynamics& p, Status* status) {
    p.hybrid_dynamics(Q + k * nq, V + k * nv, U + k * nv, F ? F + k * nf : nullptr, QDD + k * nv, TAU + k * nv, status);
  });
}

BatchOutcome BatchDynamics::mass_matrix(std::int64_t n, const double* Q, double* M) {
  const int nq = model_.nq, nv = model_.nv;
  return for_rows(n, [&](std::int64_t k, Workspace& w) {
    const Status s = soadyn::mass_matrix<double>(model_, w.data, Map(Q + k * nq, nq));
    copy_mass_matrix_rows(w.data.mass_matrix, M + k * nv * nv);
    return s;
  }, [&](std::int64_t k, PacketDynamics& p, Status* status) { p.mass_matrix(Q + k * nq, M + k * nv * nv, status); });
}

BatchOutcome BatchDynamics::dynamics_derivatives(std::int64_t n, const double* Q, const double* V, const double* U,
                                                 const double* F, const std::array<double*, 6>& D) {
  const int nq = model_.nq, nv = model_.nv, nf = 6 * model_.nbodies();
  const bool dual = derivatives_by_dual_numbers(model_);
  for (auto& w : workspaces_) {  // built once, before the parallel part
    if (dual && !w->dual) w->dual = std::make_unique<ParameterSensitivity>(model_);
    if (!dual && !w->derivatives) w->derivatives = std::make_unique<DynamicsDerivatives>(model_);
  }
  return for_rows(n, [&](std::int64_t k, Workspace& w) {
    const Map q(Q + k * nq, nq), v(V + k * nv, nv), u(U + k * nv, nv);
    const double* f = F ? F + k * nf : nullptr;
    Status status;
    std::array<const Eigen::MatrixXd*, 6> results;
    if (dual) {
      std::array<Eigen::MatrixXd, 6>& r = w.dual_results;
      for (Eigen::MatrixXd& x : r) x.setZero(nv, nv);
      status = w.dual->state_derivatives(model_, q, v, u, f, r[0], r[1], r[2], r[3], r[4], r[5]);
      for (std::size_t i = 0; i < 6; ++i) results[i] = &r[i];
    } else {
      status = soadyn::dynamics_derivatives<double>(model_, w.data, *w.derivatives, q, v, u, f);
      const DynamicsDerivatives& d = *w.derivatives;
      results = {&d.dqdd_dq, &d.dqdd_dv, &d.dqdd_du, &d.dtau_dq, &d.dtau_dv, &d.dtau_du};
    }
    for (std::size_t i = 0; i < 6; ++i) RowMajorOut(D[i] + k * nv * nv, nv, nv) = *results[i];
    return status;
  });
}

}  // namespace soadyn
