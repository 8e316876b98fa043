// The shape of a joint placement's rotation, recorded once per parameter
// change so that the sweeps' product parent * placement skips what it can.
//
// Most URDF placements are the identity or a quarter turn about coordinate
// axes (rpy of 0 and +-pi/2: six of the Panda's nine placements). A quarter-turn
// rotation maps every axis onto a coordinate axis, up to sign: column c of the
// rotation is sign[c] e_{source[c]}, so column c of R * placement is
// sign[c] times column source[c] of R, with no multiply-add.
//
// Those rotations reach the model with rounding in them: cos(pi/2) evaluated
// in double is 6.1e-17, not 0. A rotation is taken for the identity or a signed
// permutation when every entry is within one unit roundoff (machine epsilon)
// of it. The product with the exact permutation then differs from the full
// product by at most 2 eps |R| per entry, the size of the full product's own
// rounding error: no result changes by more than floating-point evaluation
// order already changes it.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "soadyn/spatial/types.hpp"

namespace soadyn {

template <class S>
struct PlacementAxes {
  enum class Kind : std::uint8_t { general, identity, signed_permutation };
  Kind kind = Kind::general;
  // signed_permutation (and identity): column c of the rotation is sign[c] e_{source[c]}.
  std::array<int, 3> source{0, 1, 2};
  std::array<S, 3> sign{S(1), S(1), S(1)};
};

// The shape of a rotation (above). Real scalars only (is_real_scalar_v): an
// automatic-differentiation scalar is always `general`, so that derivatives
// by the placement's parameters flow through the full product.
template <class S>
PlacementAxes<S> placement_axes_of(const Mat3<S>& rotation) {
  PlacementAxes<S> axes;
  if constexpr (is_real_scalar_v<S>) {
    using std::abs;
    const S tolerance = std::numeric_limits<S>::epsilon();
    int rows_taken = 0;
    bool identity = true;
    for (int c = 0; c < 3; ++c) {
      int source = -1;
      for (int r = 0; r < 3; ++r) {
        const S magnitude = abs(rotation(r, c));
        if (abs(magnitude - S(1)) <= tolerance) {
          if (source >= 0) return axes;
          source = r;
        } else if (!(magnitude <= tolerance)) {  // also false for NaN
          return axes;
        }
      }
      if (source < 0 || (rows_taken & (1 << source))) return axes;
      rows_taken |= 1 << source;
      axes.source[static_cast<std::size_t>(c)] = source;
      axes.sign[static_cast<std::size_t>(c)] = rotation(source, c) > S(0) ? S(1) : S(-1);
      identity = identity && source == c && rotation(source, c) > S(0);
    }
    axes.kind = identity ? PlacementAxes<S>::Kind::identity : PlacementAxes<S>::Kind::signed_permutation;
  }
  return axes;
}

}  // namespace soadyn
