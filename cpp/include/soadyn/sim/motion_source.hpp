// Prescribed-motion sources: position, velocity and acceleration of one
// scalar DOF as functions of time. A prescribed DOF driven by a source
// follows it exactly: the simulator writes the source's position and velocity
// into the state at every step instead of integrating its accelerations.
//
// All memory (spline tables, callbacks) is taken when a source is built;
// sampling allocates nothing and never throws.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <variant>
#include <vector>

namespace soadyn {

template <class S>
struct MotionSample {
  S position = S(0), velocity = S(0), acceleration = S(0);
};

// q = q0 + v0 (t - t0) + a (t - t0)^2 / 2: constant acceleration, or with
// a = 0 constant velocity (a turntable at a fixed rate), or holding still.
template <class S>
struct ConstantAcceleration {
  S t0 = S(0), q0 = S(0), v0 = S(0), a = S(0);
  MotionSample<S> sample(S t) const {
    const S s = t - t0;
    return {q0 + v0 * s + a * s * s / S(2), v0 + a * s, a};
  }
};

// q = sum_k c_k (t - t0)^k, degree at most 7.
template <class S>
struct Polynomial {
  static constexpr int max_degree = 7;
  S t0 = S(0);
  std::array<S, max_degree + 1> c{};
  int degree = 0;
  MotionSample<S> sample(S t) const {
    const S s = t - t0;
    MotionSample<S> m;
    for (int k = degree; k >= 0; --k) {  // Horner for q, q', q''
      m.acceleration = m.acceleration * s + S(2) * m.velocity;
      m.velocity = m.velocity * s + m.position;
      m.position = m.position * s + c[static_cast<std::size_t>(k)];
    }
    return m;
  }
};

// Cycloidal rest-to-rest motion from q0 at t0 to q1 at t0 + duration (Saha,
// Shah & Nandihal 2013, Eq. 34): q = q0 + (q1 - q0) [s/T - sin(2 pi s/T) / (2 pi)], held
// before and after.
template <class S>
struct Cycloidal {
  S t0 = S(0), duration = S(1), q0 = S(0), q1 = S(0);
  MotionSample<S> sample(S t) const {
    using std::cos;
    using std::sin;
    const S two_pi = S(2) * S(M_PI);
    const S tau = std::clamp((t - t0) / duration, S(0), S(1));
    const S h = q1 - q0;
    if (tau <= S(0) || tau >= S(1)) return {tau <= S(0) ? q0 : q1, S(0), S(0)};
    return {q0 + h * (tau - sin(two_pi * tau) / two_pi), h / duration * (S(1) - cos(two_pi * tau)),
            h * two_pi / (duration * duration) * sin(two_pi * tau)};
  }
};

// Natural cubic spline through (t_k, q_k), clamped to the end values
// outside the table (zero velocity and acceleration there).
template <class S>
struct CubicSpline {
  std::vector<S> t, q, second;  // knots, values, second derivatives at the knots

  CubicSpline() = default;
  CubicSpline(std::vector<S> times, std::vector<S> values) : t(std::move(times)), q(std::move(values)) {
    const std::size_t n = t.size();
    if (n < 2 || q.size() != n) throw std::invalid_argument("spline: need at least two knots and as many values");
    for (std::size_t k = 1; k < n; ++k)
      if (!(t[k] > t[k - 1])) throw std::invalid_argument("spline: knot times must increase strictly");
    second.assign(n, S(0));
    std::vector<S> upper(n, S(0));
    for (std::size_t k = 1; k + 1 < n; ++k) {  // tridiagonal solve (natural end conditions)
      const S h0 = t[k] - t[k - 1], h1 = t[k + 1] - t[k];
      const S rhs = S(6) * ((q[k + 1] - q[k]) / h1 - (q[k] - q[k - 1]) / h0);
      const S diag = S(2) * (h0 + h1) - h0 * upper[k - 1];
      upper[k] = h1 / diag;
      second[k] = (rhs - h0 * second[k - 1]) / diag;
    }
    for (std::size_t k = n - 1; k-- > 1;) second[k] -= upper[k] * second[k + 1];
  }

  MotionSample<S> sample(S time) const {
    if (time <= t.front()) return {q.front(), S(0), S(0)};
    if (time >= t.back()) return {q.back(), S(0), S(0)};
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
    const S h = t[k + 1] - t[k], a = (t[k + 1] - time) / h, b = (time - t[k]) / h;
    const S m0 = second[k], m1 = second[k + 1];
    return {a * q[k] + b * q[k + 1] + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / S(6),
            (q[k + 1] - q[k]) / h + ((S(1) - S(3) * a * a) * m0 + (S(3) * b * b - S(1)) * m1) * h / S(6),
            a * m0 + b * m1};
  }
};

// A user function of time (C++). It must not allocate or throw if the
// simulation is to stay real-time. A Simulator keeps its last finite
// sample and reuses it when asked for the same time again (RK4 asks for
// t + h/2 twice, and for t + h in three places).
template <class S>
struct CallbackSource {
  std::function<MotionSample<S>(S)> fn;
  MotionSample<S> sample(S t) const { return fn(t); }
};

template <class S>
using MotionSource = std::variant<ConstantAcceleration<S>, Polynomial<S>, Cycloidal<S>, CubicSpline<S>, CallbackSource<S>>;

template <class S>
MotionSample<S> sample_source(const MotionSource<S>& source, S t) {
  return std::visit([t](const auto& s) { return s.sample(t); }, source);
}

}  // namespace soadyn
