// Exponential maps used to integrate joints on their manifolds: SO(3) as
// unit quaternions (x, y, z, w), SE(3) and SE(2) with body-frame twists.
#pragma once
#include <array>
#include <cmath>
#include "soadyn/spatial/transform.hpp"

namespace soadyn {

// The coefficients near() (a series) where t2 < threshold, and far() (the
// closed form) elsewhere. A packet of states (core/packet.hpp) takes each
// lane's own branch: where its lanes disagree, both are formed and each lane
// keeps the one the double computation takes, so no lane splits on a series
// threshold and each equals its double's, bit for bit.
template <class S, class Near, class Far>
auto series_near_zero(const S& t2, const S& threshold, Near&& near, Far&& far) {
  if constexpr (is_packet_scalar_v<S>) {
    const int below = lanes_below(t2, threshold);
    if (below == S::lanes) return near();
    if (below == 0) return far();
    auto out = far();
    const auto series = near();
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = blend_below(t2, threshold, series[k], out[k]);
    return out;
  } else {
    return t2 < threshold ? near() : far();
  }
}

// Unit quaternion (x, y, z, w) of the rotation vector phi.
template <class S>
Eigen::Matrix<S, 4, 1> quaternion_exp(const Vec3<S>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S theta2 = phi.squaredNorm();
  // sin(theta/2)/theta and cos(theta/2) with their Taylor series near zero
  // (no square root there: its derivative at zero is not finite, which a
  // dual-number scalar would carry).
  const auto [k, w] = series_near_zero(
      theta2, S(1e-8), [&] { return std::array<S, 2>{S(0.5) - theta2 / S(48), S(1) - theta2 / S(8)}; },
      [&] {
        const S theta = sqrt(theta2);
        return std::array<S, 2>{sin(theta / S(2)) / theta, cos(theta / S(2))};
      });
  Eigen::Matrix<S, 4, 1> q;
  q << k * phi, w;
  return q;
}

// Hamilton product a * b of quaternions stored (x, y, z, w).
template <class S>
Eigen::Matrix<S, 4, 1> quaternion_multiply(const S* a, const S* b) {
  Eigen::Matrix<S, 4, 1> r;
  r[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
  r[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
  r[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
  r[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
  return r;
}

// Left Jacobian V of SO(3) at phi: the translation of exp((phi, u)) in SE(3)
// is V u, V = I + (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2.
template <class S>
Mat3<S> so3_left_jacobian(const Vec3<S>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S t2 = phi.squaredNorm();
  const auto [a, b] = series_near_zero(
      t2, S(1e-8), [&] { return std::array<S, 2>{S(0.5) - t2 / S(24), S(1) / S(6) - t2 / S(120)}; },
      [&] {
        const S t = sqrt(t2);
        return std::array<S, 2>{(S(1) - cos(t)) / t2, (t - sin(t)) / (t2 * t)};
      });
  const Mat3<S> k = skew(phi);
  return Mat3<S>::Identity() + a * k + b * (k * k);
}

// Right Jacobian of SO(3) at theta: the body-frame angular velocity of
// exp([theta]x) is Jr(theta) dtheta/dt,
// Jr = I - (1 - cos t)/t^2 [theta]x + (t - sin t)/t^3 [theta]x^2 (= Jl(-theta)).
template <class S>
Mat3<S> so3_right_jacobian(const Vec3<S>& theta) {
  return so3_left_jacobian(Vec3<S>(-theta));
}

// d/dt(Jr(theta)) dtheta/dt for theta moving at rate theta_dot: the
// velocity-product part of the body-frame angular acceleration of
// exp([theta]x). With a = (1 - cos t)/t^2, b = (t - sin t)/t^3 and
// t' = theta.theta_dot / t:
//   -a' t' theta x theta_dot + b' t' theta x (theta x theta_dot)
//   + b theta_dot x (theta x theta_dot),
// where a'(t)/t = (t sin t - 2 (1 - cos t))/t^4 and
// b'(t)/t = (t (1 - cos t) - 3 (t - sin t))/t^5, replaced near zero by
// their series -1/12 + t^2/180 - t^4/6720 and -1/60 + t^2/1260 - t^4/60480.
template <class S>
Vec3<S> so3_right_jacobian_rate(const Vec3<S>& theta, const Vec3<S>& theta_dot) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S t2 = theta.squaredNorm();
  const auto [b, da, db] = series_near_zero(  // b(t), a'(t)/t, b'(t)/t
      t2, S(1e-3),
      [&] {
        return std::array<S, 3>{S(1) / S(6) - t2 / S(120) + t2 * t2 / S(5040),
                                -S(1) / S(12) + t2 / S(180) - t2 * t2 / S(6720),
                                -S(1) / S(60) + t2 / S(1260) - t2 * t2 / S(60480)};
      },
      [&] {
        const S t = sqrt(t2), c = cos(t), s = sin(t);
        return std::array<S, 3>{(t - s) / (t2 * t), (t * s - S(2) * (S(1) - c)) / (t2 * t2),
                                (t * (S(1) - c) - S(3) * (t - s)) / (t2 * t2 * t)};
      });
  const S along = theta.dot(theta_dot);  // t t'
  const Vec3<S> cross = theta.cross(theta_dot);
  return -da * along * cross + db * along * theta.cross(cross) + b * theta_dot.cross(cross);
}

// The coefficient of [xi]x^2 in the inverse right Jacobian of SO(3) below,
// c = 1/t^2 - (1 + cos t)/(2 t sin t), from t^2 = |xi|^2.
template <class S>
S so3_right_jacobian_inverse_coefficient(const S& t2) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  return series_near_zero(
      t2, S(1e-6), [&] { return std::array<S, 1>{S(1) / S(12) + t2 / S(720)}; },
      [&] { return std::array<S, 1>{S(1) / t2 - (S(1) + cos(sqrt(t2))) / (S(2) * sqrt(t2) * sin(sqrt(t2)))}; })[0];
}

// Inverse right Jacobian of SO(3): I + [xi]x/2 + c [xi]x^2.
template <class S>
Mat3<S> so3_right_jacobian_inverse(const Vec3<S>& xi) {
  const Mat3<S> k = skew(xi);
  return Mat3<S>::Identity() + k / S(2) + so3_right_jacobian_inverse_coefficient(xi.squaredNorm()) * (k * k);
}

// Jr^-1(xi) w without the matrix: w + xi x w / 2 + c xi x (xi x w).
template <class S>
Vec3<S> so3_right_jacobian_inverse_times(const Vec3<S>& xi, const Vec3<S>& w) {
  const Vec3<S> k_w = xi.cross(w);
  return w + k_w / S(2) + so3_right_jacobian_inverse_coefficient(xi.squaredNorm()) * xi.cross(k_w);
}

// d/dxi of Jr^-1(xi) w (3 x 3). With Jr^-1 = I + K/2 + c(t) K^2, K = [xi]x,
// t = |xi|: -[w]x/2 + (c'(t)/t) (K^2 w) xi' + c ((xi.w) I + xi w' - 2 w xi'),
// c'(t)/t = -2/t^4 + 1/(4 t^2 sin^2(t/2)) + cot(t/2)/(2 t^3), near zero 1/360.
template <class S>
Mat3<S> so3_right_jacobian_inverse_derivative(const Vec3<S>& xi, const Vec3<S>& w) {
  using std::sin;
  using std::sqrt;
  using std::tan;
  const S t2 = xi.squaredNorm();
  const auto [c, dc_over_t] = series_near_zero(
      t2, S(1e-6), [&] { return std::array<S, 2>{S(1) / S(12) + t2 / S(720), S(1) / S(360)}; },
      [&] {
        const S t = sqrt(t2), half_cot = S(1) / tan(t / S(2)), sh = sin(t / S(2));
        return std::array<S, 2>{S(1) / t2 - half_cot / (S(2) * t),
                                (-S(2) / (t2 * t) + S(1) / (S(4) * t * sh * sh) + half_cot / (S(2) * t2)) / t};
      });
  const Mat3<S> k = skew(xi);
  const Vec3<S> kkw = k * (k * w);
  return -skew(w) / S(2) + dc_over_t * kkw * xi.transpose() +
         c * (xi.dot(w) * Mat3<S>::Identity() + xi * w.transpose() - S(2) * w * xi.transpose());
}

// SE(2): planar displacement of the body-frame twist (vx, vy, w) * dt,
// returned as (dx, dy) in the starting body frame.
template <class S>
Eigen::Matrix<S, 2, 1> se2_exp_translation(const S& vx, const S& vy, const S& phi) {
  using std::cos;
  using std::sin;
  const auto [s, c] = series_near_zero(  // sin(phi)/phi and (1 - cos(phi))/phi
      S(phi * phi), S(1e-8),
      [&] { return std::array<S, 2>{S(1) - phi * phi / S(6), phi / S(2) - phi * phi * phi / S(24)}; },
      [&] { return std::array<S, 2>{sin(phi) / phi, (S(1) - cos(phi)) / phi}; });
  return Eigen::Matrix<S, 2, 1>(s * vx - c * vy, c * vx + s * vy);
}

}  // namespace soadyn
