// The worker threads of parallel/thread_pool.hpp.
#include "soadyn/parallel/thread_pool.hpp"

#include <algorithm>
#include <stdexcept>

namespace soadyn {

int ThreadPool::hardware_threads() {
  // Asked once: std::thread::hardware_concurrency reads a file of /sys at each
  // call, several microseconds, and the batched calls ask at every call.
  static const int count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return count;
}

ThreadPool::ThreadPool(int threads) {
  if (threads < 0) throw std::invalid_argument("thread count must be >= 0 (0: one per hardware thread)");
  const int total = threads == 0 ? hardware_threads() : threads;
  workers_.reserve(static_cast<std::size_t>(total - 1));
  try {
    for (int w = 1; w < total; ++w) workers_.emplace_back([this, w] { work(w); });
  } catch (...) {  // no thread to be had: stop the ones started, then report
    stop_workers();
    throw;
  }
}

void ThreadPool::stop_workers() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_.store(true, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
}

ThreadPool::~ThreadPool() { stop_workers(); }

bool ThreadPool::stop_requested(int worker) {
  if (worker == 0 && interrupt_requested(interrupt_)) {
    interrupted_.store(true, std::memory_order_relaxed);
    failed_.store(true, std::memory_order_relaxed);
  }
  return failed_.load(std::memory_order_relaxed);
}

void ThreadPool::take_chunks(int worker) {
  for (;;) {
    if (stop_requested(worker)) return;
    const std::int64_t begin = next_.fetch_add(grain_, std::memory_order_relaxed);
    if (begin >= n_) return;
    try {
      (*job_)(begin, std::min(begin + grain_, n_), worker);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);
      return;
    }
  }
}

namespace {

// Whether `ready()` came true within `budget`, asked in a spin loop. The
// spinning thread yields now and then, so that with more threads than
// processors a thread that still has a chunk to finish gets one.
template <class Ready>
bool spin_until(Ready&& ready, std::chrono::microseconds budget) {
  const auto deadline = std::chrono::steady_clock::now() + budget;
  for (unsigned k = 1;; ++k) {
    if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    if (k % 64 == 0) {
      if (std::chrono::steady_clock::now() > deadline) return ready();
      std::this_thread::yield();
    }
  }
}

}  // namespace

void ThreadPool::work(int worker) {
  std::uint64_t seen = 0;
  const auto job_or_stop = [&] {
    return stopping_.load(std::memory_order_acquire) || generation_.load(std::memory_order_acquire) != seen;
  };
  for (;;) {
    if (!spin_until(job_or_stop, kSpinWait)) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, job_or_stop);
    }
    if (stopping_.load(std::memory_order_acquire)) return;
    seen = generation_.load(std::memory_order_acquire);
    take_chunks(worker);
    if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);  // the caller is awake, or asleep on idle_ with its check made
      idle_.notify_one();
    }
  }
}

void ThreadPool::parallel_for(std::int64_t n, std::int64_t grain, const ChunkFunction& fn) {
  if (n <= 0) return;
  std::lock_guard<std::mutex> turn(turn_);
  job_ = &fn;
  n_ = n;
  grain_ = std::max<std::int64_t>(1, grain);
  next_.store(0, std::memory_order_relaxed);
  failed_.store(false, std::memory_order_relaxed);
  interrupted_.store(false, std::memory_order_relaxed);
  error_ = nullptr;
  const bool parallel = !workers_.empty() && n > grain_;
  if (parallel) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_release);  // publishes the job to spinning workers
    }
    wake_.notify_all();
  }
  take_chunks(0);
  if (parallel) {
    const auto all_idle = [&] { return busy_.load(std::memory_order_acquire) == 0; };
    if (!spin_until(all_idle, kSpinWait)) {
      std::unique_lock<std::mutex> lock(mutex_);
      idle_.wait(lock, all_idle);
    }
  }
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

}  // namespace soadyn
