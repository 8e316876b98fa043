// The dynamics of many states of one model at once, on a thread pool: row k
// of the outputs is what the single call computes at row k of the inputs,
// bit for bit (the same algorithm on the same numbers; only the thread and
// its Data differ). One Data (and derivative workspace) per thread, built by
// the constructor, and the packet workspaces, built by the first packet
// call; after that a call allocates nothing (tests/cpp/test_batch.cpp counts),
// with packets too: a packet call takes the model's values again into its
// packet model in place (PacketModel::refresh), so values and prescribed
// flags may change between calls.
//
// Lanes: on processors with AVX2 and FMA, the forward, inverse and hybrid
// dynamics and the mass matrix take four rows per pass
// (algorithms/packet_dynamics.hpp), with the same results, bit for bit, and
// the same per-row statuses; but a rigid tree's mass matrix, which is then
// the baseline kernel's, not the single call's AVX2 FMA kernel's (they
// differ in the last bits). set_lanes(1) keeps the one-row path. The
// derivatives stay one row at a time; so does a call of fewer than
// packet_minimum_rows rows, whose results are then the single call's, the
// mass matrix included.
//
// Arrays are row-major with the batch first: Q is n x nq, V, TAU, U, QDD n x
// nv, F (optional, nullptr: none) n x nbodies x 6 body-frame wrenches, mass
// matrices n x nv x nv, derivatives six arrays of n x nv x nv. Inputs are not
// checked here (the bindings check them, naming the row); a row whose
// dynamics fail (a singular articulated inertia) leaves its outputs as the
// algorithm left them and is counted in the outcome.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "soadyn/algorithms/packet_dynamics.hpp"
#include "soadyn/model/data.hpp"
#include "soadyn/parallel/thread_pool.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn {

struct BatchOutcome {
  std::int64_t failed_rows = 0;
  std::int64_t first_failed_row = -1;  // the lowest failing row
  Status first_status;                 // its status
};

class BatchDynamics {
 public:
  // `model` must outlive this object and keep its structure; `threads` as
  // ThreadPool (0: one per hardware thread).
  BatchDynamics(const Model& model, int threads = 0);
  ~BatchDynamics();

  int threads() const { return pool_.size(); }
  // The Interrupt polled between rows (ThreadPool::set_interrupt).
  void set_interrupt(const Interrupt* interrupt) { pool_.set_interrupt(interrupt); }
  const Model& model() const { return model_; }

  // The widest packet this processor runs: PacketDynamics::lanes where
  // PacketDynamics::available(), else 1.
  static int widest_lanes();
  // The fewest rows a call runs in packets: one packet's. A packet call
  // first takes the model's values into packets (PacketModel::refresh, in
  // place), which one packet already repays (docs/guides/batch.md, small
  // batches).
  static constexpr std::int64_t packet_minimum_rows = PacketDynamics::lanes;
  // Rows per pass from now on: 1, or PacketDynamics::lanes where available
  // (std::invalid_argument otherwise, naming the value). Starts at
  // widest_lanes(). Models the packet path does not serve run one row at a
  // time whatever the lanes.
  void set_lanes(int lanes);
  int lanes() const { return lanes_; }

  BatchOutcome forward_dynamics(std::int64_t n, const double* Q, const double* V, const double* TAU, const double* F,
                                double* QDD);
  BatchOutcome inverse_dynamics(std::int64_t n, const double* Q, const double* V, const double* QDD, const double* F,
                                double* TAU);
  BatchOutcome hybrid_dynamics(std::int64_t n, const double* Q, const double* V, const double* U, const double* F,
                               double* QDD, double* TAU);
  BatchOutcome mass_matrix(std::int64_t n, const double* Q, double* M);
  // dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du (analysis/dynamics_derivatives.hpp):
  // the analytic recursion for trees, the dual-number sweeps for loops,
  // flexible bodies and point springs, as the single call chooses.
  BatchOutcome dynamics_derivatives(std::int64_t n, const double* Q, const double* V, const double* U,
                                    const double* F, const std::array<double*, 6>& D);

  // Whether dynamics_derivatives takes the dual-number sweeps for `model`.
  static bool derivatives_by_dual_numbers(const Model& model);

 private:
  struct Workspace;
  // fn(row, workspace) -> Status over rows [0, n) on the pool; with packets
  // on, packet_fn(first row, packet dynamics, statuses) over full groups of
  // four rows instead (the rows past the last full group by fn).
  template <class RowFn>
  BatchOutcome for_rows(std::int64_t n, RowFn&& fn);
  template <class RowFn, class PacketFn>
  BatchOutcome for_rows(std::int64_t n, RowFn&& fn, PacketFn&& packet_fn);
  // Whether this call takes the packet path; if so, the packet model takes
  // the model's values and every workspace has its packet dynamics.
  bool prepare_packets();
  // call(data, q, v, x, f, out) -> Status per row, for one nv-vector out
  // per row; packet_call the PacketDynamics member for four rows.
  template <class Call, class PacketCall>
  BatchOutcome vector_call(std::int64_t n, const double* Q, const double* V, const double* X, const double* F,
                           double* OUT, Call&& call, PacketCall&& packet_call);

  const Model& model_;
  int lanes_;
  std::unique_ptr<PacketModel> packet_model_;  // built at the first packet call
  ThreadPool pool_;
  std::vector<std::unique_ptr<Workspace>> workspaces_;  // one per thread
};

}  // namespace soadyn
