// The sequence lock of realtime/state_snapshot.hpp.
#include "soadyn/realtime/state_snapshot.hpp"

#include <stdexcept>

namespace soadyn {

static_assert(std::atomic<double>::is_always_lock_free, "publish() must not take a lock");

StateSnapshot::StateSnapshot(int nq, int nv) : nq_(nq), nv_(nv) {
  if (nq < 0 || nv < 0) throw std::invalid_argument("state snapshot: nq and nv must be >= 0");
  values_.reset(new std::atomic<double>[static_cast<std::size_t>(nq + nv)]);
  for (int i = 0; i < nq + nv; ++i) values_[i].store(0.0, std::memory_order_relaxed);
}

void StateSnapshot::publish(std::int64_t step, double time, const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v) noexcept {
  const std::uint64_t start = sequence_.load(std::memory_order_relaxed);
  sequence_.store(start + 1, std::memory_order_relaxed);  // odd: writing
  std::atomic_thread_fence(std::memory_order_release);
  step_.store(step, std::memory_order_relaxed);
  time_.store(time, std::memory_order_relaxed);
  for (int i = 0; i < nq_; ++i) values_[i].store(q[i], std::memory_order_relaxed);
  for (int i = 0; i < nv_; ++i) values_[nq_ + i].store(v[i], std::memory_order_relaxed);
  sequence_.store(start + 2, std::memory_order_release);  // even: done
  published_.fetch_add(1, std::memory_order_relaxed);
}

bool StateSnapshot::read(std::int64_t& step, double& time, Eigen::Ref<Eigen::VectorXd> q,
                         Eigen::Ref<Eigen::VectorXd> v, int attempts) const noexcept {
  if (q.size() != nq_ || v.size() != nv_) return false;
  for (int attempt = 0; attempt < attempts; ++attempt) {
    const std::uint64_t before = sequence_.load(std::memory_order_acquire);
    if (before == 0) return false;  // nothing published yet (ordered by the acquire, unlike published())
    if (before & 1u) continue;      // the writer is inside publish()
    step = step_.load(std::memory_order_relaxed);
    time = time_.load(std::memory_order_relaxed);
    for (int i = 0; i < nq_; ++i) q[i] = values_[i].load(std::memory_order_relaxed);
    for (int i = 0; i < nv_; ++i) v[i] = values_[nq_ + i].load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (sequence_.load(std::memory_order_relaxed) == before) return true;
  }
  return false;
}

}  // namespace soadyn
