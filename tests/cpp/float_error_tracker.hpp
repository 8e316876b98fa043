// The float-vs-double tests' bookkeeping: the worst relative error per
// quantity (|float - double| / scale, by default max(1, |double|)) and a
// count of failures (an error above the tolerance, NaN included, or a
// failure reported by the test).
#pragma once
#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace soadyn_test {

class FloatErrorTracker {
 public:
  explicit FloatErrorTracker(double tolerance) : tolerance_(tolerance) {}

  template <class FloatMatrix, class DoubleMatrix>
  void compare(const std::string& quantity, const FloatMatrix& f, const DoubleMatrix& d, double scale) {
    const double error = (f.template cast<double>() - d).cwiseAbs().maxCoeff() / scale;
    auto it = std::find_if(worst_.begin(), worst_.end(), [&](const auto& w) { return w.first == quantity; });
    if (it == worst_.end()) it = worst_.insert(worst_.end(), {quantity, 0.0});
    it->second = std::max(it->second, error);
    if (!(error <= tolerance_)) ++failures_;  // NaN fails too
  }
  template <class FloatMatrix, class DoubleMatrix>
  void compare(const std::string& quantity, const FloatMatrix& f, const DoubleMatrix& d) {
    compare(quantity, f, d, std::max(1.0, static_cast<double>(d.cwiseAbs().maxCoeff())));
  }
  void fail(const std::string& what) {
    std::printf("%s\n", what.c_str());
    ++failures_;
  }
  double max_error() const {
    double worst = 0;
    for (const auto& w : worst_) worst = std::max(worst, w.second);
    return worst;
  }
  int failures() const { return failures_; }
  void print() const {
    for (const auto& w : worst_) std::printf("  %-32s max relative error %.3e\n", w.first.c_str(), w.second);
  }

 private:
  double tolerance_;
  std::vector<std::pair<std::string, double>> worst_;
  int failures_ = 0;
};

}  // namespace soadyn_test
