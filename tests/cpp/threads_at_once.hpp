// Calls from several threads released at once, for the tests of kernels
// chosen on their first call (processor_features.hpp): every thread starts
// and waits at a spin barrier, so the process's first calls race.
#pragma once
#include <atomic>
#include <thread>
#include <vector>

namespace soadyn_test {

// Runs call(t) `calls` times on each thread t of `threads`, all released at
// once. Returns how many calls returned false.
template <class Call>
int calls_from_threads_at_once(int threads, int calls, const Call& call) {
  std::atomic<int> ready{0}, failed{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      ++ready;
      while (ready.load() < threads) {
      }
      for (int c = 0; c < calls; ++c)
        if (!call(t)) ++failed;
    });
  for (std::thread& thread : pool) thread.join();
  return failed.load();
}

}  // namespace soadyn_test
