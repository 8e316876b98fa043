// A value and one directional derivative: forward-mode automatic
// differentiation along one direction, the scalar parameter_sensitivity.cpp
// runs the dynamics on. Each operation applies the chain rule once:
// (a + e a')(b + e b') = ab + e (a'b + ab') with e^2 = 0.
//
// Eigen's AutoDiffScalar computes the same numbers, but its operators return
// expression templates, which the compiler resolves and instantiates for
// every expression of the sweeps; with this plain type the sensitivity's
// unit, the slowest of the build, compiles faster (docs/performance.md,
// build time). Its limits are double's (numeric_limits below), so that
// tolerances written std::numeric_limits<S>::epsilon() * x mean the same as
// in double.
#pragma once
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace soadyn {
namespace dual {

class DualNumber {
 public:
  constexpr DualNumber() = default;
  // Implicit from double: constants enter the dynamics with derivative 0.
  constexpr DualNumber(double value, double derivative = 0.0) : value_(value), derivative_(derivative) {}  // NOLINT

  constexpr double value() const { return value_; }
  constexpr double derivative() const { return derivative_; }

  DualNumber& operator+=(const DualNumber& b) {
    value_ += b.value_;
    derivative_ += b.derivative_;
    return *this;
  }
  DualNumber& operator-=(const DualNumber& b) {
    value_ -= b.value_;
    derivative_ -= b.derivative_;
    return *this;
  }
  DualNumber& operator*=(const DualNumber& b) { return *this = *this * b; }
  DualNumber& operator/=(const DualNumber& b) { return *this = *this / b; }

  friend DualNumber operator+(const DualNumber& a) { return a; }
  friend DualNumber operator-(const DualNumber& a) { return {-a.value_, -a.derivative_}; }
  friend DualNumber operator+(const DualNumber& a, const DualNumber& b) {
    return {a.value_ + b.value_, a.derivative_ + b.derivative_};
  }
  friend DualNumber operator-(const DualNumber& a, const DualNumber& b) {
    return {a.value_ - b.value_, a.derivative_ - b.derivative_};
  }
  friend DualNumber operator*(const DualNumber& a, const DualNumber& b) {
    return {a.value_ * b.value_, a.derivative_ * b.value_ + a.value_ * b.derivative_};
  }
  friend DualNumber operator/(const DualNumber& a, const DualNumber& b) {
    const double q = a.value_ / b.value_;
    return {q, (a.derivative_ - q * b.derivative_) / b.value_};
  }

  // Comparisons read the values: the dynamics branch on the value, as in double.
  friend bool operator==(const DualNumber& a, const DualNumber& b) { return a.value_ == b.value_; }
  friend bool operator!=(const DualNumber& a, const DualNumber& b) { return a.value_ != b.value_; }
  friend bool operator<(const DualNumber& a, const DualNumber& b) { return a.value_ < b.value_; }
  friend bool operator<=(const DualNumber& a, const DualNumber& b) { return a.value_ <= b.value_; }
  friend bool operator>(const DualNumber& a, const DualNumber& b) { return a.value_ > b.value_; }
  friend bool operator>=(const DualNumber& a, const DualNumber& b) { return a.value_ >= b.value_; }

 private:
  double value_ = 0.0;
  double derivative_ = 0.0;
};

// f(a + e a') = f(a) + e f'(a) a', given f(a) and f'(a).
inline DualNumber chain(double f, double f_prime, const DualNumber& a) { return {f, f_prime * a.derivative()}; }

inline DualNumber sqrt(const DualNumber& a) {
  const double r = std::sqrt(a.value());
  return {r, a.derivative() / (2.0 * r)};
}
inline DualNumber sin(const DualNumber& a) { return chain(std::sin(a.value()), std::cos(a.value()), a); }
inline DualNumber cos(const DualNumber& a) { return chain(std::cos(a.value()), -std::sin(a.value()), a); }
inline DualNumber tan(const DualNumber& a) {
  const double t = std::tan(a.value());
  return chain(t, 1.0 + t * t, a);
}
inline DualNumber exp(const DualNumber& a) {
  const double e = std::exp(a.value());
  return chain(e, e, a);
}
inline DualNumber log(const DualNumber& a) { return chain(std::log(a.value()), 1.0 / a.value(), a); }
inline DualNumber sinh(const DualNumber& a) { return chain(std::sinh(a.value()), std::cosh(a.value()), a); }
inline DualNumber cosh(const DualNumber& a) { return chain(std::cosh(a.value()), std::sinh(a.value()), a); }
inline DualNumber asin(const DualNumber& a) {
  return chain(std::asin(a.value()), 1.0 / std::sqrt(1.0 - a.value() * a.value()), a);
}
inline DualNumber acos(const DualNumber& a) {
  return chain(std::acos(a.value()), -1.0 / std::sqrt(1.0 - a.value() * a.value()), a);
}
inline DualNumber atan(const DualNumber& a) { return chain(std::atan(a.value()), 1.0 / (1.0 + a.value() * a.value()), a); }
inline DualNumber atan2(const DualNumber& y, const DualNumber& x) {
  const double r2 = x.value() * x.value() + y.value() * y.value();
  return {std::atan2(y.value(), x.value()), (x.value() * y.derivative() - y.value() * x.derivative()) / r2};
}
inline DualNumber pow(const DualNumber& a, double p) {
  return chain(std::pow(a.value(), p), p * std::pow(a.value(), p - 1.0), a);
}
inline DualNumber abs(const DualNumber& a) { return a.value() < 0.0 ? -a : a; }
inline DualNumber abs2(const DualNumber& a) { return a * a; }
inline DualNumber min(const DualNumber& a, const DualNumber& b) { return b < a ? b : a; }
inline DualNumber max(const DualNumber& a, const DualNumber& b) { return a < b ? b : a; }
inline bool isfinite(const DualNumber& a) { return std::isfinite(a.value()) && std::isfinite(a.derivative()); }
inline bool isnan(const DualNumber& a) { return std::isnan(a.value()) || std::isnan(a.derivative()); }
inline bool isinf(const DualNumber& a) { return std::isinf(a.value()) || std::isinf(a.derivative()); }

}  // namespace dual
}  // namespace soadyn

namespace std {
template <>
class numeric_limits<soadyn::dual::DualNumber> : public numeric_limits<double> {
 public:
  using DualNumber = soadyn::dual::DualNumber;
  static constexpr DualNumber epsilon() { return DualNumber(numeric_limits<double>::epsilon()); }
  static constexpr DualNumber min() { return DualNumber(numeric_limits<double>::min()); }
  static constexpr DualNumber max() { return DualNumber(numeric_limits<double>::max()); }
  static constexpr DualNumber lowest() { return DualNumber(numeric_limits<double>::lowest()); }
  static constexpr DualNumber infinity() { return DualNumber(numeric_limits<double>::infinity()); }
  static constexpr DualNumber quiet_NaN() { return DualNumber(numeric_limits<double>::quiet_NaN()); }
};
}  // namespace std

namespace Eigen {
template <>
struct NumTraits<soadyn::dual::DualNumber> : NumTraits<double> {
  using Real = soadyn::dual::DualNumber;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = double;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2,
    AddCost = 2,
    MulCost = 3,
  };
  static Real epsilon() { return Real(NumTraits<double>::epsilon()); }
  static Real dummy_precision() { return Real(NumTraits<double>::dummy_precision()); }
  static Real highest() { return Real(NumTraits<double>::highest()); }
  static Real lowest() { return Real(NumTraits<double>::lowest()); }
  static Real infinity() { return Real(NumTraits<double>::infinity()); }
  static Real quiet_NaN() { return Real(NumTraits<double>::quiet_NaN()); }
};
// A dual number times (or plus) a double is a dual number.
template <class BinaryOp>
struct ScalarBinaryOpTraits<soadyn::dual::DualNumber, double, BinaryOp> {
  using ReturnType = soadyn::dual::DualNumber;
};
template <class BinaryOp>
struct ScalarBinaryOpTraits<double, soadyn::dual::DualNumber, BinaryOp> {
  using ReturnType = soadyn::dual::DualNumber;
};
}  // namespace Eigen
