// The latest state of a running simulation, for readers on other threads
// (a viewer, a telemetry thread) that must never slow the real-time loop.
//
// One writer (the HIL loop) publishes (step, time, q, v); any number of
// readers copy the latest published state. A sequence lock: the writer makes
// the sequence odd, stores the values, and makes it even again; a reader
// copies the values between two reads of the sequence and keeps the copy
// only when both reads are the same even number, else tries again. The
// values are relaxed atomics, so a torn read is detected, never undefined
// behaviour, and the fences order them against the sequence (Boehm, "Can
// seqlocks get along with programming language memory models?", 2012).
//
// The writer never waits, allocates, locks or throws: publish() is nq + nv + 4
// stores. A reader may retry while the writer is inside publish(); read()
// gives up after `attempts` tries and returns false (then the caller keeps
// its previous copy). The constructor allocates the storage; nothing else
// does.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>

#include <Eigen/Core>

namespace soadyn {

class StateSnapshot {
 public:
  StateSnapshot(int nq, int nv);

  // The writer's side (one thread only).
  void publish(std::int64_t step, double time, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v) noexcept;

  // A reader's side (any thread). Fills the outputs (q: nq, v: nv, sized by
  // the caller) with one consistent published state; false when nothing was
  // published yet or the writer kept it busy for `attempts` tries.
  bool read(std::int64_t& step, double& time, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> v,
            int attempts = 1000) const noexcept;

  // How many states were published (0: none yet).
  std::int64_t published() const noexcept { return published_.load(std::memory_order_relaxed); }
  int nq() const { return nq_; }
  int nv() const { return nv_; }

 private:
  int nq_, nv_;
  std::atomic<std::uint64_t> sequence_{0};
  std::atomic<std::int64_t> step_{0}, published_{0};
  std::atomic<double> time_{0.0};
  std::unique_ptr<std::atomic<double>[]> values_;  // q then v
};

}  // namespace soadyn
