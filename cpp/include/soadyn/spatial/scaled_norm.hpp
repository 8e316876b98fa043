// The length of a 3-vector without overflow or underflow.
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

// |d|, and the unit vector d / |d| in `direction`, computed on d scaled by
// its largest entry so that neither overflows or underflows for any finite d
// (a distance loop far from the origin: |d|^2 would overflow past 1e154).
template <class S>
S scaled_norm(const Vec3<S>& d, Vec3<S>* direction) {
  const S largest = d.cwiseAbs().maxCoeff();
  if (!(largest > S(0))) {
    if (direction) *direction = d / largest;  // 0/0: NaN, as d.normalized() of a zero vector would be
    return largest;
  }
  const Vec3<S> scaled = d / largest;
  const S scaled_length = scaled.norm();
  if (direction) *direction = scaled / scaled_length;
  return largest * scaled_length;
}

}  // namespace soadyn
