// Timing in many short batches, shared by the C++ benchmarks. On a shared
// machine whose speed drifts, algorithms that are compared are timed batch by
// batch in turn, so drifts hit them alike, and the median per-call time of
// each is reported.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace soadyn_bench {

using Clock = std::chrono::steady_clock;

constexpr double kBatchSeconds = 100e-6;   // target length of one timed batch
constexpr double kCalibrateSeconds = 5e-3;  // warm-up and per-call estimate
constexpr int kStates = 8;                  // inputs cycled through, so no call repeats the last one

// One algorithm under test: `run(k)` makes one call on input state k.
struct Timed {
  Timed(std::string label_, std::function<void(int)> run_) : label(std::move(label_)), run(std::move(run_)) {}
  std::string label;
  std::function<void(int)> run;
  int batch = 1;                 // calls per timed batch
  std::vector<double> per_call;  // seconds, one entry per batch
};

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Warms up and picks the batch size that lasts about kBatchSeconds.
inline void calibrate(Timed& t) {
  int calls = 0;
  const Clock::time_point start = Clock::now();
  while (seconds_since(start) < kCalibrateSeconds) t.run(calls++ % kStates);
  const double per_call = kCalibrateSeconds / calls;
  t.batch = std::max(1, static_cast<int>(std::lround(kBatchSeconds / per_call)));
}

inline void time_one_batch(Timed& t) {
  const Clock::time_point start = Clock::now();
  for (int k = 0; k < t.batch; ++k) t.run(k % kStates);
  t.per_call.push_back(seconds_since(start) / t.batch);
}

inline double median(std::vector<double> x) {
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

// Median microseconds per call of each algorithm.
inline std::vector<double> median_microseconds(const std::vector<Timed>& algorithms) {
  std::vector<double> result;
  for (const Timed& t : algorithms) result.push_back(1e6 * median(t.per_call));
  return result;
}

inline const char* compiler() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "GCC " __VERSION__;
#else
  return "unknown compiler";
#endif
}

}  // namespace soadyn_bench
