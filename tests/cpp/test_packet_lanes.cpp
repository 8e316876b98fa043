// Packet4d's arithmetic and functions against the double operations they
// stand for (core/packet.hpp), lane by lane and bit for bit: on signed zeros,
// subnormals, infinities, NaNs of both signs, huge and tiny values and random
// doubles (a NaN result must be a NaN). Comparisons must answer for all lanes and record a split.
// Heap arrays of packets start on a cache line, whoever allocates them, and
// keep their values when resized.
// Compiled twice: for the baseline (test_packet_lanes) and for AVX2
// (test_packet_lanes_avx2), as the packet kernels are, since some functions
// take another instruction there.
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "failure_count.hpp"
#include "soadyn/core/packet.hpp"
#include "soadyn/spatial/types.hpp"

using namespace soadyn;
using soadyn_test::check;

namespace {

// Equal bits, or both NaN: which of two NaN operands an addition or a product
// passes on depends on the order the compiler gave the operands, in the
// double code as in the packet code.
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0 || (std::isnan(a) && std::isnan(b));
}

std::vector<double> test_values() {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values = {0.0,     -0.0,   1.0,   -1.0,   2.0,      0.5,     3.7,      -1e-310, 1e-310,
                                5e-324,  -5e-324, 1e300, -1e300, 1.7e308,  -1.7e308, inf,     -inf,     nan,
                                -nan,    1e-154, 4.0,   0.1,    -0.30000000000000004};
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
  for (int k = 0; k < 200; ++k) values.push_back(std::ldexp(unit(rng), exponent(rng)));
  return values;
}

// Checks one lane-wise operation over `count` packets built from `values`.
// Returns the number of lanes compared.
template <class PacketOp, class DoubleOp>
long check_operation(const std::string& name, const std::vector<double>& values, PacketOp packet_op,
                     DoubleOp double_op) {
  const std::size_t n = values.size();
  long lanes = 0;
  int wrong = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; j += 3) {
      const Packet4d a(Packet4d::Lanes{values[i], values[j], values[(i + j) % n], values[(i * 7 + 3) % n]});
      const Packet4d b(Packet4d::Lanes{values[j], values[i], values[(i * 3 + j) % n], values[(j * 5 + 1) % n]});
      const Packet4d r = packet_op(a, b);
      for (int l = 0; l < Packet4d::lanes; ++l, ++lanes)
        if (!same_bits(r[l], double_op(a[l], b[l])) && ++wrong <= 3)
          std::printf("%s(%.17g, %.17g): packet %.17g, double %.17g\n", name.c_str(), a[l], b[l], r[l],
                      double_op(a[l], b[l]));
    }
  check(wrong == 0, name + " equals the double operation in every lane");
  return lanes;
}

long check_arithmetic(const std::vector<double>& v) {
  long lanes = 0;
  lanes += check_operation("+", v, [](const Packet4d& a, const Packet4d& b) { return a + b; },
                           [](double a, double b) { return a + b; });
  lanes += check_operation("-", v, [](const Packet4d& a, const Packet4d& b) { return a - b; },
                           [](double a, double b) { return a - b; });
  lanes += check_operation("*", v, [](const Packet4d& a, const Packet4d& b) { return a * b; },
                           [](double a, double b) { return a * b; });
  lanes += check_operation("/", v, [](const Packet4d& a, const Packet4d& b) { return a / b; },
                           [](double a, double b) { return a / b; });
  lanes += check_operation("negation", v, [](const Packet4d& a, const Packet4d&) { return -a; },
                           [](double a, double) { return -a; });
  lanes += check_operation("+=", v, [](Packet4d a, const Packet4d& b) { return a += b; },
                           [](double a, double b) { return a += b; });
  lanes += check_operation("*=", v, [](Packet4d a, const Packet4d& b) { return a *= b; },
                           [](double a, double b) { return a *= b; });
  return lanes;
}

long check_functions(const std::vector<double>& v) {
  long lanes = 0;
  lanes += check_operation("abs", v, [](const Packet4d& a, const Packet4d&) { return abs(a); },
                           [](double a, double) { return std::fabs(a); });
  lanes += check_operation("sqrt", v, [](const Packet4d& a, const Packet4d&) { return sqrt(a); },
                           [](double a, double) { return std::sqrt(a); });
  lanes += check_operation("max", v, [](const Packet4d& a, const Packet4d& b) { return max(a, b); },
                           [](double a, double b) { return std::max(a, b); });
  lanes += check_operation("min", v, [](const Packet4d& a, const Packet4d& b) { return min(a, b); },
                           [](double a, double b) { return std::min(a, b); });
  lanes += check_operation("sin", v, [](const Packet4d& a, const Packet4d&) { return sin(a); },
                           [](double a, double) { return std::sin(a); });
  lanes += check_operation("cos", v, [](const Packet4d& a, const Packet4d&) { return cos(a); },
                           [](double a, double) { return std::cos(a); });
  lanes += check_operation("atan2", v, [](const Packet4d& a, const Packet4d& b) { return atan2(a, b); },
                           [](double a, double b) { return std::atan2(a, b); });
  return lanes;
}

// A comparison answers lane 0's result and records a split.
void check_comparisons() {
  clear_lane_divergence();
  const Packet4d low(1.0), high(2.0);
  check(low < high && !(high < low) && low <= high && high >= low && low != high && !(low == high),
        "comparisons of packets whose lanes agree");
  check(!lanes_diverged(), "no split recorded when the lanes agree");
  const Packet4d mixed(Packet4d::Lanes{1.0, 3.0, 1.0, 1.0});
  const bool answer = mixed < high;
  check(answer && lanes_diverged(), "a split comparison answers lane 0 and records the split");
  clear_lane_divergence();
  check(!lanes_diverged(), "clear_lane_divergence clears the record");
  const Packet4d one_nan(Packet4d::Lanes{1.0, 1.0, 1.0, std::numeric_limits<double>::quiet_NaN()});
  check(!isfinite(one_nan) && isnan(one_nan), "a NaN in one lane makes the packet non-finite");
}

// A class template of the library on its scalar, as Transform<S> is.
template <class S>
struct Holder {
  S x;
};
static_assert(holds_packets_v<Packet4d> && holds_packets_v<Mat6N<Packet4d>> && holds_packets_v<Holder<Packet4d>>);
static_assert(!holds_packets_v<double> && !holds_packets_v<Vec6<double>> && !holds_packets_v<Holder<double>>);

bool starts_on(const void* p, std::uintptr_t boundary) { return reinterpret_cast<std::uintptr_t>(p) % boundary == 0; }

// The ways the library allocates arrays of packets: Eigen's dynamic arrays
// (built, copied, resized, resized keeping their values) and the library's
// vectors of Eigen matrices and of its own types on packets.
void check_storage_alignment() {
  bool aligned = true, kept = true;
  for (int n = 1; n < 40; ++n) {
    VecX<Packet4d> x(n);
    for (int k = 0; k < n; ++k) x[k] = Packet4d(Packet4d::Lanes{double(k), 1.0, 2.0, -double(k)});
    const VecX<Packet4d> copy = x;
    MatX<Packet4d> m(n, 3);
    x.conservativeResize(n + 5);
    for (int k = 0; k < n; ++k) kept = kept && x[k][0] == double(k) && x[k][3] == -double(k);
    aligned_vector<Vec6<Packet4d>> sixes(static_cast<std::size_t>(n));
    aligned_vector<Holder<Packet4d>> held(static_cast<std::size_t>(n));
    aligned = aligned && starts_on(copy.data(), 64) && starts_on(m.data(), 64) && starts_on(x.data(), 64) &&
              starts_on(sixes.data(), 64) && starts_on(held.data(), 64);
  }
  check(aligned, "Eigen's arrays and the library's vectors of packets start on a cache line");
  check(kept, "a resized Eigen array of packets keeps its values");
}

}  // namespace

int main() {
#if defined(__AVX__)
  const char* build = "AVX2";
#else
  const char* build = "baseline";
#endif
  const std::vector<double> values = test_values();
  const long arithmetic = check_arithmetic(values);
  const long functions = check_functions(values);
  check_comparisons();
  check_storage_alignment();
  std::printf("%s build: %ld lanes of arithmetic and %ld lanes of functions against the double operations\n", build,
              arithmetic, functions);
  if (soadyn_test::failures) {
    std::printf("test_packet_lanes: FAIL: %d checks\n", soadyn_test::failures);
    return 1;
  }
  std::printf("test_packet_lanes: PASS: %s build, every lane bit for bit\n", build);
  return 0;
}
