// Gauss-Legendre quadrature on [-1, 1] and composite rules on segments.
#pragma once
#include <cmath>
#include <limits>
#include "soadyn/spatial/types.hpp"

namespace soadyn {

template <class S>
struct QuadratureRule {
  VecX<S> points;   // abscissae in [-1, 1]
  VecX<S> weights;
};

// Legendre polynomial P_n(x) and its derivative, by the three-term
// recurrence (k + 1) P_{k+1} = (2k + 1) x P_k - k P_{k-1} and
// P_n'(x) = n (x P_n - P_{n-1}) / (x^2 - 1) (valid inside (-1, 1)).
template <class S>
void legendre_with_derivative(int n, const S& x, S& p, S& dp) {
  S previous(1);
  p = x;
  for (int k = 1; k < n; ++k) {
    const S next = (S(2 * k + 1) * x * p - S(k) * previous) / S(k + 1);
    previous = p;
    p = next;
  }
  dp = S(n) * (x * p - previous) / (x * x - S(1));
}

// The n-point rule (exact for polynomials of degree 2n - 1): the roots of
// P_n by Newton's method from x_i ~ cos(pi (i + 3/4) / (n + 1/2)), weights
// w_i = 2 / ((1 - x_i^2) P_n'(x_i)^2) (Abramowitz & Stegun 25.4.29). n >= 1.
template <class S>
QuadratureRule<S> gauss_legendre_rule(int n) {
  using std::abs;
  using std::cos;
  const S pi = S(3.14159265358979323846);
  QuadratureRule<S> rule{VecX<S>(n), VecX<S>(n)};
  for (int i = 0; i < n; ++i) {
    S x = cos(pi * (S(i) + S(0.75)) / (S(n) + S(0.5)));
    S p, dp;
    for (int iteration = 0; iteration < 100; ++iteration) {
      legendre_with_derivative(n, x, p, dp);
      const S step = p / dp;
      x -= step;
      if (abs(step) <= S(4) * std::numeric_limits<S>::epsilon()) break;
    }
    legendre_with_derivative(n, x, p, dp);
    rule.points[i] = x;
    rule.weights[i] = S(2) / ((S(1) - x * x) * dp * dp);
  }
  return rule;
}

// Calls visit(x, w) for every point x and weight w of the composite rule:
// `rule` mapped onto each of `segments` equal segments of [a, b].
template <class S, class Visitor>
void for_each_quadrature_point(const S& a, const S& b, int segments, const QuadratureRule<S>& rule,
                               Visitor&& visit) {
  const S h = (b - a) / S(segments);
  for (int s = 0; s < segments; ++s) {
    const S centre = a + (S(s) + S(0.5)) * h;
    for (Eigen::Index i = 0; i < rule.points.size(); ++i)
      visit(centre + S(0.5) * h * rule.points[i], S(0.5) * h * rule.weights[i]);
  }
}

}  // namespace soadyn
