// A tension-against-length table for nonlinear springs and jounce stops,
// interpolated by the monotone piecewise-cubic Hermite interpolant of
// Fritsch & Carlson, "Monotone Piecewise Cubic Interpolation", SIAM J.
// Numerical Analysis 17(2), 1980, with the knot slopes of Fritsch & Butland
// (weighted harmonic mean of the neighbouring secants; zero at a local
// extremum of the data) and the one-sided three-point end slopes of Moler,
// "Numerical Computing with MATLAB", 2004, Sect. 3.4 (the same interpolant as
// scipy.interpolate.PchipInterpolator). The curve never overshoots the data,
// which is what a jounce stop needs. Outside the table the force continues
// linearly with the slope at the end knot.
#pragma once
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace soadyn {

template <class S>
struct ForceLawTpl {
  std::vector<S> length;  // knots, strictly increasing
  std::vector<S> force;   // tension at each knot (positive pulls the two points together)
  std::vector<S> slope;   // dF/dL at each knot (set by build_slopes)
  std::vector<S> integral_to_knot;  // int_{length[0]}^{length[k]} F dL

  bool empty() const { return length.empty(); }

  // Checks the table (at least two knots, finite values, strictly increasing
  // lengths; throws std::invalid_argument naming `owner`) and computes the slopes.
  void build(const std::string& owner) {
    const std::size_t n = length.size();
    if (n != force.size()) throw std::invalid_argument(owner + ": force_law lengths and forces differ in size");
    if (n < 2) throw std::invalid_argument(owner + ": force_law needs at least 2 points");
    for (std::size_t k = 0; k < n; ++k) {
      if (!std::isfinite(static_cast<double>(length[k])) || !std::isfinite(static_cast<double>(force[k])))
        throw std::invalid_argument(owner + ": force_law point " + std::to_string(k) + " is not finite");
      if (k > 0 && !(length[k] > length[k - 1]))
        throw std::invalid_argument(owner + ": force_law lengths must be strictly increasing (point " +
                                    std::to_string(k) + ")");
    }
    build_slopes();
    integral_to_knot.assign(n, S(0));
    for (std::size_t k = 0; k + 1 < n; ++k) {  // exact integral of the Hermite cubic over a segment
      const S h = length[k + 1] - length[k];
      integral_to_knot[k + 1] = integral_to_knot[k] + h * (force[k] + force[k + 1]) / S(2) +
                                h * h * (slope[k] - slope[k + 1]) / S(12);
    }
  }

  // Tension at `L` and, when asked, dF/dL and int_{length[0]}^{L} F.
  S value(S L, S* derivative = nullptr, S* integral = nullptr) const {
    const std::size_t n = length.size();
    if (L <= length[0] || L >= length[n - 1]) {  // linear continuation beyond the table
      const std::size_t e = L <= length[0] ? 0 : n - 1;
      const S x = L - length[e];
      if (derivative) *derivative = slope[e];
      if (integral) *integral = integral_to_knot[e] + force[e] * x + slope[e] * x * x / S(2);
      return force[e] + slope[e] * x;
    }
    std::size_t k = 0, hi = n - 1;  // bisection: length[k] <= L < length[hi]
    while (hi - k > 1) {
      const std::size_t mid = (k + hi) / 2;
      (length[mid] <= L ? k : hi) = mid;
    }
    const S h = length[k + 1] - length[k], t = (L - length[k]) / h, t2 = t * t, t3 = t2 * t;
    const S y0 = force[k], y1 = force[k + 1], d0 = h * slope[k], d1 = h * slope[k + 1];
    if (derivative)
      *derivative = ((S(6) * t2 - S(6) * t) * (y0 - y1) + (S(3) * t2 - S(4) * t + S(1)) * d0 +
                     (S(3) * t2 - S(2) * t) * d1) / h;
    if (integral) {
      const S t4 = t2 * t2;
      *integral = integral_to_knot[k] + h * ((t4 / S(2) - t3 + t) * y0 + (t4 / S(4) - S(2) * t3 / S(3) + t2 / S(2)) * d0 +
                                              (-t4 / S(2) + t3) * y1 + (t4 / S(4) - t3 / S(3)) * d1);
    }
    return (S(2) * t3 - S(3) * t2 + S(1)) * y0 + (t3 - S(2) * t2 + t) * d0 + (S(3) * t2 - S(2) * t3) * y1 +
           (t3 - t2) * d1;
  }

 private:
  static int sign(S x) { return (x > S(0)) - (x < S(0)); }

  // Knot slopes (Fritsch & Butland interior, three-point ends).
  void build_slopes() {
    const std::size_t n = length.size();
    slope.assign(n, S(0));
    std::vector<S> h(n - 1), secant(n - 1);
    for (std::size_t k = 0; k + 1 < n; ++k) {
      h[k] = length[k + 1] - length[k];
      secant[k] = (force[k + 1] - force[k]) / h[k];
    }
    if (n == 2) {
      slope[0] = slope[1] = secant[0];
      return;
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const S m0 = secant[k - 1], m1 = secant[k];
      if (sign(m0) != sign(m1) || m0 == S(0) || m1 == S(0)) continue;  // local extremum: flat
      const S w1 = S(2) * h[k] + h[k - 1], w2 = h[k] + S(2) * h[k - 1];
      slope[k] = (w1 + w2) / (w1 / m0 + w2 / m1);
    }
    slope[0] = end_slope(h[0], h[1], secant[0], secant[1]);
    slope[n - 1] = end_slope(h[n - 2], h[n - 3], secant[n - 2], secant[n - 3]);
  }

  static S end_slope(S h0, S h1, S m0, S m1) {
    S d = ((S(2) * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
    if (sign(d) != sign(m0))
      d = S(0);
    else if (sign(m0) != sign(m1) && std::abs(d) > S(3) * std::abs(m0))
      d = S(3) * m0;
    return d;
  }
};

}  // namespace soadyn
