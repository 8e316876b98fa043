// Cantilever beam builder (templated implementation of cantilever_beam.hpp).
#pragma once
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include "soadyn/flex/cantilever_beam.hpp"
#include "soadyn/flex/flexible_body.hxx"
#include "soadyn/flex/gauss_legendre.hpp"

namespace soadyn {

namespace flex_detail {

template <class S>
S pi() {
  return S(3.14159265358979323846);
}

// f(x) = cos x + sech x vanishes exactly where 1 + cos x cosh x = 0 and,
// unlike it, stays O(1) for large x. f'(x) = -sin x - tanh x sech x.
template <class S>
void characteristic_function(const S& x, S& f, S& df) {
  using std::cos;
  using std::exp;
  using std::sin;
  const S e2 = exp(S(-2) * x);
  const S sech = S(2) * exp(-x) / (S(1) + e2);
  const S tanh = (S(1) - e2) / (S(1) + e2);
  f = cos(x) + sech;
  df = -sin(x) - tanh * sech;
}

// Mode-shape column [rotation; translation] of a bending mode in the x-y
// plane (plane 0) or the x-z plane (plane 1) (cantilever_beam.hpp).
template <class S>
Vec6<S> beam_mode_shape_column(int plane, const BeamModeValues<S>& v) {
  Vec6<S> column = Vec6<S>::Zero();
  if (plane == 0) {
    column[2] = v.slope;  // rotation about z
    column[4] = v.shape;  // translation along y
  } else {
    column[1] = -v.slope;  // rotation about y
    column[5] = v.shape;   // translation along z
  }
  return column;
}

template <class S>
void require_positive(const S& value, const char* name) {
  if (!(value > S(0)) || !std::isfinite(static_cast<double>(value)))
    throw std::invalid_argument(std::string("cantilever_beam: ") + name + " must be positive and finite");
}

// A node at x with the given mass and rotary inertia; its mode shape
// columns follow the interleaved ordering of cantilever_beam.hpp.
template <class S>
FlexibleNode<S> beam_node(const S& x, const S& mass, const Mat3<S>& rotary_inertia,
                          const std::vector<ClampedFreeMode<S>>& modes) {
  FlexibleNode<S> node;
  node.position = Vec3<S>(x, S(0), S(0));
  node.mass = mass;
  node.rotary_inertia = rotary_inertia;
  const int per_plane = static_cast<int>(modes.size());
  node.mode_shape.resize(6, 2 * per_plane);
  for (int i = 0; i < per_plane; ++i) {
    const BeamModeValues<S> v = modes[static_cast<std::size_t>(i)].at(x);
    for (int plane = 0; plane < 2; ++plane) node.mode_shape.col(2 * i + plane) = beam_mode_shape_column(plane, v);
  }
  return node;
}

// K_ik = integral_0^L EI phi_i'' phi_k'' dx for both planes (block pattern
// of the interleaved modes; no coupling between the planes). An 8-point
// Gauss-Legendre rule on 4 segments per mode: each segment spans less than
// a quarter of the shortest half-wave, so the error is at rounding level.
template <class S>
MatX<S> beam_modal_stiffness(const S& length, const S& bending_stiffness,
                             const std::vector<ClampedFreeMode<S>>& modes) {
  const int per_plane = static_cast<int>(modes.size());
  MatX<S> plane_stiffness = MatX<S>::Zero(per_plane, per_plane);
  VecX<S> curvature(per_plane);
  for_each_quadrature_point(S(0), length, 4 * per_plane, gauss_legendre_rule<S>(8), [&](const S& x, const S& w) {
    for (int i = 0; i < per_plane; ++i) curvature[i] = modes[static_cast<std::size_t>(i)].at(x).curvature;
    plane_stiffness += (w * bending_stiffness) * curvature * curvature.transpose();
  });
  MatX<S> stiffness = MatX<S>::Zero(2 * per_plane, 2 * per_plane);
  for (int plane = 0; plane < 2; ++plane)
    for (int i = 0; i < per_plane; ++i)
      for (int k = 0; k < per_plane; ++k) stiffness(2 * i + plane, 2 * k + plane) = plane_stiffness(i, k);
  return stiffness;
}

}  // namespace flex_detail

template <class S>
S clamped_free_root(int i) {
  using std::abs;
  if (i < 1) throw std::invalid_argument("clamped_free_root: the mode number must be >= 1");
  // Root i lies in [(i - 1) pi, i pi], where f changes sign; safeguarded
  // Newton from (i - 1/2) pi, bisecting whenever a step leaves the bracket.
  S lo = S(i - 1) * flex_detail::pi<S>(), hi = S(i) * flex_detail::pi<S>();
  S f_lo, df;
  flex_detail::characteristic_function(lo, f_lo, df);
  S x = S(0.5) * (lo + hi);
  for (int iteration = 0; iteration < 200; ++iteration) {
    S f;
    flex_detail::characteristic_function(x, f, df);
    if ((f > S(0)) == (f_lo > S(0))) {
      lo = x;
      f_lo = f;
    } else {
      hi = x;
    }
    S next = x - f / df;
    if (!(next > lo && next < hi)) next = S(0.5) * (lo + hi);
    const bool converged = abs(next - x) <= S(4) * std::numeric_limits<S>::epsilon() * x;
    x = next;
    if (converged) break;
  }
  return x;
}

template <class S>
ClampedFreeMode<S>::ClampedFreeMode(int i, const S& length) : length_(length) {
  using std::cos;
  using std::exp;
  using std::sin;
  const S bl = clamped_free_root<S>(i);
  beta_ = bl / length;
  // With d = 2 e^{-bL} (sinh bL + sin bL) every term below is O(1):
  //   s       = 2 e^{-bL} (cosh bL + cos bL) / d,
  //   (1 - s) = 2 e^{-bL} (sin bL - cos bL - e^{-bL}) / d,
  //   (1 + s) = 2 e^{-bL} (e^{bL} + sin bL + cos bL) / d.
  const S e = exp(-bl);
  const S d = S(1) - e * e + S(2) * e * sin(bl);
  sigma_ = (S(1) + e * e + S(2) * e * cos(bl)) / d;
  growing_ = S(2) * (sin(bl) - cos(bl) - e) / d;
  decaying_ = S(2) * (S(1) + e * (sin(bl) + cos(bl))) / d;
}

template <class S>
BeamModeValues<S> ClampedFreeMode<S>::at(const S& x) const {
  using std::cos;
  using std::exp;
  using std::sin;
  const S z = beta_ * x;
  const S grow = S(0.5) * growing_ * exp(beta_ * (x - length_));
  const S decay = S(0.5) * decaying_ * exp(-z);
  const S cosh_part = grow + decay;  // cosh z - s sinh z
  const S sinh_part = grow - decay;  // sinh z - s cosh z
  const S c = cos(z), s = sin(z);
  BeamModeValues<S> v;
  v.shape = cosh_part - c + sigma_ * s;
  v.slope = beta_ * (sinh_part + s + sigma_ * c);
  v.curvature = beta_ * beta_ * (cosh_part + c - sigma_ * s);
  return v;
}

template <class S>
FlexibleBodyTpl<S> cantilever_beam(const S& length, const S& bending_stiffness, const S& mass_per_length,
                                   int n_modes_per_plane, int n_nodes) {
  using namespace flex_detail;
  require_positive(length, "length");
  require_positive(bending_stiffness, "EI (bending stiffness)");
  require_positive(mass_per_length, "mass per length");
  if (n_modes_per_plane < 1) throw std::invalid_argument("cantilever_beam: n_modes must be >= 1");
  if (n_nodes < 1) throw std::invalid_argument("cantilever_beam: n_nodes must be >= 1");

  std::vector<ClampedFreeMode<S>> modes;
  for (int i = 1; i <= n_modes_per_plane; ++i) modes.emplace_back(i, length);

  const S h = length / S(n_nodes);
  const S segment_mass = mass_per_length * h;
  // Thin rod about its centre: m h^2 / 12 about the transverse axes.
  const S transverse_inertia = segment_mass * h * h / S(12);
  const Mat3<S> segment_inertia = Vec3<S>(S(0), transverse_inertia, transverse_inertia).asDiagonal();

  FlexibleBodyDescription<S> beam;
  for (int j = 0; j < n_nodes; ++j)
    beam.nodes.push_back(beam_node((S(j) + S(0.5)) * h, segment_mass, segment_inertia, modes));
  beam.nodes.push_back(beam_node<S>(length, S(0), Mat3<S>::Zero(), modes));
  beam.attachments["tip"] = n_nodes;
  beam.stiffness = beam_modal_stiffness(length, bending_stiffness, modes);
  beam.damping = MatX<S>::Zero(2 * n_modes_per_plane, 2 * n_modes_per_plane);
  return FlexibleBodyTpl<S>(std::move(beam));
}

}  // namespace soadyn
