// A fixed set of worker threads for data-parallel loops (batched dynamics,
// rollouts): parallel_for(n, grain, fn) splits [0, n) into chunks of `grain`
// indices that the caller's thread and the workers take in turn from a
// shared counter (a slow or preempted thread takes fewer chunks), and
// returns when every chunk is done. Which thread computes an index never
// changes a result: each index writes only its own outputs, with its
// thread's workspace (`worker`, 0 .. size() - 1, the caller being 0).
//
// Waiting, a thread spins for a short while (kSpinWait) before it sleeps on
// a condition variable: a worker between the calls of a loop of batched
// calls, and the caller for the workers' last chunks, then carry on without
// the wake-up of a sleeping thread (tens of microseconds on a virtual
// machine, against a batched call of a few hundred).
//
// Not for the real-time loop: waking the workers takes a mutex and a
// condition variable. Calls from several threads take turns. An exception
// thrown by `fn` stops the loop from taking new chunks and is rethrown by
// parallel_for once every thread is idle again. `fn` must not call
// parallel_for on the same pool (it would wait for itself).
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <type_traits>
#include <mutex>
#include <thread>
#include <vector>

#include "soadyn/core/interrupt.hpp"

namespace soadyn {

class ThreadPool {
 public:
  // fn(begin, end, worker): a reference to the caller's function object,
  // which outlives the parallel_for it is passed to. Unlike a std::function,
  // taking it allocates nothing, whatever the function captures.
  class ChunkFunction {
   public:
    template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, ChunkFunction>>>
    ChunkFunction(F&& fn)  // NOLINT: implicit, from the lambda at the call
        : fn_(static_cast<const void*>(std::addressof(fn))), call_(&call<std::remove_reference_t<F>>) {}
    void operator()(std::int64_t begin, std::int64_t end, int worker) const { call_(fn_, begin, end, worker); }

   private:
    template <class F>
    static void call(const void* fn, std::int64_t begin, std::int64_t end, int worker) {
      (*static_cast<F*>(const_cast<void*>(fn)))(begin, end, worker);
    }
    const void* fn_;
    void (*call_)(const void*, std::int64_t, std::int64_t, int);
  };

  // `threads` in all, the calling thread included (>= 1; 0: one per
  // hardware thread). Throws std::invalid_argument for a negative count.
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }
  void parallel_for(std::int64_t n, std::int64_t grain, const ChunkFunction& fn);

  // An Interrupt (soadyn/core/interrupt.hpp; null: none) that the calling thread
  // polls between chunks and in stop_requested(); when it asks, no new chunk
  // starts and parallel_for returns early with interrupted() true. The
  // caller keeps it alive until parallel_for returns.
  void set_interrupt(const Interrupt* interrupt) { interrupt_ = interrupt; }
  bool interrupted() const { return interrupted_.load(std::memory_order_relaxed); }
  // For long chunks (rollouts), asked between their steps: whether the loop
  // is stopping (an exception elsewhere or the Interrupt). Polls the
  // Interrupt when `worker` is the calling thread (0).
  bool stop_requested(int worker);

  // One per hardware thread (at least 1), as the process first found them.
  static int hardware_threads();

 private:
  void work(int worker);
  void stop_workers();
  void take_chunks(int worker);

  // How long a waiting thread spins before it sleeps.
  static constexpr std::chrono::microseconds kSpinWait{200};

  std::vector<std::thread> workers_;
  std::mutex turn_;   // one parallel_for at a time
  std::mutex mutex_;  // taken to change what follows (a sleeper then sees it)
  std::condition_variable wake_, idle_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> busy_{0};
  std::atomic<bool> stopping_{false};
  const ChunkFunction* job_ = nullptr;
  std::int64_t n_ = 0, grain_ = 1;
  std::atomic<std::int64_t> next_{0};
  std::atomic<bool> failed_{false}, interrupted_{false};
  const Interrupt* interrupt_ = nullptr;
  std::exception_ptr error_;
};

}  // namespace soadyn
