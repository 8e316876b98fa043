// Uniform Euler-Bernoulli cantilever as a modal flexible body.
//
// The beam lies along the body x axis from the root x = 0 (the body origin,
// clamped at the hinge) to the tip x = L. Lumped model: n_nodes equal
// segments of length h = L / n_nodes, one node at each segment centre
// x_j = (j + 1/2) h with the segment's mass mu h and its rotary inertia as
// a thin rod about its centre, diag(0, mu h^3 / 12, mu h^3 / 12); plus a
// massless node at the tip, the attachment "tip" (node index n_nodes).
//
// Modes: transverse bending in both planes, n_modes_per_plane in each, so
// n_m = 2 n_modes_per_plane, interleaved so the frequencies ascend:
//   mode 2i     bending in the x-y plane: translation (0, phi_i, 0),
//               rotation (0, 0, phi_i') (about z);
//   mode 2i + 1 bending in the x-z plane: translation (0, 0, phi_i),
//               rotation (0, -phi_i', 0) (about y; a slope dw/dx tilts x
//               towards +z, a negative rotation about y).
// phi_i is the clamped-free mode (i = 1, 2, ...)
//   phi_i(x) = cosh(b x) - cos(b x) - s_i (sinh(b x) - sin(b x)),
//   s_i = (cosh(b L) + cos(b L)) / (sinh(b L) + sin(b L)),  b = beta_i,
// with beta_i L the i-th root of 1 + cos(x) cosh(x) = 0; unscaled, so that
// the integral of phi_i^2 over the beam is L and |phi_i(L)| = 2.
// Modal stiffness K_ik = integral_0^L EI phi_i'' phi_k'' dx (per plane, no
// coupling between the planes) by composite Gauss-Legendre quadrature; the
// analytic modes make it diagonal only up to quadrature error, which is not
// assumed. Damping is zero; shear, torsion, axial stretch and foreshortening
// are not modelled.
#pragma once
#include "soadyn/flex/flexible_body.hpp"

namespace soadyn {

// beta_i L: the i-th root (i >= 1) of 1 + cos(x) cosh(x) = 0.
template <class S>
S clamped_free_root(int i);

// phi, phi' and phi'' of a clamped-free mode at one point.
template <class S>
struct BeamModeValues {
  S shape;
  S slope;
  S curvature;
};

// Mode i (i >= 1) of the clamped-free beam of length L.
template <class S>
class ClampedFreeMode {
 public:
  ClampedFreeMode(int i, const S& length);
  const S& beta() const { return beta_; }
  BeamModeValues<S> at(const S& x) const;

 private:
  S beta_, length_, sigma_;
  // (1 - s) e^{b x} = growing_ e^{b (x - L)} and (1 + s) e^{-b x} =
  // decaying_ e^{-b x}: the hyperbolic terms without cancellation.
  S growing_, decaying_;
};

// The cantilever described above. Throws std::invalid_argument for a
// non-positive or non-finite length, EI or mass per length, or counts < 1.
template <class S>
FlexibleBodyTpl<S> cantilever_beam(const S& length, const S& bending_stiffness, const S& mass_per_length,
                                   int n_modes_per_plane, int n_nodes = 60);

extern template double clamped_free_root<double>(int);
extern template float clamped_free_root<float>(int);
extern template class ClampedFreeMode<double>;
extern template class ClampedFreeMode<float>;
extern template FlexibleBodyTpl<double> cantilever_beam<double>(const double&, const double&, const double&, int, int);
extern template FlexibleBodyTpl<float> cantilever_beam<float>(const float&, const float&, const float&, int, int);

}  // namespace soadyn
